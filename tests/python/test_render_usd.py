"""USD stages rendered against equivalent JSON scenes; the CLI and the bad-input corpus."""
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest
from conftest import ROOT, SCENES, add_camera, add_mesh, import_stage, quad
from pxr import Gf, Sdf, Usd, UsdGeom, UsdLux

import photonmap
import usd_delegate


def _usd_matrix(ir_rows):
    return Gf.Matrix4d(np.array(ir_rows, dtype=np.float64).T.tolist())


def write_cornell_usda(path, desc):
    stage = Usd.Stage.CreateNew(path)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    for m in desc["meshes"]:
        mat = desc["materials"][m["material"]]
        mesh = UsdGeom.Mesh.Define(stage, "/" + m["name"])
        mesh.CreatePointsAttr([Gf.Vec3f(*p) for p in m["positions"]])
        mesh.CreateFaceVertexCountsAttr([4])
        mesh.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
        mesh.CreateNormalsAttr([Gf.Vec3f(*n) for n in m["normals"]])
        mesh.SetNormalsInterpolation("vertex")
        mesh.CreateSubdivisionSchemeAttr("none")
        mesh.CreateDisplayColorPrimvar().Set([Gf.Vec3f(*mat["color"])])
    for l in desc["lights"]:
        L = UsdLux.RectLight.Define(stage, "/" + l["name"])
        L.CreateWidthAttr(l["width"])
        L.CreateHeightAttr(l["height"])
        L.CreateNormalizeAttr(True)
        L.CreateIntensityAttr(l["power"] / math.pi)
        L.AddTransformOp().Set(_usd_matrix(l["transform"]))
    cam = UsdGeom.Camera.Define(stage, "/Camera")
    cam.CreateFocalLengthAttr(50.0)
    ap = 2 * 50.0 * math.tan(desc["camera"]["fov"] / 2)
    cam.CreateHorizontalApertureAttr(ap)
    cam.CreateVerticalApertureAttr(ap)
    cam.AddTransformOp().Set(_usd_matrix(desc["camera"]["transform"]))
    stage.GetRootLayer().Save()


def test_usd_cornell_box_is_bit_identical_to_json(tmp_path):
    desc = json.load(open(os.path.join(SCENES, "cornell_diffuse.json")))
    usda = str(tmp_path / "cornell.usda")
    write_cornell_usda(usda, desc)
    r = usd_delegate.load_stage(usda, width=desc["film"]["width"])
    ir = r.ir
    cam = ir["camera"]
    fov = 2 * math.atan(cam["sensor_width"] / (2 * cam["focal_length"]))
    assert fov == pytest.approx(desc["camera"]["fov"], rel=1e-6)
    assert np.allclose(cam["transform"], desc["camera"]["transform"])
    # The lens is compared above; both scenes then see through the same camera description.
    desc["camera"] = cam
    ir["film"] = desc["film"]
    for a, b in zip(ir["meshes"], desc["meshes"]):
        assert np.array_equal(a["positions"], np.array(b["positions"], np.float32))
        assert np.array_equal(a["indices"], np.array(b["indices"], np.uint32))
    assert ir["lights"][0]["power"] == pytest.approx(10.0)
    a = photonmap.render(photonmap.Scene.from_dict(ir), spp=4, seed=7)
    b = photonmap.render(photonmap.Scene.from_dict(desc), spp=4, seed=7)
    for t in ("combined",) + photonmap.TERMS:
        assert np.array_equal(a[t], b[t]), t
    assert a["combined"].mean() > 0.01


FLOOR = {"name": "floor", "positions": [[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0]],
         "indices": [[0, 1, 2], [0, 2, 3]], "material": 0}
TOP = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 1.5], [0, 0, 0, 1]]


def _usd_light_scene(tmp_path, kind, setup):
    path = str(tmp_path / f"{kind}.usda")
    stage = Usd.Stage.CreateNew(path)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    quad(stage, "/floor", size=3.0).CreateDisplayColorPrimvar().Set([Gf.Vec3f(0.5, 0.5, 0.5)])
    L = getattr(UsdLux, kind).Define(stage, "/L")
    setup(L)
    add_camera(stage, z=6.0, focal=35.0)
    stage.GetRootLayer().Save()
    return path


