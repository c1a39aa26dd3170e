"""UsdGeom.Camera -> IR camera. Focal length and apertures are in tenths of a scene unit
(the UsdGeom convention), so the IR's `units_per_mm` is 0.1; clipping range, fStop,
focusDistance and aperture offsets (as lens shift) are carried over."""

from __future__ import annotations

import math

import numpy as np
from pxr import Gf, Usd, UsdGeom

from .xform import ir_matrix, split_scale, to_numpy


def find_camera(stage, path, diag):
    if path:
        prim = stage.GetPrimAtPath(path)
        if not prim or not prim.IsValid():
            raise diag.error(path, "--camera: no such prim")
        if not prim.IsA(UsdGeom.Camera):
            raise diag.error(path, f"--camera: prim is a `{prim.GetTypeName()}`, not a Camera")
        return prim
    for prim in stage.Traverse():
        if prim.IsA(UsdGeom.Camera):
            return prim
    return None


def read_camera(prim, xcache, time, diag, width=None):
    cam = UsdGeom.Camera(prim)
    g = cam.GetCamera(time)
    if g.projection != Gf.Camera.Perspective:
        diag.warn(prim, "orthographic cameras are not supported; rendered in perspective")
    world = to_numpy(xcache.GetLocalToWorldTransform(prim))
    rigid, _ = split_scale(world)
    ha, va = float(g.horizontalAperture), float(g.verticalAperture)
    f = float(g.focalLength)
    for n, v in (("focalLength", f), ("horizontalAperture", ha), ("verticalAperture", va)):
        if not (math.isfinite(v) and v > 0):
            raise diag.error(prim, f"{n} must be > 0, got {v}")
    near, far = g.clippingRange.min, g.clippingRange.max
    w = int(width or 512)
    h = max(1, int(round(w * va / ha)))
    c = {
        "transform": ir_matrix(rigid),
        "focal_length": f,
        "sensor_width": ha,
        "sensor_height": va,
        "sensor_fit": "horizontal",
        "shift": [float(g.horizontalApertureOffset) / ha, float(g.verticalApertureOffset) / ha],
        "near": float(max(near, 1e-6)),
        "far": float(max(far, near * 1.0001 + 1e-6)),
        "units_per_mm": 0.1,
    }
    if g.fStop > 0:
        c["fstop"] = float(g.fStop)
        c["focus_distance"] = float(g.focusDistance) if g.focusDistance > 0 else 10.0
    return c, {"width": w, "height": h}


def default_camera(stage, time, purposes, up_axis, diag):
    """A view framing the stage bounds (documented default when the stage has no camera)."""
    cache = UsdGeom.BBoxCache(time, ["default"] + list(purposes), useExtentsHint=False)
    box = cache.ComputeWorldBound(stage.GetPseudoRoot()).ComputeAlignedRange()
    if box.IsEmpty():
        lo, hi = np.array([-1.0, -1, -1]), np.array([1.0, 1, 1])
    else:
        lo, hi = np.array(box.GetMin()), np.array(box.GetMax())
    center = (lo + hi) / 2
    radius = max(float(np.linalg.norm(hi - lo)) / 2, 1e-3)
    fov = math.radians(40)
    dist = radius / math.sin(fov / 2)
    up = np.array([0, 0, 1.0]) if up_axis == "Z" else np.array([0, 1.0, 0])
    back = np.array([0, -1.0, 0.35]) if up_axis == "Z" else np.array([0, 0.35, 1.0])
    back /= np.linalg.norm(back)
    eye = center + back * dist
    z = back
    x = np.cross(up, z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = x, y, z, eye
    diag.warn(None, "the stage has no camera: a view framing the stage bounds is used")
    return {"transform": ir_matrix(m), "fov": fov, "near": dist * 1e-4, "far": dist * 10}, {"width": 512, "height": 512}
