"""Lights -> IR lights, in Blender's units (watts; sun strength in W/m^2), as Cycles reads
them: an area light of power P and area A has radiance P/(pi A), a point or spot light of
power P intensity P/(4 pi), a point light of radius r is a sphere of radiance P/(4 pi^2 r^2)."""

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
        warn(f"light '{name}': colour temperature is not supported; uses the colour")
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
    if t == "POINT":
        return {"type": "point", "name": name, "position": pos, "power": power, "color": color,
                "radius": float(light.shadow_soft_size)}
    if t == "SPOT":
        return {"type": "spot", "name": name, "position": pos, "direction": direction,
                "power": power, "color": color, "cone_angle": float(light.spot_size),
                "blend": float(light.spot_blend), "radius": float(light.shadow_soft_size)}
    if t == "AREA":
        rt, sx, sy = _decompose(matrix_world)
        w = float(light.size) * sx
        h = float(light.size_y if light.shape in {"RECTANGLE", "ELLIPSE"} else light.size) * sy
        if abs(getattr(light, "spread", math.pi) - math.pi) > 1e-4:
            warn(f"light '{name}': spread is not supported; emits into the full hemisphere")
        if light.shape in {"SQUARE", "RECTANGLE"}:
            return {"type": "rect", "name": name, "transform": matrix_rows(rt), "width": w,
                    "height": h, "power": power, "color": color}
        if light.shape == "ELLIPSE" and abs(w - h) > 1e-6 * max(w, h):
            warn(f"light '{name}': an ellipse becomes a disk of the same area")
        return {"type": "disk", "name": name, "transform": matrix_rows(rt),
                "radius": 0.5 * math.sqrt(w * h), "power": power, "color": color}
    warn(f"light '{name}': type {t} is not supported; skipped")
    return None
