"""The node corpus' comparison sees small errors in shading graphs at the setting CI runs
(corpus/node_sensitivity.py): each case's scene is exported by the add-on, rendered as exported
(it must pass) and with one error put into its graph (it must fail), at "ci" with the corpus'
seeds, and compared with the Cycles references."""

from __future__ import annotations

import copy

import pytest

from corpus import compare, node_sensitivity, refs, render_addon, render_usd, sensitivity
from corpus.settings import settings
from test_corpus import SEEDS

_CONTROLS: dict = {}


def _render(name: str, ir: dict):
    setting = settings("ci", refs.tags(name))
    outs = [render_usd.render_ir(ir, setting, seed=s) for s in SEEDS]
    return compare.compare(name, tuple(o["combined"] for o in outs), refs.load(name))


def _control(name: str):
    """The scene as exported: its IR, and its renders' comparison, which is the corpus test's
    (its renders through the engine, shared through render_addon.render_seeds). The cases
    render this IR with one error put in. The engine's own export of the scene can differ from
    it in the last bits, as any two exports do (Blender hands over normals that differ in their
    last bit from one evaluation to the next): at most 3e-4 in a pixel of nodes_wood, far
    below the noise."""
    if name not in _CONTROLS:
        ir, _ = render_addon.export_ir(name)
        outs = render_addon.render_seeds(name, settings("ci", refs.tags(name)), SEEDS)
        res = compare.compare(name, tuple(o["combined"] for o in outs), refs.load(name))
        _CONTROLS[name] = (ir, res)
    return _CONTROLS[name]


@pytest.mark.parametrize("case", list(node_sensitivity.CASES))
def test_comparison_sees_a_small_graph_error(addon, case):
    name, modify = node_sensitivity.CASES[case]
    ir, control = _control(name)
    print("\nas exported: " + control.message)
    assert control.passed, "the scene as exported must pass: " + control.message
    res = _render(name, modify(copy.deepcopy(ir)))
    line = sensitivity.row(case, name, control, res)
    sensitivity.TABLE.append(line)
    print(f"{case}: " + res.message + "\n" + line)
    assert not res.passed, f"{case} went unnoticed: " + res.message
