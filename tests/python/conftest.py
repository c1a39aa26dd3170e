import json
import math
import os
import sys

import numpy as np
import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCENES = os.path.join(ROOT, "tests", "data", "scenes")
sys.path.append(os.path.join(ROOT, "tests"))

import skip_policy  # noqa: E402


def pytest_configure(config):
    # Skips are listed at the end; on CI one not allowed by tests/skip_policy.py fails the run.
    skip_policy.register(config)


from pxr import Gf, Sdf, Usd, UsdGeom, UsdLux, UsdShade  # noqa: E402

import photonmap  # noqa: E402
import usd_delegate  # noqa: E402


def new_stage(tmp_path, name="s.usda", up="Z"):
    path = str(tmp_path / name)
    stage = Usd.Stage.CreateNew(path)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z if up == "Z" else UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    return stage, path


def add_mesh(stage, path, points, counts, indices, **kw):
    m = UsdGeom.Mesh.Define(stage, path)
    m.CreatePointsAttr([Gf.Vec3f(*p) for p in points])
    m.CreateFaceVertexCountsAttr(list(counts))
    m.CreateFaceVertexIndicesAttr(list(indices))
    m.CreateSubdivisionSchemeAttr(kw.pop("scheme", "none"))
    for k, v in kw.items():
        getattr(m, f"Create{k}Attr")(v)
    return m


def add_camera(stage, path="/Cam", z=4.0, focal=50.0, h_ap=36.0, v_ap=36.0):
    c = UsdGeom.Camera.Define(stage, path)
    c.CreateFocalLengthAttr(focal)
    c.CreateHorizontalApertureAttr(h_ap)
    c.CreateVerticalApertureAttr(v_ap)
    UsdGeom.XformCommonAPI(c).SetTranslate((0, 0, z))
    return c


def import_stage(stage, path, **kw):
    stage.GetRootLayer().Save()
    return usd_delegate.load_stage(path, **kw)


def quad(stage, path="/Floor", size=1.0, z=0.0):
    s = size
    return add_mesh(stage, path, [(-s, -s, z), (s, -s, z), (s, s, z), (-s, s, z)], [4], [0, 1, 2, 3])


@pytest.fixture
def stage_factory(tmp_path):
    def make(name="s.usda", up="Z"):
        return new_stage(tmp_path, name, up)
    return make


def _ir_matrix(rows):
    return Gf.Matrix4d(np.array(rows, dtype=np.float64).T.tolist())


def write_scene_usda(path, desc, camera_x=(0.0,), frame_start=1):
    """A USD stage of a JSON scene IR of triangle meshes, UsdPreviewSurface materials
    (diffuse, mirror; glass as a MaterialX OpenPBR shader with full transmission, since a
    UsdPreviewSurface's opacity is coverage) and rect lights, with the IR's camera moved sideways by
    ``camera_x[i]`` at frame ``frame_start + i`` (a camera-only animation)."""
    stage = Usd.Stage.CreateNew(path)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    mats = []
    for i, m in enumerate(desc["materials"]):
        mat = UsdShade.Material.Define(stage, f"/Materials/m{i}")
        sh = UsdShade.Shader.Define(stage, f"/Materials/m{i}/s")
        sh.CreateIdAttr("UsdPreviewSurface")
        inp = lambda n, t, v: sh.CreateInput(n, t).Set(v)  # noqa: E731
        if m["type"] == "diffuse":
            inp("diffuseColor", Sdf.ValueTypeNames.Color3f, Gf.Vec3f(*m["color"]))
            inp("roughness", Sdf.ValueTypeNames.Float, 1.0)
        elif m["type"] == "mirror":
            inp("diffuseColor", Sdf.ValueTypeNames.Color3f, Gf.Vec3f(*m["color"]))
            inp("metallic", Sdf.ValueTypeNames.Float, 1.0)
            inp("roughness", Sdf.ValueTypeNames.Float, 0.0)
        else:
            sh.GetIdAttr().Set("ND_open_pbr_surface_surfaceshader")
            inp("base_color", Sdf.ValueTypeNames.Color3f, Gf.Vec3f(1, 1, 1))
            inp("transmission_weight", Sdf.ValueTypeNames.Float, 1.0)
            inp("specular_ior", Sdf.ValueTypeNames.Float, m.get("ior", 1.5))
            inp("specular_roughness", Sdf.ValueTypeNames.Float, 0.0)
            sh.CreateOutput("surface", Sdf.ValueTypeNames.Token)
            mat.CreateSurfaceOutput("mtlx").ConnectToSource(sh.ConnectableAPI(), "surface")
            mats.append(mat)
            continue
        mat.CreateSurfaceOutput().ConnectToSource(sh.ConnectableAPI(), "surface")
        mats.append(mat)
    for m in desc["meshes"]:
        mesh = UsdGeom.Mesh.Define(stage, "/" + m["name"])
        mesh.CreatePointsAttr([Gf.Vec3f(*p) for p in m["positions"]])
        mesh.CreateFaceVertexCountsAttr([3] * len(m["indices"]))
        mesh.CreateFaceVertexIndicesAttr([int(i) for t in m["indices"] for i in t])
        if m.get("normals"):
            mesh.CreateNormalsAttr([Gf.Vec3f(*n) for n in m["normals"]])
            mesh.SetNormalsInterpolation("vertex")
        mesh.CreateSubdivisionSchemeAttr("none")
        if "transform" in m:
            mesh.AddTransformOp().Set(_ir_matrix(m["transform"]))
        UsdShade.MaterialBindingAPI.Apply(mesh.GetPrim()).Bind(mats[m["material"]])
    for l in desc["lights"]:
        L = UsdLux.RectLight.Define(stage, "/" + l["name"])
        L.CreateWidthAttr(l["width"])
        L.CreateHeightAttr(l["height"])
        L.CreateNormalizeAttr(True)
        L.CreateIntensityAttr(l["power"] / math.pi)
        L.AddTransformOp().Set(_ir_matrix(l["transform"]))
    cam = UsdGeom.Camera.Define(stage, "/Camera")
    cam.CreateFocalLengthAttr(50.0)
    ap = 2 * 50.0 * math.tan(desc["camera"]["fov"] / 2)
    cam.CreateHorizontalApertureAttr(ap)
    cam.CreateVerticalApertureAttr(ap)
    op = cam.AddTransformOp()
    base = np.array(desc["camera"]["transform"], dtype=np.float64)
    for i, dx in enumerate(camera_x):
        t = base.copy()
        t[0][3] += dx
        op.Set(_ir_matrix(t), frame_start + i)
    stage.SetStartTimeCode(frame_start)
    stage.SetEndTimeCode(frame_start + len(camera_x) - 1)
    stage.GetRootLayer().Save()
    return path


def pytest_terminal_summary(terminalreporter):
    """The corpus sensitivity table (test_corpus_sensitivity.py), when its cases ran."""
    mod = sys.modules.get("corpus.sensitivity")
    if mod is not None and mod.TABLE:
        terminalreporter.section("corpus sensitivity at 'ci': margins beyond the tolerance")
        terminalreporter.line(mod.HEADER)
        for line in mod.TABLE:
            terminalreporter.line(line)
