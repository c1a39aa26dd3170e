"""Camera -> IR camera, and the pixel window of the render (resolution %, render border).

The IR camera is always written with an explicit ``fov`` across the image width and a shift,
computed here from Blender's lens, sensor size and fit, so that a render border can be
rendered alone: the border's window of the image plane is a camera of its own.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from mathutils import Matrix, Vector

from .mesh import matrix_rows


@dataclass
class Window:
    """Full image size and the rendered region (x0, y0 from the bottom-left, as Blender)."""

    full_w: int
    full_h: int
    x0: int
    y0: int
    w: int
    h: int


def render_window(scene) -> Window:
    r = scene.render
    pct = r.resolution_percentage / 100.0
    W = max(1, int(r.resolution_x * pct))
    H = max(1, int(r.resolution_y * pct))
    if r.use_border:
        x0 = int(round(r.border_min_x * W))
        x1 = int(round(r.border_max_x * W))
        y0 = int(round(r.border_min_y * H))
        y1 = int(round(r.border_max_y * H))
        if x1 > x0 and y1 > y0:
            return Window(W, H, x0, y0, x1 - x0, y1 - y0)
    return Window(W, H, 0, 0, W, H)


def image_plane(lens, sensor_w, sensor_h, fit, shift, W, H):
    """Half extents (hx, hy) and centre (cx, cy) of the image plane at distance 1, as Blender's
    BKE_camera_params_compute_viewplane: the sensor spans the fit axis, shift is in units of
    that side."""
    if fit == "AUTO":
        horizontal, sensor = W >= H, sensor_w
    elif fit == "HORIZONTAL":
        horizontal, sensor = True, sensor_w
    else:
        horizontal, sensor = False, sensor_h
    fit_half = 0.5 * sensor / lens
    if horizontal:
        hx, hy = fit_half, fit_half * H / W
    else:
        hx, hy = fit_half * W / H, fit_half
    return hx, hy, shift[0] * 2 * fit_half, shift[1] * 2 * fit_half


def camera_ir(matrix_world, lens, sensor_w, sensor_h, fit, shift, near, far, win: Window,
              fstop=None, focus=None, units_per_mm=1e-3) -> dict:
    hx, hy, cx, cy = image_plane(lens, sensor_w, sensor_h, fit, shift, win.full_w, win.full_h)
    # The rendered window of the image plane.
    x0 = cx + hx * (2.0 * win.x0 / win.full_w - 1.0)
    x1 = cx + hx * (2.0 * (win.x0 + win.w) / win.full_w - 1.0)
    y0 = cy + hy * (2.0 * win.y0 / win.full_h - 1.0)
    y1 = cy + hy * (2.0 * (win.y0 + win.h) / win.full_h - 1.0)
    width = x1 - x0
    cam = {
        "transform": matrix_rows(matrix_world),
        "fov": 2.0 * math.atan(0.5 * width),
        "sensor_fit": "horizontal",
        "shift": [0.5 * (x0 + x1) / width, 0.5 * (y0 + y1) / width],
        "focal_length": float(lens),
        "sensor_width": float(sensor_w),
        "sensor_height": float(sensor_h),
        "near": float(near),
        "far": float(far),
        "units_per_mm": float(units_per_mm),
    }
    if fstop and focus:
        cam["fstop"] = float(fstop)
        cam["focus_distance"] = float(focus)
    return cam


def export_camera(scene, cam_obj, win: Window, warn) -> dict:
    units_per_mm = 1e-3 / (scene.unit_settings.scale_length or 1.0)
    if cam_obj is None or cam_obj.type != "CAMERA":
        warn("no scene camera; renders from the world origin looking down -Z")
        return camera_ir(Matrix.Identity(4), 50.0, 36.0, 24.0, "AUTO", (0, 0), 1e-3, 1e30, win)
    c = cam_obj.data
    if c.type != "PERSP":
        warn(f"camera '{cam_obj.name}': {c.type} cameras are not supported; renders perspective")
    fstop = focus = None
    if c.dof.use_dof:
        fstop = c.dof.aperture_fstop
        if c.dof.focus_object is not None:
            m = cam_obj.matrix_world
            fwd = (m.to_3x3() @ Vector((0.0, 0.0, -1.0))).normalized()
            focus = (c.dof.focus_object.matrix_world.translation - m.translation).dot(fwd)
        else:
            focus = c.dof.focus_distance
        focus = max(float(focus), 1e-4)
    return camera_ir(cam_obj.matrix_world, c.lens, c.sensor_width, c.sensor_height, c.sensor_fit,
                     (c.shift_x, c.shift_y), c.clip_start, c.clip_end, win, fstop, focus,
                     units_per_mm)
