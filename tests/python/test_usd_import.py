"""USD stages written with pxr, one per feature; assertions on the imported IR."""
import math

import numpy as np
import pytest
from conftest import add_camera, add_mesh, import_stage, quad
from pxr import Gf, Sdf, Usd, UsdGeom, UsdLux, UsdShade, Vt

import photonmap
import usd_delegate


def test_concave_polygon_and_ngon_triangulation(stage_factory):
    stage, path = stage_factory()
    # An L-shaped hexagon (concave) and a convex pentagon.
    L = [(0, 0, 0), (2, 0, 0), (2, 1, 0), (1, 1, 0), (1, 2, 0), (0, 2, 0)]
    P = [(5 + math.cos(a), math.sin(a), 0) for a in np.linspace(0, 2 * math.pi, 6)[:-1]]
    add_mesh(stage, "/M", L + P, [6, 5], list(range(11)))
    add_camera(stage)
    r = import_stage(stage, path)
    m = r.ir["meshes"][0]
    assert len(m["indices"]) == 4 + 3
    pos = m["positions"][m["indices"][:4]]
    area = 0.5 * np.linalg.norm(np.cross(pos[:, 1] - pos[:, 0], pos[:, 2] - pos[:, 0]), axis=1)
    assert area.sum() == pytest.approx(3.0)  # the L's area: no triangle outside it
    n = np.cross(pos[:, 1] - pos[:, 0], pos[:, 2] - pos[:, 0])
    assert np.all(n[:, 2] > 0)  # winding kept
    assert r.stats["triangles"] == 7


def test_left_handed_flips_winding_and_transforms(stage_factory):
    stage, path = stage_factory()
    UsdGeom.Xform.Define(stage, "/X")
    m = quad(stage, "/X/Q")
    m.CreateOrientationAttr(UsdGeom.Tokens.leftHanded)
    UsdGeom.XformCommonAPI(stage.GetPrimAtPath("/X")).SetTranslate((1, 2, 3))
    UsdGeom.XformCommonAPI(m).SetScale((2, 2, 2))
    add_camera(stage)
    r = import_stage(stage, path)
    mesh = r.ir["meshes"][0]
    p = mesh["positions"][mesh["indices"][0]]
    assert np.cross(p[1] - p[0], p[2] - p[0])[2] < 0
    t = np.array(mesh["transform"])
    assert np.allclose(t[:3, 3], [1, 2, 3]) and np.allclose(np.diag(t)[:3], 2)


@pytest.mark.parametrize("interp", ["constant", "uniform", "vertex", "faceVarying"])
def test_normals_every_interpolation(stage_factory, interp):
    stage, path = stage_factory()
    pts = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (2, 0, 0), (2, 1, 0)]
    m = add_mesh(stage, "/M", pts, [4, 4], [0, 1, 2, 3, 1, 4, 5, 2])
    n = {"constant": 1, "uniform": 2, "vertex": 6, "faceVarying": 8}[interp]
    vals = [Gf.Vec3f(0, 0.6 if i % 2 else 0, 0.8 if i % 2 else 1) for i in range(n)]
    pv = UsdGeom.PrimvarsAPI(m).CreatePrimvar("normals", Sdf.ValueTypeNames.Normal3fArray, interp)
    pv.Set(vals)
    add_camera(stage)
    mesh = import_stage(stage, path).ir["meshes"][0]
    nv = {"constant": 6, "uniform": 8, "vertex": 6, "faceVarying": 8}[interp]
    assert len(mesh["positions"]) == nv
    assert np.allclose(np.linalg.norm(mesh["normals"], axis=1), 1)
    if interp == "uniform":  # each face's corners carry that face's normal
        fn = mesh["normals"][mesh["indices"]]
        assert np.allclose(fn[:2], [0, 0, 1]) and np.allclose(fn[2:], [0, 0.6, 0.8])


