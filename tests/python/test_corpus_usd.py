"""The Cycles parity corpus through the USD path: every committed corpus stage
(tests/blender/corpus/usd/, written by Blender 5.0.1's own USD exporter) read by
``usd_delegate`` and rendered by ``photonmap.render`` at the light "ci" setting, compared with
the same Cycles references as the add-on (tests/blender/corpus/compare.py). Scenes without a
stage (the exporter drops mesh volumes) are listed in the references' manifest with the
reason. Known failures are ``xfail(strict=True)`` (corpus/expected.py). No bpy.

Two exporter bugs that the importer follows per UsdLux change a whole scene's light by a known
factor: the 6500 K colour temperature enabled on every light (a tint of about 1.043, 0.984,
1.035) and a sun of strength S written as S/4. Where every emitter of a stage has the same
factor, the reference is multiplied by it (corpus/usd_export.py, computed from the stage, not
from the importer's IR), so that the comparison still sees everything else."""

import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blender"))
from corpus import compare, expected, refs, render_usd, usd_export  # noqa: E402
from corpus.settings import settings  # noqa: E402

NAMES = refs.usd_names()
SEEDS = (1, 2, 3, 4)  # their scatter is our noise floor, photon-map noise included


@pytest.mark.parametrize("name", [pytest.param(n, marks=expected.marks("usd", n))
                                  for n in NAMES])
def test_stage_matches_cycles(name, record_property):
    ir, res_import = render_usd.load_ir(name)
    setting = settings("ci", refs.tags(name))
    outs = [render_usd.render_ir(ir, setting, seed=s) for s in SEEDS]
    ref, factor, why = usd_export.corrected(refs.usd_path(name), refs.load(name))
    res = compare.compare(name, tuple(o["combined"] for o in outs), ref)
    for key in ("pooled", "max_dev", "max_dev_sigma", "n_failed", "relmse", "relmse_tol"):
        record_property(key, getattr(res, key))
    warnings = [f"{p}: {m}" for p, m in res_import.diagnostics.warnings]
    secs = sum(o["seconds"] for o in outs)
    note = f"\n  reference times ({', '.join(f'{x:.4f}' for x in factor)}): {why}"
    print("\n" + res.message + note + f"\n  {secs:.1f}s; import warnings: {warnings}")
    assert res.passed, res.message + note + f"\n  import warnings: {warnings}"


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
