"""The Cycles parity corpus through the Blender add-on (tests/blender/corpus/).

Every corpus scene is built the way users build it, rendered by PhotonMap through
``bpy.ops.render.render()`` at the light "ci" setting (corpus/settings.py) and compared with
its two Cycles references, per 8x8 block and per pixel (corpus/compare.py). Scenes that fail
for a known reason are ``xfail(strict=True)`` (corpus/expected.py).

Each scene is rendered with two seeds: their spread is our noise floor, photon-map noise
included.

The sensitivity tests show that the comparison sees small errors: the add-on's IR of a scene
is rendered as exported (it must pass) and with one error put in (it must fail, at the same
tolerance): a light 2% brighter, an area light made two-sided and the Principled BSDF read as
Lambert at the "sensitivity" setting (less noise than "ci"), a spot turned by 5 deg at "ci";
on the jade scene, a light 2% brighter, the subsurface radius doubled and the subsurface part
dropped (the diffuse base alone), at "sensitivity".
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from corpus import compare, expected, refs, render_addon
from corpus.settings import settings

NAMES = refs.names()
#: Two seeds of ours: their spread is our noise floor, photon-map noise included (the error
#: AOV holds the camera samples' noise only).
SEEDS = (1, 2)


@pytest.mark.parametrize("name", [pytest.param(n, marks=expected.marks("addon", n))
                                  for n in NAMES])
def test_scene_matches_cycles(addon, name, record_property):
    from corpus import scenes

    setting = settings("ci", scenes.SCENES[name].tags)
    outs = [render_addon.render_scene(name, setting, seed=s) for s in SEEDS]
    assert not outs[0]["errors"], outs[0]["errors"]
    res = compare.compare(name, tuple(o["combined"] for o in outs), refs.load(name))
    for key in ("pooled", "max_dev", "max_dev_sigma", "n_failed", "relmse", "relmse_tol"):
        record_property(key, getattr(res, key))
    secs = sum(o["seconds"] for o in outs)
    print("\n" + res.message + f"\n  {secs:.1f}s; warnings: {outs[0]['warnings']}")
    assert res.passed, res.message + f"\n  export warnings: {outs[0]['warnings']}"


# -- sensitivity ---------------------------------------------------------------------------

#: The sensitivity tests' setting: low enough noise to see a 2% error.
SENSITIVITY = settings("sensitivity")


def render_ir(ir: dict, setting: dict) -> tuple:
    import photonmap

    scene = photonmap.Scene.from_dict(ir)
    return tuple(photonmap.render(scene, seed=s, **setting)["combined"] for s in SEEDS)


def brighter(ir):
    for light in ir["lights"]:
        key = "irradiance" if light["type"] == "distant" else "power"
        light[key] *= 1.02
    return ir


def subsurface_radius_doubled(ir):
    for m in ir["materials"]:
        if m.get("subsurface"):
            m["subsurface"]["radius"] = [2.0 * r for r in m["subsurface"]["radius"]]
    return ir


def subsurface_dropped(ir):
    for m in ir["materials"]:
        m.pop("subsurface", None)
    return ir


def spot_turned(ir):
    a = math.radians(5.0)
    for light in ir["lights"]:
        if light["type"] == "spot":
            x, y, z = light["direction"]
            light["direction"] = [x, y * math.cos(a) - z * math.sin(a),
                                  y * math.sin(a) + z * math.cos(a)]
    return ir


def two_sided(ir):
    for light in ir["lights"]:
        if light["type"] in ("rect", "disk"):
            light["two_sided"] = True
    return ir


def lambert(ir):
    for i, m in enumerate(ir["materials"]):
        if m["type"] == "principled":
            ir["materials"][i] = {"type": "diffuse", "name": m.get("name", ""),
                                  "color": m["base_color"]}
    return ir


#: case -> (scene, the error put in, setting). A 2% scale error needs the "sensitivity"
#: setting's noise; the turned spot moves its pool by ~15 cm and shows at "ci".
CASES = {
    "light_2pct_brighter": ("room_empty", brighter, SENSITIVITY),
    "spot_turned_5deg": ("spot_blend", spot_turned, settings("ci")),
    "area_two_sided": ("room_empty", two_sided, SENSITIVITY),
    "principled_as_lambert": ("mat_default", lambert, SENSITIVITY),
    "subsurface_light_2pct_brighter": ("sss_jade", brighter, SENSITIVITY),
    "subsurface_radius_doubled": ("sss_jade", subsurface_radius_doubled, SENSITIVITY),
    "subsurface_as_diffuse": ("sss_jade", subsurface_dropped, SENSITIVITY),
}


@pytest.fixture(scope="module")
def controls(addon):
    """Each sensitivity scene's IR and its comparison as exported (rendered once)."""
    done = {}

    def get(name, setting):
        key = (name, repr(setting))
        if key not in done:
            ir, _ = render_addon.export_ir(name)
            done[key] = (ir, compare.compare(name, render_ir(ir, setting), refs.load(name)))
        return done[key]

    return get


@pytest.mark.parametrize("case", sorted(CASES))
def test_comparison_sees_a_small_error(controls, case):
    name, modify, setting = CASES[case]
    ir, control = controls(name, setting)
    print("\nas exported: " + control.message)
    assert control.passed, "the unmodified scene must pass: " + control.message
    res = compare.compare(name, render_ir(modify(copy.deepcopy(ir)), setting), refs.load(name))
    print(f"{case}: " + res.message)
    assert not res.passed, f"{case} went unnoticed: " + res.message


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