def test_faceVarying_indexed_uvs_split_vertices(stage_factory):
    stage, path = stage_factory()
    m = quad(stage)
    pv = UsdGeom.PrimvarsAPI(m).CreatePrimvar("st", Sdf.ValueTypeNames.TexCoord2fArray, "faceVarying")
    pv.Set([(0, 0), (1, 0), (1, 1), (0, 1)])
    pv.SetIndices(Vt.IntArray([0, 1, 2, 3]))
    add_camera(stage)
    mesh = import_stage(stage, path).ir["meshes"][0]
    assert mesh["uvs"].shape == (4, 2)
    i = np.argmin(np.linalg.norm(mesh["positions"] - [1, 1, 0], axis=1))
    assert np.allclose(mesh["uvs"][i], [1, 1])


def test_subdivision_cage_gets_smooth_normals_and_a_warning(stage_factory):
    stage, path = stage_factory()
    add_mesh(stage, "/S", [(0, 0, 0), (1, 0, 0), (1, 1, 1), (0, 1, 1), (2, 0, 1)], [4, 3], [0, 1, 2, 3, 1, 4, 2], scheme="catmullClark")
    add_camera(stage)
    r = import_stage(stage, path)
    assert r.ir["meshes"][0]["normals"] is not None
    assert any("subdivisionScheme" in m for m in r.diagnostics.messages())
    with pytest.raises(usd_delegate.UsdImportError, match="/S: subdivision"):
        import_stage(stage, path, strict=True)


def _preview_material(stage, path, color, **inputs):
    mat = UsdShade.Material.Define(stage, path)
    sh = UsdShade.Shader.Define(stage, path + "/Preview")
    sh.CreateIdAttr("UsdPreviewSurface")
    sh.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).Set(color)
    for k, v in inputs.items():
        tn = Sdf.ValueTypeNames.Color3f if isinstance(v, tuple) else Sdf.ValueTypeNames.Float
        sh.CreateInput(k, tn).Set(v)
    mat.CreateSurfaceOutput().ConnectToSource(sh.ConnectableAPI(), "surface")
    return mat, sh


def test_geomsubset_material_ids(stage_factory):
    stage, path = stage_factory()
    pts = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (2, 0, 0), (2, 1, 0)]
    m = add_mesh(stage, "/M", pts, [4, 4], [0, 1, 2, 3, 1, 4, 5, 2])
    red, _ = _preview_material(stage, "/Mat/Red", (1, 0, 0))
    blue, _ = _preview_material(stage, "/Mat/Blue", (0, 0, 1))
    UsdShade.MaterialBindingAPI.Apply(m.GetPrim()).Bind(red)
    sub = UsdGeom.Subset.CreateGeomSubset(m, "right", "face", Vt.IntArray([1]), "materialBind")
    UsdShade.MaterialBindingAPI.Apply(sub.GetPrim()).Bind(blue)
    add_camera(stage)
    layer_before = stage.GetRootLayer().ExportToString()
    r = import_stage(stage, path)
    mesh = r.ir["meshes"][0]
    mats = r.ir["materials"]
    ids = mesh["material_indices"]
    assert len(ids) == 4
    assert [mats[i]["base_color"] for i in ids] == [[1, 0, 0]] * 2 + [[0, 0, 1]] * 2
    assert stage.GetRootLayer().ExportToString() == layer_before  # read-only


def test_preview_surface_mapping(stage_factory):
    stage, path = stage_factory()
    m = quad(stage)
    mat, _ = _preview_material(stage, "/Mat/P", (0.2, 0.3, 0.4), metallic=0.7, roughness=0.25,
                               ior=1.33, opacity=0.4, emissiveColor=(1.0, 0.5, 0.0))
    UsdShade.MaterialBindingAPI.Apply(m.GetPrim()).Bind(mat)
    add_camera(stage)
    g = import_stage(stage, path).ir["materials"][0]
    # Opacity below 1 is coverage (the UsdPreviewSurface spec), not transmission: a
    # Principled in a graph, with Alpha = opacity.
    assert g["type"] == "graph"
    (p,) = [n for n in g["nodes"] if n["type"] == "principled"]
    i = p["inputs"]
    assert np.allclose(i["base_color"], [0.2, 0.3, 0.4])
    assert i["metallic"] == pytest.approx(0.7) and i["roughness"] == pytest.approx(0.25)
    assert i["ior"] == pytest.approx(1.33) and i["alpha"] == pytest.approx(0.4)
    assert i.get("transmission_weight", 0.0) == 0.0
    assert np.allclose(i["emission_color"], [1.0, 0.5, 0.0]) and i["emission_strength"] == 1.0


