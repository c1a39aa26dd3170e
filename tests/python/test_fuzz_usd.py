"""Mutation fuzzing of the USD importer with hypothesis.

A small Cornell-box-like stage (walls with a UsdPreviewSurface and displayColor, a glass box
in a GeomSubset, a RectLight, a SphereLight, a camera) is written with pxr and exported as
.usda text; hypothesis deletes and duplicates tokens, replaces numbers with NaN, inf, huge or
negative values, and truncates the text. ``usd_delegate.load_stage`` must then return an
import result or raise ``UsdImportError`` (its documented error); an IR that it returns must be
accepted by ``photonmap.Scene.from_dict`` or rejected with ``photonmap.SceneError``. Any other
exception fails the test. Bounded to 600 examples (about 20 s).
"""
import os
import re

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pxr import Gf, Sdf, Usd, UsdGeom, UsdLux, UsdShade, Vt

import photonmap
import usd_delegate

NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")
TOKEN = re.compile(r"\S+")
BAD_NUMBERS = ["nan", "-nan", "inf", "-inf", "1e38", "3.5e38", "1e300", "-1", "-1e30", "0",
               "1e-45", "-0", "4294967295", "-2147483649", "99999999999999999999"]


def cornell_usda() -> str:
    stage = Usd.Stage.CreateInMemory("cornell.usda")
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdGeom.Xform.Define(stage, "/World")
    mat = UsdShade.Material.Define(stage, "/World/Looks/White")
    sh = UsdShade.Shader.Define(stage, "/World/Looks/White/Surface")
    sh.CreateIdAttr("UsdPreviewSurface")
    sh.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).Set(Gf.Vec3f(0.75, 0.75, 0.75))
    sh.CreateInput("roughness", Sdf.ValueTypeNames.Float).Set(0.8)
    mat.CreateSurfaceOutput().ConnectToSource(sh.ConnectableAPI(), "surface")
    glass = UsdShade.Material.Define(stage, "/World/Looks/Glass")
    gs = UsdShade.Shader.Define(stage, "/World/Looks/Glass/Surface")
    gs.CreateIdAttr("ND_open_pbr_surface_surfaceshader")
    gs.CreateInput("transmission_weight", Sdf.ValueTypeNames.Float).Set(1.0)
    gs.CreateInput("specular_ior", Sdf.ValueTypeNames.Float).Set(1.5)
    gs.CreateInput("specular_roughness", Sdf.ValueTypeNames.Float).Set(0.0)
    gs.CreateOutput("surface", Sdf.ValueTypeNames.Token)
    glass.CreateSurfaceOutput("mtlx").ConnectToSource(gs.ConnectableAPI(), "surface")

    walls = UsdGeom.Mesh.Define(stage, "/World/Walls")
    p = [(-1, -1, 1), (1, -1, 1), (1, -1, -1), (-1, -1, -1),
         (-1, 1, 1), (1, 1, 1), (1, 1, -1), (-1, 1, -1)]
    walls.CreatePointsAttr([Gf.Vec3f(*v) for v in p])
    walls.CreateFaceVertexCountsAttr([4, 4, 4, 4, 4])
    walls.CreateFaceVertexIndicesAttr([0, 1, 2, 3, 4, 7, 6, 5, 3, 2, 6, 7, 0, 3, 7, 4, 1, 5, 6, 2])
    walls.CreateSubdivisionSchemeAttr("none")
    walls.CreateDisplayColorPrimvar(UsdGeom.Tokens.uniform).Set(
        [Gf.Vec3f(0.75, 0.75, 0.75)] * 3 + [Gf.Vec3f(0.63, 0.06, 0.05), Gf.Vec3f(0.14, 0.45, 0.09)])
    UsdShade.MaterialBindingAPI.Apply(walls.GetPrim()).Bind(mat)
    st_pv = UsdGeom.PrimvarsAPI(walls).CreatePrimvar("st", Sdf.ValueTypeNames.TexCoord2fArray,
                                                     UsdGeom.Tokens.faceVarying)
    st_pv.Set([(0, 0), (1, 0), (1, 1), (0, 1)] * 5)

    box = UsdGeom.Mesh.Define(stage, "/World/Box")
    b = 0.3
    bp = [(-b, -b, -b), (b, -b, -b), (b, b, -b), (-b, b, -b),
          (-b, -b, b), (b, -b, b), (b, b, b), (-b, b, b)]
    box.CreatePointsAttr([Gf.Vec3f(*v) for v in bp])
    box.CreateFaceVertexCountsAttr([4] * 6)
    box.CreateFaceVertexIndicesAttr([0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4,
                                     2, 3, 7, 6, 1, 2, 6, 5, 0, 4, 7, 3])
    box.CreateSubdivisionSchemeAttr("none")
    box.CreateNormalsAttr([Gf.Vec3f(0, 0, 1)] * 8)
    box.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
    UsdGeom.XformCommonAPI(box).SetTranslate((0.3, -0.7, 0.2))
    UsdGeom.XformCommonAPI(box).SetRotate((0, 30, 0))
    sub = UsdGeom.Subset.CreateGeomSubset(box, "glassFaces", UsdGeom.Tokens.face,
                                          Vt.IntArray([0, 1, 2]), UsdShade.Tokens.materialBind)
    UsdShade.MaterialBindingAPI.Apply(sub.GetPrim()).Bind(glass)

    rect = UsdLux.RectLight.Define(stage, "/World/Lamp")
    rect.CreateWidthAttr(0.5)
    rect.CreateHeightAttr(0.4)
    rect.CreateIntensityAttr(20.0)
    rect.CreateExposureAttr(0.5)
    rect.CreateColorAttr(Gf.Vec3f(1.0, 0.9, 0.8))
    UsdGeom.XformCommonAPI(rect).SetTranslate((0, 0.98, 0))
    UsdGeom.XformCommonAPI(rect).SetRotate((90, 0, 0))
    ball = UsdLux.SphereLight.Define(stage, "/World/Ball")
    ball.CreateRadiusAttr(0.05)
    ball.CreateIntensityAttr(5.0)
    ball.AddTranslateOp().Set(Gf.Vec3d(-0.5, 0.5, 0.0))

    cam = UsdGeom.Camera.Define(stage, "/World/Cam")
    cam.CreateFocalLengthAttr(35.0)
    cam.CreateHorizontalApertureAttr(36.0)
    cam.CreateVerticalApertureAttr(36.0)
    cam.CreateClippingRangeAttr(Gf.Vec2f(0.01, 1000.0))
    UsdGeom.XformCommonAPI(cam).SetTranslate((0, 0, 4))
    return stage.GetRootLayer().ExportToString()