LIGHT_CASES = {
    "RectLight": (lambda L: (L.CreateWidthAttr(0.5), L.CreateHeightAttr(0.4), L.CreateIntensityAttr(40.0),
                             L.AddTranslateOp().Set((0, 0, 1.5))),
                  {"type": "rect", "transform": TOP, "width": 0.5, "height": 0.4, "power": 40 * math.pi * 0.2}),
    "DiskLight": (lambda L: (L.CreateRadiusAttr(0.3), L.CreateIntensityAttr(40.0), L.CreateNormalizeAttr(True),
                             L.AddTranslateOp().Set((0, 0, 1.5))),
                  {"type": "disk", "transform": TOP, "radius": 0.3, "power": 40 * math.pi}),
    "SphereLight": (lambda L: (L.CreateRadiusAttr(0.2), L.CreateIntensityAttr(30.0), L.CreateExposureAttr(1.0),
                               L.AddTranslateOp().Set((0, 0, 1.5))),
                    {"type": "sphere", "position": [0, 0, 1.5], "radius": 0.2, "power": 60 * 4 * math.pi ** 2 * 0.04}),
    "DistantLight": (lambda L: (L.CreateIntensityAttr(2.0),),
                     {"type": "distant", "direction": [0, 0, -1], "irradiance": 2.0, "angle": math.radians(0.53)}),
    "CylinderLight": (lambda L: (L.CreateRadiusAttr(0.1), L.CreateLengthAttr(0.8), L.CreateIntensityAttr(20.0),
                                 L.AddTranslateOp().Set((0, 0, 1.5))),
                      {"type": "sphere", "position": [0, 0, 1.5], "radius": math.sqrt(0.04),
                       "power": 20 * math.pi * (2 * math.pi * 0.1 * 0.8)}),
    "DomeLight": (lambda L: (L.CreateColorAttr((0.3, 0.4, 0.5)),), None),
}


@pytest.mark.parametrize("kind", sorted(LIGHT_CASES))
def test_every_usdlux_light_matches_the_json_scene(tmp_path, kind):
    setup, light = LIGHT_CASES[kind]
    path = _usd_light_scene(tmp_path, kind, setup)
    r = usd_delegate.load_stage(path, width=24)
    desc = {"camera": r.ir["camera"], "film": {"width": 24, "height": 24},
            "materials": [{"type": "diffuse", "color": [0.5, 0.5, 0.5]}], "meshes": [FLOOR], "lights": []}
    if light is None:
        desc["environment"] = {"color": [0.3, 0.4, 0.5]}
    else:
        desc["lights"] = [light]
    ir = r.ir
    ir["film"] = desc["film"]
    a = photonmap.render(ir, spp=16, seed=1)["combined"].mean(axis=(0, 1))
    b = photonmap.render(desc, spp=16, seed=1)["combined"].mean(axis=(0, 1))
    assert b.mean() > 1e-3
    assert np.allclose(a, b, rtol=0.05), (a, b)


def run_cli(*args, cwd=None):
    env = dict(os.environ, RUST_BACKTRACE="0")
    return subprocess.run([sys.executable, "-m", "photonmap.cli", *args], capture_output=True,
                          text=True, cwd=cwd, env=env, timeout=300)


def test_cli_renders_usd_frames_with_stats(tmp_path):
    path = _usd_light_scene(tmp_path, "RectLight", LIGHT_CASES["RectLight"][0])
    stage = Usd.Stage.Open(path)
    L = UsdLux.RectLight(stage.GetPrimAtPath("/L"))
    L.GetIntensityAttr().Set(10.0, 1)
    L.GetIntensityAttr().Set(40.0, 3)
    stage.GetRootLayer().Save()
    out = str(tmp_path / "f.#.exr")
    p = run_cli("render", path, "-o", out, "--frames", "1:3x2", "--width", "16", "--spp", "2",
                "--stats", str(tmp_path / "s.#.json"), "--png", str(tmp_path / "f.#.png"))
    assert p.returncode == 0, p.stderr
    for f in (1, 3):
        assert os.path.exists(tmp_path / f"f.{f:04d}.exr") and os.path.exists(tmp_path / f"f.{f:04d}.png")
    s1 = json.load(open(tmp_path / "s.0001.json"))
    assert s1["import"]["triangles"] == 2 and s1["import"]["time_code"] == 1.0
    assert s1["width"] == 16 and "seconds" in s1
    import OpenImageIO as oiio
    m1 = np.mean(oiio.ImageBuf(str(tmp_path / "f.0001.exr")).get_pixels(oiio.FLOAT)[:, :, :3])
    m3 = np.mean(oiio.ImageBuf(str(tmp_path / "f.0003.exr")).get_pixels(oiio.FLOAT)[:, :, :3])
    assert m3 > 2 * m1


def test_cli_default_scene_and_json(tmp_path):
    p = run_cli("render", "-o", str(tmp_path / "d.exr"), "--width", "32", "--spp", "1", "--quiet")
    assert p.returncode == 0 and p.stderr == "", p.stderr
    p = run_cli("render", os.path.join(SCENES, "cornell_diffuse.json"), "-o", str(tmp_path / "c.exr"), "--spp", "1")
    assert p.returncode == 0 and "wrote" in p.stderr