def test_openpbr_glass_preferred_over_preview_surface(stage_factory):
    stage, path = stage_factory()
    m = quad(stage)
    mat, _ = _preview_material(stage, "/Mat/Glass", (0.8, 0.8, 0.8), opacity=1.0)
    sh = UsdShade.Shader.Define(stage, "/Mat/Glass/OpenPBR")
    sh.CreateIdAttr("ND_open_pbr_surface_surfaceshader")
    sh.CreateInput("base_color", Sdf.ValueTypeNames.Color3f).Set((1, 1, 1))
    sh.CreateInput("base_weight", Sdf.ValueTypeNames.Float).Set(0.5)
    sh.CreateInput("transmission_weight", Sdf.ValueTypeNames.Float).Set(1.0)
    sh.CreateInput("specular_ior", Sdf.ValueTypeNames.Float).Set(1.45)
    sh.CreateInput("specular_roughness", Sdf.ValueTypeNames.Float).Set(0.0)
    sh.CreateInput("specular_weight", Sdf.ValueTypeNames.Float).Set(1.0)
    sh.CreateOutput("surface", Sdf.ValueTypeNames.Token)
    mat.CreateSurfaceOutput("mtlx").ConnectToSource(sh.ConnectableAPI(), "surface")
    UsdShade.MaterialBindingAPI.Apply(m.GetPrim()).Bind(mat)
    add_camera(stage)
    p = import_stage(stage, path).ir["materials"][0]
    assert p["transmission"] == 1.0 and p["ior"] == pytest.approx(1.45)
    assert p["roughness"] == 0.0 and np.allclose(p["base_color"], 0.5)


def test_standard_surface(stage_factory):
    stage, path = stage_factory()
    m = quad(stage)
    mat = UsdShade.Material.Define(stage, "/Mat/S")
    sh = UsdShade.Shader.Define(stage, "/Mat/S/SS")
    sh.CreateIdAttr("ND_standard_surface_surfaceshader")
    sh.CreateInput("metalness", Sdf.ValueTypeNames.Float).Set(1.0)
    sh.CreateInput("base_color", Sdf.ValueTypeNames.Color3f).Set((0.9, 0.6, 0.2))
    sh.CreateInput("base", Sdf.ValueTypeNames.Float).Set(1.0)
    mat.CreateSurfaceOutput("mtlx").ConnectToSource(sh.ConnectableAPI(), "surface")
    UsdShade.MaterialBindingAPI.Apply(m.GetPrim()).Bind(mat)
    add_camera(stage)
    p = import_stage(stage, path).ir["materials"][0]
    assert p["metallic"] == 1.0 and np.allclose(p["base_color"], [0.9, 0.6, 0.2])
    assert p["roughness"] == pytest.approx(0.2)


def test_textures_and_missing_texture(stage_factory, tmp_path):
    import OpenImageIO as oiio

    img = np.zeros((2, 4, 3), np.uint8)
    img[:, :, 0] = 255
    img[0, 0] = (188, 188, 188)
    tex = str(tmp_path / "t.png")
    out = oiio.ImageOutput.create(tex)
    out.open(tex, oiio.ImageSpec(4, 2, 3, oiio.UINT8))
    out.write_image(img)
    out.close()
    stage, path = stage_factory()
    for name, f in (("A", "t.png"), ("B", "missing.png")):
        m = quad(stage, f"/{name}", z=0 if name == "A" else 1)
        mat, sh = _preview_material(stage, f"/Mat/{name}", (0.5, 0.5, 0.5))
        t = UsdShade.Shader.Define(stage, f"/Mat/{name}/Tex")
        t.CreateIdAttr("UsdUVTexture")
        t.CreateInput("file", Sdf.ValueTypeNames.Asset).Set(f)
        t.CreateInput("wrapS", Sdf.ValueTypeNames.Token).Set("clamp")
        t.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
        sh.GetInput("diffuseColor").ConnectToSource(t.ConnectableAPI(), "rgb")
        UsdShade.MaterialBindingAPI.Apply(m.GetPrim()).Bind(mat)
    add_camera(stage)
    r = import_stage(stage, path)
    mats = r.ir["materials"]
    assert mats[0]["base_color"] == {"texture": 0, "scale": [1.0, 1.0, 1.0]}
    t0 = r.ir["textures"][0]
    assert (t0["width"], t0["height"], t0["channels"], t0["wrap"]) == (4, 2, 3, "clamp")
    # An 8-bit sRGB image is passed encoded; the core decodes after interpolating.
    assert t0["encoding"] == "srgb" and t0["data"][0] == pytest.approx(188 / 255, abs=1e-6)
    assert mats[1]["base_color"] == [1.0, 0.0, 1.0]
    w = [m for m in r.diagnostics.messages() if "missing.png" in m]
    assert w and "/Mat/B/Tex" in w[0]


