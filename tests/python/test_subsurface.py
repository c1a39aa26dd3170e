"""Subsurface scattering through the Python API and the USD importer: the `subsurface` term
in the result and the pass names, OpenPBR's and standard_surface's subsurface inputs read
into the IR, and the warnings on bad input."""
import numpy as np
import pytest
from conftest import add_camera, import_stage, quad
from pxr import Sdf, UsdShade

import photonmap


def _sphere(n_rings=16, n_seg=32, r=1.0):
    """A closed UV sphere with outward winding."""
    pts = [(0.0, 0.0, r)]
    for i in range(1, n_rings):
        th = np.pi * i / n_rings
        for j in range(n_seg):
            ph = 2 * np.pi * j / n_seg
            pts.append((r * np.sin(th) * np.cos(ph), r * np.sin(th) * np.sin(ph), r * np.cos(th)))
    pts.append((0.0, 0.0, -r))
    tris = []
    for j in range(n_seg):
        tris.append((0, 1 + j, 1 + (j + 1) % n_seg))
    for i in range(n_rings - 2):
        a, b = 1 + i * n_seg, 1 + (i + 1) * n_seg
        for j in range(n_seg):
            j1 = (j + 1) % n_seg
            tris.append((a + j, b + j, b + j1))
            tris.append((a + j, b + j1, a + j1))
    last = len(pts) - 1
    a = 1 + (n_rings - 2) * n_seg
    for j in range(n_seg):
        tris.append((a + j, last, a + (j + 1) % n_seg))
    return np.array(pts, dtype=np.float32), np.array(tris, dtype=np.uint32)


def _scene(subsurface):
    p, t = _sphere()
    mat = {"type": "principled", "name": "wax", "base_color": [0.9, 0.6, 0.4], "ior": 1.4}
    if subsurface is not None:
        mat["subsurface"] = subsurface
    return photonmap.Scene.from_dict({
        "camera": {"fov": 0.6, "transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4],
                                             [0, 0, 0, 1]]},
        "film": {"width": 24, "height": 24},
        "materials": [mat],
        "meshes": [{"name": "ball", "positions": p, "indices": t, "material": 0}],
        "lights": [{"type": "point", "position": [2, 2, 3], "power": 400}],
    })


def test_the_subsurface_term_reaches_python_and_sums_to_the_beauty():
    assert "subsurface" in photonmap.TERMS and "Subsurface" in photonmap.PASS_NAMES
    out = photonmap.render(_scene({"radius": [0.3, 0.15, 0.08]}), spp=2, seed=1)
    sub = out["subsurface"]
    assert sub.shape == (24, 24, 3) and sub.dtype == np.float32
    assert sub.max() > 0
    total = sum(out[t] for t in photonmap.TERMS)
    assert np.array_equal(total, out["combined"]) or np.allclose(total, out["combined"], rtol=1e-6,
                                                                  atol=1e-7)
    assert out["stats"]["work"]["subsurface_walks"] > 0


def test_without_subsurface_nothing_is_built_and_radius_zero_is_warned():
    out = photonmap.render(_scene(None), spp=1, seed=1)
    assert out["stats"]["work"]["subsurface_walks"] == 0
    assert any(t["term"] == "subsurface" for t in out["stats"]["skipped"])
    assert not out["subsurface"].any()
    out = photonmap.render(_scene({"radius": [0, 0, 0]}), spp=1, seed=1)
    assert any("'wax'" in w and "radius 0" in w for w in out["stats"]["warnings"])


def _openpbr(stage, inputs):
    m = quad(stage)
    mat = UsdShade.Material.Define(stage, "/Mat/Wax")
    sh = UsdShade.Shader.Define(stage, "/Mat/Wax/OpenPBR")
    sh.CreateIdAttr("ND_open_pbr_surface_surfaceshader")
    for name, (kind, value) in inputs.items():
        sh.CreateInput(name, kind).Set(value)
    sh.CreateOutput("surface", Sdf.ValueTypeNames.Token)
    mat.CreateSurfaceOutput("mtlx").ConnectToSource(sh.ConnectableAPI(), "surface")
    UsdShade.MaterialBindingAPI.Apply(m.GetPrim()).Bind(mat)
    add_camera(stage)


def test_openpbr_subsurface_inputs(stage_factory):
    stage, path = stage_factory()
    T = Sdf.ValueTypeNames
    _openpbr(stage, {"subsurface_weight": (T.Float, 0.7),
                     "subsurface_color": (T.Color3f, (0.9, 0.5, 0.3)),
                     "subsurface_radius": (T.Float, 0.1),
                     "subsurface_radius_scale": (T.Color3f, (1.0, 0.5, 0.25)),
                     "subsurface_scatter_anisotropy": (T.Float, 0.3),
                     "specular_ior": (T.Float, 1.45)})
    r = import_stage(stage, path)
    sub = r.ir["materials"][0]["subsurface"]
    assert sub["weight"] == pytest.approx(0.7)
    assert np.allclose(sub["radius"], [0.1, 0.05, 0.025])
    assert np.allclose(sub["color"], [0.9, 0.5, 0.3])
    assert sub["anisotropy"] == pytest.approx(0.3) and sub["ior"] == pytest.approx(1.45)
    assert not [m for m in r.diagnostics.messages() if "subsurface" in m]


def test_openpbr_subsurface_radius_zero_is_warned_and_none_without_weight(stage_factory):
    stage, path = stage_factory()
    T = Sdf.ValueTypeNames
    _openpbr(stage, {"subsurface_weight": (T.Float, 1.0), "subsurface_radius": (T.Float, 0.0)})
    r = import_stage(stage, path)
    assert any("/Mat/Wax/OpenPBR" in m and "radius 0" in m for m in r.diagnostics.messages())
    stage, path = stage_factory("b.usda")
    _openpbr(stage, {"subsurface_weight": (T.Float, 0.0)})
    assert "subsurface" not in import_stage(stage, path).ir["materials"][0]
