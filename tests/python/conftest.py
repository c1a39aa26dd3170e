import json
import math
import os
import sys

import numpy as np
import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCENES = os.path.join(ROOT, "tests", "data", "scenes")

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