def test_mtlx_image_through_a_type_conversion(stage_factory, tmp_path):
    """Blender's exporter: ND_image_color4 -> ND_convert_color4_color3 -> a NodeGraph output
    -> OpenPBR base_color. The conversion passes the image on."""
    import OpenImageIO as oiio

    tex = str(tmp_path / "c.png")
    out = oiio.ImageOutput.create(tex)
    out.open(tex, oiio.ImageSpec(2, 2, 3, oiio.UINT8))
    out.write_image(np.full((2, 2, 3), 255, np.uint8))
    out.close()
    stage, path = stage_factory()
    m = quad(stage)
    mat = UsdShade.Material.Define(stage, "/Mat/C")
    sh = UsdShade.Shader.Define(stage, "/Mat/C/PBR")
    sh.CreateIdAttr("ND_open_pbr_surface_surfaceshader")
    g = UsdShade.NodeGraph.Define(stage, "/Mat/C/NodeGraphs")
    img = UsdShade.Shader.Define(stage, "/Mat/C/NodeGraphs/img")
    img.CreateIdAttr("ND_image_color4")
    img.CreateInput("file", Sdf.ValueTypeNames.Asset).Set("c.png")
    img.CreateOutput("out", Sdf.ValueTypeNames.Color4f)
    conv = UsdShade.Shader.Define(stage, "/Mat/C/NodeGraphs/node")
    conv.CreateIdAttr("ND_convert_color4_color3")
    conv.CreateInput("in", Sdf.ValueTypeNames.Color4f).ConnectToSource(img.ConnectableAPI(), "out")
    conv.CreateOutput("out", Sdf.ValueTypeNames.Color3f)
    g.CreateOutput("node_out", Sdf.ValueTypeNames.Color3f).ConnectToSource(conv.ConnectableAPI(), "out")
    sh.CreateInput("base_color", Sdf.ValueTypeNames.Color3f).ConnectToSource(g.ConnectableAPI(), "node_out")
    sh.CreateOutput("surface", Sdf.ValueTypeNames.Token)
    mat.CreateSurfaceOutput("mtlx").ConnectToSource(sh.ConnectableAPI(), "surface")
    UsdShade.MaterialBindingAPI.Apply(m.GetPrim()).Bind(mat)
    add_camera(stage)
    r = import_stage(stage, path)
    assert r.ir["materials"][0]["base_color"] == {"texture": 0, "scale": [1.0, 1.0, 1.0]}
    assert not [w for w in r.diagnostics.messages() if "unsupported" in w]


def _light_stage(stage_factory, kind, **inputs):
    stage, path = stage_factory()
    L = getattr(UsdLux, kind).Define(stage, "/L")
    for k, v in inputs.items():
        tn = {bool: Sdf.ValueTypeNames.Bool, tuple: Sdf.ValueTypeNames.Color3f}.get(type(v), Sdf.ValueTypeNames.Float)
        L.GetPrim().CreateAttribute(f"inputs:{k}", tn).Set(v)
    add_camera(stage)
    return stage, path, L


