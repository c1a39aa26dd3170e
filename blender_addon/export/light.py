"""Lights -> IR lights, in Blender's units (watts; sun strength in W/m^2), as Cycles reads
them: an area light of power P and area A has radiance P/(pi A), a point or spot light of
power P intensity P/(4 pi), a point light of radius r an emitter of radiance P/(4 pi^2 r^2):
a disk facing the shading point with Soft Falloff (Blender's default), else a sphere.

Also carried: Ray Visibility > Camera, Exposure (x 2^exposure), colour Temperature (x the light's `temperature_color`),
Normalize off (the power is then per unit area: x A for area lights, x pi r^2 for point and
spot lights with a radius), area-light Spread and the ellipse's two radii."""

from __future__ import annotations

import math

from mathutils import Matrix, Vector

from .mesh import matrix_rows


def _decompose(m):
    """(rotation+translation rows, scale x, scale y) of a world matrix."""
    loc, rot, scale = m.decompose()
    rt = Matrix.Translation(loc) @ rot.to_matrix().to_4x4()
    return rt, abs(scale.x), abs(scale.y)


def export_light(obj, matrix_world, warn) -> dict | None:
    light = obj.data
    name = obj.name
    power_scale = 2.0 ** float(getattr(light, "exposure", 0.0))
    color = [float(c) for c in light.color[:3]]
    if getattr(light, "use_temperature", False):
        tint = getattr(light, "temperature_color", None)
        if tint is None:
            warn(f"light '{name}': colour temperature needs Blender 4.5 or later; uses the colour")
        else:
            color = [c * float(t) for c, t in zip(color, tint[:3])]
    normalize = bool(getattr(light, "normalize", True))
    # Ray Visibility > Camera (area lights are off by default in Blender 5.0).
    camera_visible = bool(getattr(obj, "visible_camera", True))
    if light.node_tree is not None and getattr(light, "use_nodes", False):
        warn(f"light '{name}': light node trees are not supported; ignored")
    pos = [float(x) for x in matrix_world.translation]
    down = matrix_world.to_3x3() @ Vector((0.0, 0.0, -1.0))
    down.normalize()
    direction = [float(x) for x in down]
    t = light.type
    if t == "SUN":
        return {"type": "distant", "name": name, "direction": direction,
                "irradiance": float(light.energy) * power_scale, "color": color,
                "angle": float(light.angle)}
    power = float(light.energy) * power_scale
    if t in {"POINT", "SPOT"}:
        radius = float(light.shadow_soft_size)
        if not normalize and radius > 0.0:
            power *= math.pi * radius * radius
        d = {"type": "point", "name": name, "position": pos, "power": power, "color": color,
             "radius": radius, "soft_falloff": bool(getattr(light, "use_soft_falloff", True)),
             "camera_visible": camera_visible}
        if t == "SPOT":
            d.update(type="spot", direction=direction, cone_angle=float(light.spot_size),
                     blend=float(light.spot_blend))
        return d
    if t == "AREA":
        rt, sx, sy = _decompose(matrix_world)
        w = float(light.size) * sx
        h = float(light.size_y if light.shape in {"RECTANGLE", "ELLIPSE"} else light.size) * sy
        spread = float(getattr(light, "spread", math.pi))
        if spread <= 0.0:
            warn(f"light '{name}': spread 0 emits nothing in Cycles but a single direction; "
                 f"uses 0.1 degree")
            spread = math.radians(0.1)
        spread = min(spread, math.pi)
        rect = light.shape in {"SQUARE", "RECTANGLE"}
        if not normalize:
            power *= w * h * (1.0 if rect else math.pi / 4.0)
        if rect:
            return {"type": "rect", "name": name, "transform": matrix_rows(rt), "width": w,
                    "height": h, "power": power, "color": color, "spread": spread,
                    "camera_visible": camera_visible}
        return {"type": "disk", "name": name, "transform": matrix_rows(rt), "radius": 0.5 * w,
                "radius_y": 0.5 * h, "power": power, "color": color, "spread": spread,
                "camera_visible": camera_visible}
    warn(f"light '{name}': type {t} is not supported; skipped")
    return None
