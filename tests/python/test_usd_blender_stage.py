"""Stages written by Blender, read the way Blender renders them (usd_delegate/lights.py):
lights hidden from the camera unless the stage says otherwise, and the sun's angle that
Blender 5.0's exporter writes halved doubled back. Small stages built in memory, with the
metadata Blender 5.0.1 writes (copied from tests/blender/corpus/usd/*.usda: the layer's
`doc = "Blender v5.0.1"`, `customData` on the root prim, `userProperties:blender:*` on each
prim); the same stages without that metadata are read per UsdLux."""

import math

import pytest
from pxr import Sdf, Usd, UsdGeom, UsdLux

import photonmap
import usd_delegate
from usd_delegate.stage import import_stage

BLENDER_DOC = "Blender v5.0.1"


def stage_with(light_type="SphereLight", blender=True, doc=BLENDER_DOC, layer=None):
    """/root/Light/Light of ``light_type`` the way Blender 5.0.1 writes it (with
    ``blender``: its layer metadata and user properties), and a 2x2 floor."""
    stage = Usd.Stage.Open(layer) if layer is not None else Usd.Stage.CreateInMemory()
    root_layer = stage.GetRootLayer()
    if blender and doc:
        root_layer.documentation = doc
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    root = UsdGeom.Xform.Define(stage, "/root").GetPrim()
    stage.SetDefaultPrim(root)
    if blender:
        root.SetCustomData({"Blender": {"generated": True}})
    xf = UsdGeom.Xform.Define(stage, "/root/Light")
    xf.AddTranslateOp().Set((0.0, 0.6, 1.35))
    prim = stage.DefinePrim("/root/Light/Light", light_type)
    a = prim.CreateAttribute
    a("inputs:enableColorTemperature", Sdf.ValueTypeNames.Bool).Set(True)
    a("inputs:normalize", Sdf.ValueTypeNames.Bool).Set(True)
    a("inputs:intensity", Sdf.ValueTypeNames.Float).Set(9.549296)
    if light_type == "RectLight":
        a("inputs:width", Sdf.ValueTypeNames.Float).Set(0.5)
        a("inputs:height", Sdf.ValueTypeNames.Float).Set(0.5)
    elif light_type in ("DiskLight", "SphereLight"):
        a("inputs:radius", Sdf.ValueTypeNames.Float).Set(0.1)
    elif light_type == "DistantLight":
        a("inputs:angle", Sdf.ValueTypeNames.Float).Set(5.0)
        a("inputs:intensity", Sdf.ValueTypeNames.Float).Set(0.75)
    if blender:
        a("userProperties:blender:data_name", Sdf.ValueTypeNames.String, custom=True).Set("Light")
    floor = UsdGeom.Mesh.Define(stage, "/root/Floor")
    floor.CreatePointsAttr([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)])
    floor.CreateFaceVertexCountsAttr([4])
    floor.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    return stage


def spot(stage):
    """The stage's sphere light made a Blender spot (ShapingAPI, cone 22.5 deg)."""
    prim = stage.GetPrimAtPath("/root/Light/Light")
    shaping = UsdLux.ShapingAPI.Apply(prim)
    shaping.CreateShapingConeAngleAttr(22.5)
    shaping.CreateShapingConeSoftnessAttr(0.15)
    return stage


def read(stage):
    r = import_stage(stage)
    (light,) = r.ir["lights"]
    # The IR the importer builds must be one the core accepts.
    photonmap.Scene.from_dict(r.ir)
    return light, r


def notes_of(r, path="/root/Light/Light"):
    return [m for p, m in r.diagnostics.notes if p == path]


HIDDEN = "hidden from the camera"


# -- lights hidden from the camera --------------------------------------------------------


@pytest.mark.parametrize("light_type,ir_type", [("SphereLight", "point"), ("RectLight", "rect"),
                                                ("DiskLight", "disk"), ("spot", "spot")])