def test_rect_light_normalize_exposure_temperature(stage_factory):
    stage, path, L = _light_stage(stage_factory, "RectLight", width=0.5, height=0.4, intensity=10.0)
    r = import_stage(stage, path)
    l = r.ir["lights"][0]
    assert l["type"] == "rect" and l["power"] == pytest.approx(10 * math.pi * 0.2)
    L.GetPrim().GetAttribute("inputs:normalize").Set(True) if L.GetPrim().GetAttribute("inputs:normalize") else L.CreateNormalizeAttr(True)
    L.CreateExposureAttr(1.0)
    UsdGeom.XformCommonAPI(L).SetScale((2, 1, 1))
    l = import_stage(stage, path).ir["lights"][0]
    assert l["power"] == pytest.approx(20 * math.pi)  # normalised: independent of the area
    assert l["width"] == pytest.approx(1.0)
    L.CreateEnableColorTemperatureAttr(True)
    L.CreateColorTemperatureAttr(6500.0)
    r = import_stage(stage, path)
    assert np.allclose(r.ir["lights"][0]["color"], [1.0433, 0.9836, 1.0346], atol=1e-3)
    assert any("colour temperature" in m for m in r.diagnostics.messages())


def test_old_light_inputs_without_prefix(stage_factory):
    stage, path = stage_factory()
    prim = stage.DefinePrim("/L", "SphereLight")
    prim.CreateAttribute("intensity", Sdf.ValueTypeNames.Float).Set(3.0)
    prim.CreateAttribute("radius", Sdf.ValueTypeNames.Float).Set(0.1)
    add_camera(stage)
    l = import_stage(stage, path).ir["lights"][0]
    assert l["type"] == "sphere" and l["power"] == pytest.approx(3 * 4 * math.pi ** 2 * 0.01)


def test_sphere_spot_distant_disk_cylinder_dome(stage_factory):
    stage, path = stage_factory()
    s = UsdLux.SphereLight.Define(stage, "/Spot")
    s.CreateRadiusAttr(0.0)
    s.CreateTreatAsPointAttr(True)
    s.CreateNormalizeAttr(True)
    s.CreateIntensityAttr(100.0)
    sh = UsdLux.ShapingAPI.Apply(s.GetPrim())
    sh.CreateShapingConeAngleAttr(30.0)
    sh.CreateShapingConeSoftnessAttr(0.2)
    d = UsdLux.DistantLight.Define(stage, "/Sun")
    d.CreateIntensityAttr(3.0)
    d.CreateAngleAttr(1.0)
    UsdLux.DiskLight.Define(stage, "/Disk").CreateRadiusAttr(0.25)
    c = UsdLux.CylinderLight.Define(stage, "/Cyl")
    c.CreateRadiusAttr(0.1)
    c.CreateLengthAttr(2.0)
    UsdLux.DomeLight.Define(stage, "/Dome").CreateColorAttr((0.1, 0.2, 0.3))
    add_camera(stage)
    r = import_stage(stage, path)
    by = {l["name"]: l for l in r.ir["lights"]}
    spot = by["/Spot"]
    assert spot["type"] == "spot" and spot["cone_angle"] == pytest.approx(math.radians(60))
    assert spot["blend"] == pytest.approx(0.2) and spot["power"] == pytest.approx(100 * math.pi)
    assert np.allclose(spot["direction"], [0, 0, -1])
    sun = by["/Sun"]
    assert sun["irradiance"] == 3.0 and sun["angle"] == pytest.approx(math.radians(1.0))
    assert by["/Disk"]["power"] == pytest.approx(math.pi * math.pi * 0.0625)
    cyl = by["/Cyl"]
    assert cyl["type"] == "sphere" and 4 * math.pi * cyl["radius"] ** 2 == pytest.approx(2 * math.pi * 0.1 * 2)
    assert any("cylinder" in m for m in r.diagnostics.messages())
    assert r.ir["environment"]["color"] == pytest.approx([0.1, 0.2, 0.3])


