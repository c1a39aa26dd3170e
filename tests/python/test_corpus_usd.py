"""The Cycles parity corpus through the USD path: every committed corpus stage
(tests/blender/corpus/usd/, written by Blender 5.0.1's own USD exporter) read by
``usd_delegate`` and rendered by ``photonmap.render`` at the light "ci" setting, compared with
the same Cycles references as the add-on (tests/blender/corpus/compare.py). Scenes without a
stage (the exporter drops mesh volumes) are listed in the references' manifest with the
reason. Known failures are ``xfail(strict=True)`` (corpus/expected.py), rendered with one seed and
judged by the error AOV, and the stage lines their reasons quote are checked to be in the
stage. No bpy.

Two exporter bugs that the importer follows per UsdLux change a whole scene's light by a known
factor: the 6500 K colour temperature enabled on every light (a tint of about 1.043, 0.984,
1.035) and a sun of strength S written as S/4. Where every emitter of a stage has the same
factor, the reference is multiplied by it (corpus/usd_export.py, computed from the stage, not
from the importer's IR), so that the comparison still sees everything else."""

import os
import re
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blender"))
from corpus import compare, expected, refs, render_usd, usd_export  # noqa: E402
from corpus.settings import settings  # noqa: E402

NAMES = refs.usd_names()
SEEDS = (1, 2, 3, 4)  # their scatter is our noise floor, photon-map noise included
#: A scene known to fail for the exporter (expected.USD) is rendered once and judged with the
#: render's error AOV: it fails by tens to hundreds of sigma, and the stage line that makes it
#: fail is checked on its own (test_expected_failures_quote_their_stage).
XFAIL_SEEDS = (1,)


@pytest.mark.parametrize("name", [pytest.param(n, marks=expected.marks("usd", n))
                                  for n in NAMES])
def test_stage_matches_cycles(name, record_property):
    setting = settings("ci", refs.tags(name))
    known = expected.reason("usd", name) is not None
    outs, warnings = render_usd.render_seeds(name, setting, XFAIL_SEEDS if known else SEEDS)
    ref, factor, why = usd_export.corrected(refs.usd_path(name), refs.load(name))
    if known:
        res = compare.compare(name, outs[0]["combined"], ref, outs[0]["error"])
    else:
        res = compare.compare(name, tuple(o["combined"] for o in outs), ref)
    for key in ("pooled", "max_dev", "max_dev_sigma", "n_failed", "relmse", "relmse_tol"):
        record_property(key, getattr(res, key))
    secs = sum(o["seconds"] for o in outs)
    note = f"\n  reference times ({', '.join(f'{x:.4f}' for x in factor)}): {why}"
    print("\n" + res.message + note + f"\n  {secs:.1f}s; import warnings: {warnings}")
    assert res.passed, res.message + note + f"\n  import warnings: {warnings}"


#: A stage line quoted in an expected failure's reason: 'text' between quotes that are not
#: apostrophes (no word character outside them).
_QUOTED = re.compile(r"(?<!\w)'([^'\s][^']*?)'(?!\w)")


@pytest.mark.parametrize("name", sorted(expected.USD))
def test_expected_failures_quote_their_stage(name):
    """Each expected failure of the USD path names the stage's lines that cause it, and the
    committed stage still has them: a stage written again by a fixed exporter drops the entry's
    ground, and this fails until the entry goes."""
    why = expected.USD[name]
    quoted = _QUOTED.findall(why)
    assert quoted, f"{name}: the reason quotes no line of the stage: {why}"
    with open(refs.usd_path(name)) as f:
        text = f.read()
    missing = [q for q in quoted if q not in text]
    assert not missing, f"{name}: {refs.usd_path(name)} no longer has {missing}"


def test_every_scene_has_a_stage_or_a_reason():
    man = refs.manifest()["scenes"]
    assert len(NAMES) >= 20
    for name, rec in man.items():
        if name in NAMES:
            assert rec["usd"] == f"usd/{name}.usda"
        else:
            assert rec.get("no_usd"), f"{name}: no stage and no reason"


def test_the_known_factors():
    """The exporter's factors as the stages carry them: the 6500 K tint on every light, and
    the sun's S/4 times that tint; none where the stage has no lights."""
    tint = (1.0433, 0.9836, 1.0346)
    f, _ = usd_export.factor(refs.usd_path("room_empty"))
    assert f is not None and max(abs(a - b) for a, b in zip(f, tint)) < 1e-3, f
    f, why = usd_export.factor(refs.usd_path("sun_angle"))
    assert f is not None and max(abs(a - b / 4) for a, b in zip(f, tint)) < 1e-3, (f, why)
    f, _ = usd_export.factor(refs.usd_path("emission_principled"))
    assert f is not None and all(x == 1.0 for x in f)
