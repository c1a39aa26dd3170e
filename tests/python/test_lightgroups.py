"""Light groups through USD and the command line: the importer's attribute
(``primvars:photonmap:lightgroup``), the EXR's group and term layers summing to the beauty,
and bad names reported with the prim path."""

from __future__ import annotations

import numpy as np
import pytest
from pxr import Gf, Sdf, UsdGeom, UsdLux

import photonmap
import usd_delegate
from conftest import add_camera, import_stage, quad
from photonmap import cli


def _group(prim, name):
    UsdGeom.PrimvarsAPI(prim).CreatePrimvar(
        "photonmap:lightgroup", Sdf.ValueTypeNames.String).Set(name)


def _two_light_stage(stage_factory):
    stage, path = stage_factory()
    add_camera(stage, z=4.0)
    quad(stage, "/Floor", size=2.0)
    key = UsdLux.SphereLight.Define(stage, "/Lights/Key")
    key.CreateIntensityAttr(30.0)
    key.CreateRadiusAttr(0.1)
    UsdGeom.XformCommonAPI(key).SetTranslate((0.8, 0.0, 1.0))
    _group(key.GetPrim(), "key")
    fill = UsdLux.SphereLight.Define(stage, "/Lights/Fill")
    fill.CreateIntensityAttr(10.0)
    fill.CreateRadiusAttr(0.1)
    fill.CreateColorAttr(Gf.Vec3f(1.0, 0.6, 0.3))
    UsdGeom.XformCommonAPI(fill).SetTranslate((-0.8, 0.0, 1.0))
    _group(fill.GetPrim(), "fill")
    # Set on the parent scope: primvars inherit down the namespace.
    UsdGeom.Xform.Define(stage, "/Lights/Grouped")
    rim = UsdLux.SphereLight.Define(stage, "/Lights/Grouped/Rim")
    rim.CreateIntensityAttr(5.0)
    rim.CreateRadiusAttr(0.1)
    UsdGeom.XformCommonAPI(rim).SetTranslate((0.0, 0.8, 1.5))
    _group(stage.GetPrimAtPath("/Lights/Grouped"), "fill")
    spare = UsdLux.SphereLight.Define(stage, "/Lights/Spare")  # in no group: `default`
    spare.CreateIntensityAttr(5.0)
    spare.CreateRadiusAttr(0.1)
    UsdGeom.XformCommonAPI(spare).SetTranslate((0.0, -0.8, 1.5))
    return stage, path


def test_usd_lightgroup_primvar_names_the_groups(stage_factory):
    stage, path = _two_light_stage(stage_factory)
    res = import_stage(stage, path)
    names = [light["name"] for light in res.ir["lights"]]
    groups = {g["name"]: [names[i] for i in g.get("lights", [])] for g in res.ir["lightgroups"]}
    assert groups == {"key": ["/Lights/Key"],
                      "fill": ["/Lights/Fill", "/Lights/Grouped/Rim"]}


def test_group_and_term_layers_are_written_and_sum(stage_factory, tmp_path):
    import OpenImageIO as oiio

    stage, path = _two_light_stage(stage_factory)
    stage.GetRootLayer().Save()
    exr = tmp_path / "groups.exr"
    code = cli.main(["render", path, "-o", str(exr), "--quality", "draft", "--spp", "8",
                     "--width", "48", "--quiet"])
    assert code == 0
    inp = oiio.ImageInput.open(str(exr))
    spec = inp.spec()
    px = inp.read_image(oiio.FLOAT)
    inp.close()
    ch = {n: i for i, n in enumerate(spec.channelnames)}
    groups = ["key", "fill", "default"]
    for c in "RGB":
        beauty = px[..., ch[c]]
        terms = np.zeros_like(beauty)
        for t in photonmap.TERMS:
            terms += px[..., ch[f"{t}.{c}"]]
        assert np.array_equal(terms, beauty)
        total = sum(px[..., ch[f"lightgroup.{g}.{c}"]] for g in groups)
        np.testing.assert_allclose(total, beauty, rtol=1e-5, atol=1e-7)
    for g in groups:
        assert px[..., ch[f"lightgroup.{g}.R"]].mean() > 0, g
    # The warm fill light shows in its group: red over blue; the white key light does not.
    fill = [px[..., ch[f"lightgroup.fill.{c}"]].mean() for c in "RB"]
    key = [px[..., ch[f"lightgroup.key.{c}"]].mean() for c in "RB"]
    assert fill[0] > 1.5 * fill[1] and abs(key[0] / key[1] - 1) < 0.05, (fill, key)
    # The core's list of the AOVs names the same layers.
    listed = [a["name"] for a in photonmap.aov_specs(["key", "fill"])]
    assert listed == ["error"] + [f"lightgroup.{g}" for g in groups]


def test_a_bad_group_name_names_the_prim(stage_factory):
    stage, path = _two_light_stage(stage_factory)
    _group(stage.GetPrimAtPath("/Lights/Key"), "key light")
    with pytest.raises(usd_delegate.UsdImportError, match=r"/Lights/Key.*key light"):
        import_stage(stage, path)


def test_a_bad_group_in_the_ir_names_its_pointer():
    ir = {
        "camera": {"fov": 0.5}, "film": {"width": 8, "height": 8},
        "materials": [{"type": "diffuse", "name": "grey"}],
        "lights": [{"type": "point", "name": "bulb", "position": [0, 0, 1], "power": 10}],
        "lightgroups": [{"name": "a", "lights": [0]}, {"name": "b", "lights": [0]}],
    }
    with pytest.raises(photonmap.SceneError, match=r"/lightgroups/1/lights/0.*`a`"):
        photonmap.Scene.from_dict(ir)