def test_camera_fov_selection_and_default(stage_factory):
    stage, path = stage_factory()
    quad(stage)
    UsdLux.DistantLight.Define(stage, "/Sun")
    add_camera(stage, "/A", focal=50, h_ap=36, v_ap=24)
    b = add_camera(stage, "/B", focal=20, h_ap=36, v_ap=36)
    b.CreateFStopAttr(2.0)
    b.CreateFocusDistanceAttr(4.0)
    b.CreateHorizontalApertureOffsetAttr(3.6)
    r = import_stage(stage, path)
    cam = r.ir["camera"]
    assert r.stats["camera"] == "/A"
    assert 2 * math.atan(cam["sensor_width"] / (2 * cam["focal_length"])) == pytest.approx(2 * math.atan(0.36))
    assert r.ir["film"]["height"] == round(r.ir["film"]["width"] * 24 / 36)
    cam = import_stage(stage, path, camera="/B").ir["camera"]
    assert cam["fstop"] == 2.0 and cam["focus_distance"] == 4.0 and cam["shift"][0] == pytest.approx(0.1)
    assert cam["units_per_mm"] == 0.1
    with pytest.raises(usd_delegate.UsdImportError, match="/Nope"):
        import_stage(stage, path, camera="/Nope")
    stage.RemovePrim("/A")
    stage.RemovePrim("/B")
    r = import_stage(stage, path)
    assert any("no camera" in m for m in r.diagnostics.messages())


def test_purposes_and_visibility(stage_factory):
    stage, path = stage_factory()
    quad(stage, "/Default")
    quad(stage, "/Proxy").CreatePurposeAttr("proxy")
    quad(stage, "/Render").CreatePurposeAttr("render")
    quad(stage, "/Guide").CreatePurposeAttr("guide")
    quad(stage, "/Hidden").CreateVisibilityAttr("invisible")
    add_camera(stage)
    names = lambda r: sorted(m["name"] for m in r.ir["meshes"])
    assert names(import_stage(stage, path)) == ["/Default", "/Render"]
    assert names(import_stage(stage, path, purposes=["proxy"])) == ["/Default", "/Proxy"]


def test_point_instancer_shares_one_mesh(stage_factory):
    stage, path = stage_factory()
    pi = UsdGeom.PointInstancer.Define(stage, "/PI")
    quad(stage, "/PI/Protos/Q", size=0.1)
    pi.CreatePrototypesRel().SetTargets(["/PI/Protos/Q"])
    pi.CreateProtoIndicesAttr([0] * 5)
    pi.CreatePositionsAttr([Gf.Vec3f(i, 0, 0) for i in range(5)])
    add_camera(stage)
    r = import_stage(stage, path)
    assert len(r.ir["meshes"]) == 1 and len(r.ir["instances"]) == 5
    xs = sorted(np.array(i["transform"])[0, 3] for i in r.ir["instances"])
    assert np.allclose(xs, range(5))


def test_instanceable_prims_share_one_mesh(stage_factory):
    stage, path = stage_factory()
    proto = stage.CreateClassPrim("/_proto")
    quad(stage, "/_proto/Q", size=0.1)
    for i in range(3):
        p = stage.DefinePrim(f"/I{i}", "Xform")
        p.GetInherits().AddInherit("/_proto")
        p.SetInstanceable(True)
        UsdGeom.XformCommonAPI(p).SetTranslate((i, 0, 0))
    add_camera(stage)
    r = import_stage(stage, path)
    assert len(r.ir["meshes"]) == 1 and len(r.ir["instances"]) == 3
    xs = sorted(np.array(i["transform"])[0, 3] for i in r.ir["instances"])
    assert np.allclose(xs, [0, 1, 2])


def test_stage_metadata_and_y_up_dome(stage_factory):
    stage, path = stage_factory(up="Y")
    UsdGeom.SetStageMetersPerUnit(stage, 0.01)
    UsdLux.DomeLight.Define(stage, "/Dome")
    add_camera(stage)
    r = import_stage(stage, path)
    assert r.stats["meters_per_unit"] == 0.01 and r.stats["up_axis"] == "Y"
    t = np.array(r.ir["environment"]["transform"])
    assert np.allclose(t[:3, :3] @ [0, 0, 1], [0, 1, 0])  # environment +Z is world +Y


