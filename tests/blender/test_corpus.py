"""The Cycles parity corpus through the Blender add-on (tests/blender/corpus/).

Every corpus scene is built the way users build it, rendered by PhotonMap through
``bpy.ops.render.render()`` at the light "ci" setting (corpus/settings.py) and compared with
its two Cycles references, per 8x8 block and per pixel (corpus/compare.py). Scenes that fail
for a known reason are ``xfail(strict=True)`` (corpus/expected.py).

Each scene is rendered with four seeds: their scatter is our noise floor, photon-map noise
included (compare.MIN_SEEDS).

That this comparison sees small errors at "ci", of both signs, is shown on the same scenes'
USD stages by tests/python/test_corpus_sensitivity.py (corpus/sensitivity.py).
"""

from __future__ import annotations

import numpy as np
import pytest

from corpus import compare, expected, refs, render_addon
from corpus.settings import settings

NAMES = refs.names()
#: Four seeds of ours: their scatter is our noise floor, photon-map noise included (the error
#: AOV holds the camera samples' noise only).
SEEDS = (1, 2, 3, 4)


@pytest.mark.parametrize("name", [pytest.param(n, marks=expected.marks("addon", n))
                                  for n in NAMES])
def test_scene_matches_cycles(addon, name, record_property):
    from corpus import scenes

    setting = settings("ci", scenes.SCENES[name].tags)
    outs = render_addon.render_seeds(name, setting, SEEDS)
    assert not outs[0]["errors"], outs[0]["errors"]
    res = compare.compare(name, tuple(o["combined"] for o in outs), refs.load(name))
    for key in ("pooled", "max_dev", "max_dev_sigma", "n_failed", "relmse", "relmse_tol"):
        record_property(key, getattr(res, key))
    secs = sum(o["seconds"] for o in outs)
    print("\n" + res.message + f"\n  {secs:.1f}s; warnings: {outs[0]['warnings']}")
    assert res.passed, res.message + f"\n  export warnings: {outs[0]['warnings']}"


def test_corpus_is_complete():
    """Every scene of scenes.py has references, and the references are the corpus' size."""
    from corpus import scenes

    assert set(scenes.SCENES) == set(NAMES)
    assert len(NAMES) >= 22
    w, h = refs.resolution()
    for name in NAMES:
        a, b = refs.load(name)
        assert a.shape == b.shape == (h, w, 3)
        assert np.isfinite(a).all() and np.isfinite(b).all()


def test_export_does_not_depend_on_blenders_mesh_order(addon):
    """Blender's evaluated mesh may hand the same triangles over in another order from one
    build to the next (and its normals may differ in the last bit); the export puts them in an
    order of their own data, so a seed's render does not change with it."""
    irs = [render_addon.export_ir("emission_principled")[0] for _ in range(3)]
    for ir in irs[1:]:
        assert [m["name"] for m in ir["meshes"]] == [m["name"] for m in irs[0]["meshes"]]
        for a, b in zip(irs[0]["meshes"], ir["meshes"]):
            for key in ("positions", "indices", "uvs"):
                assert np.array_equal(np.asarray(a[key]), np.asarray(b[key])), (a["name"], key)
            assert np.allclose(a["normals"], b["normals"], atol=1e-6), a["name"]


def test_canonical_order_keeps_the_triangles():
    """Unit check of the ordering on a shuffled quad pair: same triangles (as corner data, with
    winding), shared corners merged, and the same result for any input order."""
    import importlib.util
    import os

    spec = importlib.util.spec_from_file_location(
        "pm_mesh", os.path.join(os.path.dirname(__file__), "..", "..", "blender_addon", "export",
                                "mesh.py"))
    mesh = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mesh)
    rng = np.random.default_rng(3)
    pos = rng.random((6, 3)).astype(np.float32)
    arrays = {"positions": pos, "normals": np.tile([[0, 0, 1]], (6, 1)).astype(np.float32),
              "indices": np.array([[0, 1, 2], [2, 3, 0], [3, 4, 5]], np.int32),
              "slots": np.array([0, 1, 0], np.int32)}

    def corners(a):  # each triangle as its slot and cyclic corner sequence, rotation-free
        out = []
        for s, t in zip(a["slots"], a["positions"][a["indices"]]):
            rows = [tuple(r) for r in t]
            k = rows.index(min(rows))
            out.append((int(s), tuple(rows[k:] + rows[:k])))
        return sorted(out)

    base = mesh.canonical(arrays)
    assert corners(base) == corners(arrays)
    for _ in range(5):
        perm = rng.permutation(3)
        rot = rng.integers(0, 3, 3)
        idx = np.stack([np.roll(arrays["indices"][i], r) for i, r in zip(perm, rot)])
        vperm = rng.permutation(6)  # the corners in another order too
        inv = np.argsort(vperm)
        other = mesh.canonical(dict(arrays, positions=pos[vperm], normals=arrays["normals"][vperm],
                                    indices=inv[idx].astype(np.int32),
                                    slots=arrays["slots"][perm]))
        for key in ("positions", "normals", "indices", "slots"):
            assert np.array_equal(base[key], other[key]), key