def test_blender_lights_are_hidden_from_the_camera_with_a_note(light_type, ir_type):
    stage = spot(stage_with("SphereLight")) if light_type == "spot" else stage_with(light_type)
    light, r = read(stage)
    assert light["type"] == ir_type
    assert light["camera_visible"] is False
    notes = [m for m in notes_of(r) if HIDDEN in m]
    assert len(notes) == 1, r.diagnostics.notes
    assert "Blender v5.0.1" in notes[0] and "as Blender renders" in notes[0]
    assert not any(HIDDEN in m for _, m in r.diagnostics.warnings)  # a note, not a warning


@pytest.mark.parametrize("light_type", ["SphereLight", "RectLight", "DiskLight"])
def test_the_same_stage_without_blenders_metadata_shows_its_lights(light_type):
    light, r = read(stage_with(light_type, blender=False))
    assert light["camera_visible"] is True
    assert not any(HIDDEN in m for m in r.diagnostics.messages())


def test_treat_as_point_light_of_blender_is_hidden_too():
    stage = stage_with("SphereLight")
    prim = stage.GetPrimAtPath("/root/Light/Light")
    prim.GetAttribute("inputs:radius").Set(0.0)
    prim.CreateAttribute("inputs:treatAsPoint", Sdf.ValueTypeNames.Bool).Set(True)
    light, _ = read(stage)
    assert light["type"] == "point" and light.get("radius", 0.0) == 0.0
    assert light["camera_visible"] is False


def test_blender_named_by_the_creator_or_only_by_user_properties():
    stage = stage_with(blender=False)
    stage.GetRootLayer().customLayerData = {"creator": "Blender v5.0.1"}
    light, r = read(stage)
    assert light["camera_visible"] is False
    assert any("Blender v5.0.1" in m and HIDDEN in m for m in notes_of(r))
    # No layer metadata, only the exporter's user properties on the prim.
    light, r = read(stage_with(doc=None))
    assert light["camera_visible"] is False
    assert any(m.startswith("written by Blender:") and HIDDEN in m for m in notes_of(r))


def test_a_non_blender_doc_is_not_blender():
    stage = stage_with(blender=False)
    stage.GetRootLayer().documentation = "Exported from Houdini 20.5"
    light, _ = read(stage)
    assert light["camera_visible"] is True


# What a stage may say about a light's camera visibility: the first authored of these decides.
OPINIONS = [
    ("primvars:photonmap:camera_visible", Sdf.ValueTypeNames.Bool, True),
    ("karma:light:renderlightgeo", Sdf.ValueTypeNames.Bool, True),
    ("primvars:ri:attributes:visibility:camera", Sdf.ValueTypeNames.Int, 1),
]


@pytest.mark.parametrize("name,type_name,value", OPINIONS)
def test_an_authored_opinion_that_shows_a_blender_light_is_respected(name, type_name, value):
    stage = stage_with("RectLight")
    stage.GetPrimAtPath("/root/Light/Light").CreateAttribute(name, type_name).Set(value)
    light, r = read(stage)
    assert light["camera_visible"] is True
    assert not any(HIDDEN in m for m in r.diagnostics.messages())


@pytest.mark.parametrize("name,type_name,value", OPINIONS)
def test_an_authored_opinion_that_hides_a_light_is_respected_on_any_stage(name, type_name, value):
    stage = stage_with("RectLight", blender=False)
    stage.GetPrimAtPath("/root/Light/Light").CreateAttribute(name, type_name).Set(
        type(value)(0))
    light, _ = read(stage)
    assert light["camera_visible"] is False


def test_the_renderers_primvar_is_inherited_from_an_ancestor():
    stage = stage_with("SphereLight")
    UsdGeom.PrimvarsAPI(stage.GetPrimAtPath("/root")).CreatePrimvar(
        "photonmap:camera_visible", Sdf.ValueTypeNames.Bool).Set(True)
    light, _ = read(stage)
    assert light["camera_visible"] is True