def _nd_surface(stage, path, node_id, inputs, port="bsdf"):
    """A Material over ND_surface fed by one pbrlib node, the way Blender's exporter writes it."""
    mat = UsdShade.Material.Define(stage, path)
    surf = UsdShade.Shader.Define(stage, f"{path}/surface")
    surf.CreateIdAttr("ND_surface")
    g = UsdShade.NodeGraph.Define(stage, f"{path}/NodeGraphs")
    n = UsdShade.Shader.Define(stage, f"{path}/NodeGraphs/n")
    n.CreateIdAttr(node_id)
    for k, (tn, v) in inputs.items():
        n.CreateInput(k, tn).Set(v)
    n.CreateOutput("out", Sdf.ValueTypeNames.Token)
    g.CreateOutput("n_out", Sdf.ValueTypeNames.Token).ConnectToSource(n.ConnectableAPI(), "out")
    surf.CreateInput(port, Sdf.ValueTypeNames.Token).ConnectToSource(g.ConnectableAPI(), "n_out")
    surf.CreateOutput("surface", Sdf.ValueTypeNames.Token)
    mat.CreateSurfaceOutput("mtlx").ConnectToSource(surf.ConnectableAPI(), "surface")
    return mat, n


T = Sdf.ValueTypeNames


@pytest.mark.parametrize("node_id, inputs, port, expect", [
    ("ND_oren_nayar_diffuse_bsdf", {"color": (T.Color3f, (0.8, 0.5, 0.2)),
                                    "roughness": (T.Float, 0.0)}, "bsdf",
     {"type": "diffuse", "color": [0.8, 0.5, 0.2]}),
    ("ND_conductor_bsdf", {"roughness": (T.Float2, (0.2, 0.2)),
                           "ior": (T.Color3f, (0.2, 0.2, 0.2)),
                           "extinction": (T.Color3f, (3.0, 3.0, 3.0))}, "bsdf",
     {"type": "glossy", "color": [(0.8 ** 2 + 9) / (1.2 ** 2 + 9)] * 3, "roughness": 0.2}),
    ("ND_dielectric_bsdf", {"ior": (T.Float, 1.45), "roughness": (T.Float2, (0.1, 0.1)),
                            "scatter_mode": (T.String, "RT"),
                            "tint": (T.Color3f, (1.0, 0.9, 0.8))}, "bsdf",
     {"type": "dielectric", "ior": 1.45, "roughness": 0.1, "color": [1.0, 0.9, 0.8]}),
    ("ND_uniform_edf", {"color": (T.Color3f, (6.0, 5.0, 4.0))}, "edf",
     {"type": "emission", "color": [6.0, 5.0, 4.0], "strength": 1.0}),
])
def test_mtlx_surface_over_one_pbrlib_node(stage_factory, node_id, inputs, port, expect):
    stage, path = stage_factory()
    m = quad(stage)
    mat, _ = _nd_surface(stage, "/Mat/N", node_id, inputs, port)
    UsdShade.MaterialBindingAPI.Apply(m.GetPrim()).Bind(mat)
    add_camera(stage)
    r = import_stage(stage, path)
    got = r.ir["materials"][0]
    for k, v in expect.items():
        assert got[k] == (pytest.approx(v, rel=1e-5) if not isinstance(v, str) else v), (k, got)
    msgs = r.diagnostics.messages()
    assert not [w for w in msgs if "unsupported" in w or "not supported" in w], msgs
    # An emissive surface lights the stage.
    assert any("no supported lights" in w for w in msgs) == (port != "edf"), msgs


def test_mtlx_surface_unsupported_bsdf_names_the_node(stage_factory):
    stage, path = stage_factory()
    m = quad(stage)
    mat, _ = _nd_surface(stage, "/Mat/S", "ND_sheen_bsdf", {})
    UsdShade.MaterialBindingAPI.Apply(m.GetPrim()).Bind(mat)
    add_camera(stage)
    r = import_stage(stage, path)
    assert r.ir["materials"][0]["type"] == "diffuse"
    assert [w for w in r.diagnostics.messages() if "/Mat/S/NodeGraphs/n" in w and "ND_sheen_bsdf" in w]