BAD_USDA = {
    "nan_points": ("def Mesh \"M\" {\n point3f[] points = [(0,0,0),(1,0,0),(nan,1,0)]\n int[] faceVertexCounts = [3]\n int[] faceVertexIndices = [0,1,2]\n}", "/M: points[2] is not finite"),
    "two_vertex_face": ("def Mesh \"M\" {\n point3f[] points = [(0,0,0),(1,0,0),(0,1,0)]\n int[] faceVertexCounts = [3, 2]\n int[] faceVertexIndices = [0,1,2,0,1]\n}", "/M: faceVertexCounts[1] = 2"),
    "index_out_of_range": ("def Mesh \"M\" {\n point3f[] points = [(0,0,0),(1,0,0),(0,1,0)]\n int[] faceVertexCounts = [3]\n int[] faceVertexIndices = [0,1,7]\n}", "/M: faceVertexIndices[2] = 7 out of range"),
    "missing_attributes": ("def Mesh \"M\" {\n point3f[] points = [(0,0,0),(1,0,0),(0,1,0)]\n}", "/M: mesh lacks faceVertexCounts"),
    "bad_counts": ("def Mesh \"M\" {\n point3f[] points = [(0,0,0),(1,0,0),(0,1,0)]\n int[] faceVertexCounts = [4]\n int[] faceVertexIndices = [0,1,2]\n}", "/M: faceVertexCounts sum to 4"),
}


@pytest.mark.parametrize("case", sorted(BAD_USDA))
def test_bad_input_corpus_gives_one_line_errors(tmp_path, case):
    body, expected = BAD_USDA[case]
    path = tmp_path / f"{case}.usda"
    path.write_text("#usda 1.0\n" + body + "\n")
    p = run_cli("render", str(path), "-o", str(tmp_path / "o.exr"), "--spp", "1")
    assert p.returncode == 1, p.stderr
    assert expected in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert p.stderr.strip().splitlines()[0].startswith("photonmap: error:")


def test_truncated_usda_missing_file_and_bad_flag(tmp_path):
    path = tmp_path / "t.usda"
    path.write_text('#usda 1.0\ndef Mesh "M" {\n  point3f[] points = [(0,0,0), (1,')
    p = run_cli("render", str(path), "-o", str(tmp_path / "o.exr"))
    assert p.returncode == 1 and "t.usda" in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert len(p.stderr.strip().splitlines()) <= 5
    p = run_cli("render", str(tmp_path / "nope.usda"), "-o", str(tmp_path / "o.exr"))
    assert p.returncode == 1 and "nope.usda" in p.stderr and "no such file" in p.stderr
    p = run_cli("render", "-o", str(tmp_path / "o.exr"), "--quality", "ultra")
    assert p.returncode == 2 and "ultra" in p.stderr
    p = run_cli("render", "-o", str(tmp_path / "o.exr"), "--spp", "0")
    assert p.returncode == 2 and "--spp" in p.stderr


def test_missing_texture_is_a_warning_and_magenta(tmp_path):
    path = tmp_path / "tex.usda"
    path.write_text('''#usda 1.0
(upAxis = "Z")
def Mesh "M" (prepend apiSchemas = ["MaterialBindingAPI"]) {
  point3f[] points = [(-1,-1,0),(1,-1,0),(1,1,0),(-1,1,0)]
  int[] faceVertexCounts = [4]
  int[] faceVertexIndices = [0,1,2,3]
  uniform token subdivisionScheme = "none"
  rel material:binding = </Mat>
}
def Material "Mat" {
  token outputs:surface.connect = </Mat/P.outputs:surface>
  def Shader "P" {
    uniform token info:id = "UsdPreviewSurface"
    color3f inputs:diffuseColor.connect = </Mat/T.outputs:rgb>
    token outputs:surface
  }
  def Shader "T" {
    uniform token info:id = "UsdUVTexture"
    asset inputs:file = @gone.png@
    float3 outputs:rgb
  }
}
def Camera "C" {
  double3 xformOp:translate = (0, 0, 4)
  uniform token[] xformOpOrder = ["xformOp:translate"]
}
def DistantLight "Sun" {
  float inputs:intensity = 2
}
''')
    out = tmp_path / "o.exr"
    p = run_cli("render", str(path), "-o", str(out), "--width", "8", "--spp", "1")
    assert p.returncode == 0, p.stderr
    assert "/T: texture file not found" in p.stderr and "gone.png" in p.stderr
    import OpenImageIO as oiio
    px = oiio.ImageBuf(str(out)).get_pixels(oiio.FLOAT)[4, 4]
    assert px[0] > 0.1 and px[2] > 0.1 and px[1] < 0.3 * px[0]  # magenta (plus white specular)
    p = run_cli("render", str(path), "-o", str(out), "--width", "8", "--spp", "1", "--strict")
    assert p.returncode == 1 and "--strict" in p.stderr