BASE = cornell_usda()
N_TOKENS = len(TOKEN.findall(BASE))
N_NUMBERS = len(NUMBER.findall(BASE))

mutation = st.one_of(
    st.tuples(st.just("delete"), st.integers(0, N_TOKENS - 1), st.integers(1, 3)),
    st.tuples(st.just("duplicate"), st.integers(0, N_TOKENS - 1), st.integers(1, 3)),
    st.tuples(st.just("number"), st.integers(0, N_NUMBERS - 1), st.sampled_from(BAD_NUMBERS)),
    st.tuples(st.just("truncate"), st.integers(0, len(BASE)), st.just(None)),
)


def mutate(text: str, ops) -> str:
    for kind, at, arg in ops:
        if kind == "truncate":
            text = text[:at]
            continue
        pattern = NUMBER if kind == "number" else TOKEN
        spans = [m.span() for m in pattern.finditer(text)]
        if not spans:
            continue
        i = at % len(spans)
        if kind == "number":
            a, b = spans[i]
            text = text[:a] + arg + text[b:]
        else:
            j = min(i + arg, len(spans)) - 1
            a, b = spans[i][0], spans[j][1]
            piece = "" if kind == "delete" else text[a:b] + " " + text[a:b]
            text = text[:a] + piece + text[b:]
    return text


def import_or_documented_error(path):
    """Imports the stage; returns the IR or None when the importer rejects the stage."""
    try:
        r = usd_delegate.load_stage(str(path), width=16)
    except usd_delegate.UsdImportError:
        return None
    try:
        photonmap.Scene.from_dict(r.ir)
    except photonmap.SceneError:
        pass
    return r.ir


def test_base_stage_imports(tmp_path):
    path = tmp_path / "base.usda"
    path.write_text(BASE)
    ir = import_or_documented_error(path)
    assert ir is not None and len(ir["meshes"]) == 2 and len(ir["lights"]) == 2
    photonmap.Scene.from_dict(ir)


# PHOTONMAP_FUZZ_EXAMPLES raises the count and draws new examples (scripts/fuzz.sh); by default
# the same examples run every time.
EXAMPLES = int(os.environ.get("PHOTONMAP_FUZZ_EXAMPLES", "0"))


@settings(max_examples=EXAMPLES or 600, deadline=None, derandomize=not EXAMPLES, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(ops=st.lists(mutation, min_size=1, max_size=4))
def test_mutated_usda_imports_or_raises_import_error(tmp_path, ops):
    text = mutate(BASE, ops)
    path = tmp_path / "m.usda"
    path.write_text(text)
    import_or_documented_error(path)


@pytest.mark.parametrize("value", BAD_NUMBERS)
def test_every_number_replaced_by_a_bad_value(tmp_path, value):
    """Each bad value in every numeric slot of the walls and the lamp, one slot at a time."""
    spans = [m.span() for m in NUMBER.finditer(BASE)]
    path = tmp_path / "n.usda"
    for a, b in spans[:: max(1, len(spans) // 40)]:
        path.write_text(BASE[:a] + value + BASE[b:])
        import_or_documented_error(path)


# Inputs the fuzzing found, each once a TypeError or a pxr Tf.ErrorException out of the
# importer: a primvar of an unknown type, and a translate op whose type name is unknown.
FOUND = {
    "unknown_primvar_type": ("texCoord2f[] primvars:st", "texCoordnanf[] primvars:st",
                             "/World/Walls: primvars:st"),
    "unknown_xform_op_type": ("double3 xformOp:translate = (0.3", "double0 xformOp:translate = (0.3",
                              "/World/Box: Invalid combination of opType"),
}


@pytest.mark.parametrize("case", sorted(FOUND))
def test_found_inputs_raise_import_error_naming_the_prim(tmp_path, case):
    old, new, message = FOUND[case]
    assert old in BASE
    path = tmp_path / f"{case}.usda"
    path.write_text(BASE.replace(old, new, 1))
    with pytest.raises(usd_delegate.UsdImportError, match=re.escape(message)):
        usd_delegate.load_stage(str(path))