def _emissive_reader_material(stage, path, reader_id, varname, out_type):
    """A graph of a primvar reader into an emission colour (MaterialX surface over a
    UsdPrimvarReader), so that a render shows the primvar's value directly."""
    mat = UsdShade.Material.Define(stage, path)
    rd = UsdShade.Shader.Define(stage, path + "/Reader")
    rd.CreateIdAttr(reader_id)
    rd.CreateInput("varname", Sdf.ValueTypeNames.String).Set(varname)
    rd.CreateOutput("result", out_type)
    sh = UsdShade.Shader.Define(stage, path + "/Preview")
    sh.CreateIdAttr("UsdPreviewSurface")
    sh.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).Set((0, 0, 0))
    sh.CreateInput("emissiveColor", Sdf.ValueTypeNames.Color3f).ConnectToSource(
        rd.ConnectableAPI(), "result")
    mat.CreateSurfaceOutput().ConnectToSource(sh.ConnectableAPI(), "surface")
    return mat


@pytest.mark.parametrize("interp", ["vertex", "faceVarying", "uniform"])
def test_a_primvar_reader_reads_the_mesh_primvar_per_vertex(stage_factory, interp):
    stage, path = stage_factory()
    pts = [(-1, -1, 0), (0, -1, 0), (0, 1, 0), (-1, 1, 0), (1, -1, 0), (1, 1, 0)]
    m = add_mesh(stage, "/M", pts, [4, 4], [0, 1, 2, 3, 1, 4, 5, 2])
    pv = UsdGeom.PrimvarsAPI(m).CreatePrimvar("paint", Sdf.ValueTypeNames.Color3fArray, interp)
    red, blue = (1, 0, 0), (0, 0, 1)
    pv.Set({"vertex": [red, red, red, red, blue, blue],
            "faceVarying": [red] * 4 + [blue] * 4,
            "uniform": [red, blue]}[interp])
    mat = _emissive_reader_material(stage, "/Mat/Paint", "UsdPrimvarReader_float3", "paint",
                                    Sdf.ValueTypeNames.Float3)
    UsdShade.MaterialBindingAPI.Apply(m.GetPrim()).Bind(mat)
    add_camera(stage)
    r = import_stage(stage, path)
    assert not [w for w in r.diagnostics.messages() if "paint" in w], r.diagnostics.messages()
    mesh = r.ir["meshes"][0]
    a = mesh["attributes"]["paint"]
    assert a.shape == (len(mesh["positions"]), 4)
    # The left square's corners read red, the right one's blue (shared edge points split or
    # blended as the interpolation says).
    left = mesh["positions"][:, 0] < -0.5
    right = mesh["positions"][:, 0] > 0.5
    assert np.allclose(a[left], [1, 0, 0, 1]) and np.allclose(a[right], [0, 0, 1, 1])
    out = photonmap.render(photonmap.Scene.from_dict(r.ir), spp=4, seed=1)
    img = out["combined"][..., :3]
    w = img.shape[1]
    # Left of the image is the red square, right the blue one (the camera looks down -z).
    row = img[img.shape[0] // 2]
    assert row[w // 4, 0] > 0.9 and row[w // 4, 2] < 1e-3
    if interp == "vertex":  # the shared middle points are red: the right square blends
        r, b = row[w // 2:int(0.8 * w), 0], row[w // 2:int(0.8 * w), 2]
        assert np.allclose(r + b, 1.0, atol=0.02) and np.all(np.diff(b) >= -0.02) and b[-1] > 0.6
    else:
        assert row[3 * w // 4, 2] > 0.9 and row[3 * w // 4, 0] < 1e-3


def test_per_vertex_displayColor_without_a_material_is_read_per_vertex(stage_factory):
    stage, path = stage_factory()
    m = quad(stage)
    pv = UsdGeom.PrimvarsAPI(m).CreatePrimvar("displayColor", Sdf.ValueTypeNames.Color3fArray,
                                             "vertex")
    pv.Set([(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1)])
    add_camera(stage)
    r = import_stage(stage, path)
    (mat,) = r.ir["materials"]
    assert mat["type"] == "graph" and mat["nodes"][0]["params"]["name"] == "displayColor"
    a = r.ir["meshes"][0]["attributes"]["displayColor"]
    i = int(np.argmin(np.linalg.norm(r.ir["meshes"][0]["positions"] - [1, 1, 0], axis=1)))
    assert np.allclose(a[i], [0, 0, 1, 1])
    photonmap.Scene.from_dict(r.ir)