def test_the_renderers_primvar_comes_before_karmas():
    stage = stage_with("RectLight")
    prim = stage.GetPrimAtPath("/root/Light/Light")
    prim.CreateAttribute("karma:light:renderlightgeo", Sdf.ValueTypeNames.Bool).Set(True)
    prim.CreateAttribute("primvars:photonmap:camera_visible", Sdf.ValueTypeNames.Bool).Set(False)
    light, _ = read(stage)
    assert light["camera_visible"] is False


def test_an_unauthored_visibility_attribute_is_no_opinion():
    stage = stage_with("RectLight")
    stage.GetPrimAtPath("/root/Light/Light").CreateAttribute(
        "karma:light:renderlightgeo", Sdf.ValueTypeNames.Bool)  # declared, no value
    light, _ = read(stage)
    assert light["camera_visible"] is False


# -- the sun's angle ----------------------------------------------------------------------


def test_blender_5_0_suns_angle_is_doubled_with_a_note():
    light, r = read(stage_with("DistantLight"))
    assert light["type"] == "distant"
    # Blender's Angle 10 deg, written `float inputs:angle = 5`.
    assert light["angle"] == pytest.approx(math.radians(10.0))
    assert light["irradiance"] == pytest.approx(0.75)  # intensity read per UsdLux
    assert "camera_visible" not in light  # the IR's distant lights take none
    notes = notes_of(r)
    assert any("Blender v5.0.1" in m and "angle 5 deg read as 10 deg" in m for m in notes), notes


def test_a_non_blender_suns_angle_is_read_per_usdlux():
    light, r = read(stage_with("DistantLight", blender=False))
    assert light["angle"] == pytest.approx(math.radians(5.0))
    assert not any("Blender" in m for m in r.diagnostics.messages())


@pytest.mark.parametrize("doc", ["Blender v4.2.3 LTS", "Blender v5.1.0"])
def test_other_blender_versions_are_read_per_usdlux_and_noted(doc):
    light, r = read(stage_with("DistantLight", doc=doc))
    assert light["angle"] == pytest.approx(math.radians(5.0))
    assert any(doc in m and "read per UsdLux" in m for m in notes_of(r)), r.diagnostics.notes


def test_no_version_no_doubling():
    light, _ = read(stage_with("DistantLight", doc=None))  # only userProperties:blender:*
    assert light["angle"] == pytest.approx(math.radians(5.0))


def test_the_layer_of_the_angles_strongest_opinion_decides():
    """A Blender 5.0.1 layer under a stage of another writer: its own angle is doubled, an
    angle overridden in the stronger layer is not."""
    blender_layer = Sdf.Layer.CreateAnonymous(".usda")
    stage_with("DistantLight", layer=blender_layer)
    top = Sdf.Layer.CreateAnonymous(".usda")
    top.subLayerPaths.append(blender_layer.identifier)
    stage = Usd.Stage.Open(top)
    assert stage.GetRootLayer().documentation == ""
    light, r = read(stage)
    assert light["angle"] == pytest.approx(math.radians(10.0))
    stage.GetPrimAtPath("/root/Light/Light").GetAttribute("inputs:angle").Set(8.0)
    light, r = read(stage)
    assert light["angle"] == pytest.approx(math.radians(8.0))


def test_the_committed_blender_stage_reads_its_sun_as_blender_has_it():
    """tests/blender/corpus/usd/sun_angle.usda: Blender's sun of Angle 10 deg, written as
    `float inputs:angle = 5`."""
    import os

    here = os.path.dirname(os.path.abspath(__file__))
    path = os.path.join(here, "..", "blender", "corpus", "usd", "sun_angle.usda")
    with open(path) as f:
        assert "float inputs:angle = 5\n" in f.read()
    r = usd_delegate.load_stage(path)
    (sun,) = [x for x in r.ir["lights"] if x["type"] == "distant"]
    assert sun["angle"] == pytest.approx(math.radians(10.0))
