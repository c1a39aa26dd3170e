"""The corpus comparison sees small errors at the setting CI runs (tests/blender/corpus/
sensitivity.py): each case's scene is read from its committed USD stage, rendered as read (it
must pass) and with one error put in (it must fail), at "ci" with the corpus' seeds, and
compared with the Cycles references by tests/blender/corpus/compare.py. Every case's margin is
printed, and the table of them at the end of the run."""

import copy
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blender"))
from corpus import compare, refs, render_usd, sensitivity, usd_export  # noqa: E402
from corpus.settings import settings  # noqa: E402

from test_corpus_usd import SEEDS  # noqa: E402

_CONTROLS: dict = {}


def _compare(name: str, outs):
    ref, _, _ = usd_export.corrected(refs.usd_path(name), refs.load(name))
    return compare.compare(name, tuple(o["combined"] for o in outs), ref)


def _render(name: str, ir: dict):
    setting = settings("ci", refs.tags(name))
    return _compare(name, [render_usd.render_ir(ir, setting, seed=s) for s in SEEDS])


def _control(name: str):
    """The scene as read: its IR, and its renders' comparison (the corpus test's renders,
    shared through render_usd.render_seeds)."""
    if name not in _CONTROLS:
        ir, _ = render_usd.load_ir(name)
        outs, _ = render_usd.render_seeds(name, settings("ci", refs.tags(name)), SEEDS)
        _CONTROLS[name] = (ir, _compare(name, outs))
    return _CONTROLS[name]


@pytest.mark.parametrize("case", list(sensitivity.CASES))
def test_comparison_sees_a_small_error(case):
    name, modify = sensitivity.CASES[case]
    ir, control = _control(name)
    print("\nas read: " + control.message)
    assert control.passed, "the scene as read must pass: " + control.message
    res = _render(name, modify(copy.deepcopy(ir)))
    line = sensitivity.row(case, name, control, res)
    sensitivity.TABLE.append(line)
    print(f"{case}: " + res.message + "\n" + line)
    assert not res.passed, f"{case} went unnoticed: " + res.message
