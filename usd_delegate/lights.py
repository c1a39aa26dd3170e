"""UsdLux lights -> IR lights (photonmap units: W for point/spot/area lights, W/m^2 for distant
lights, radiance for the environment).

Radiance L = intensity * 2^exposure * color (* blackbody(colorTemperature) when
enableColorTemperature, normalised to luminance 1); with ``normalize`` it is divided by the
light's world-space area. An IR area light of area A and radiance L has power P = L*pi*A; a
sphere light of radius r has P = L*4*pi^2*r^2. Distant lights: irradiance = intensity *
2^exposure. Inputs are read with or without the ``inputs:`` prefix (old files).

Stages written by Blender (a layer's `doc` or `customLayerData` `creator` "Blender vX.Y.Z",
or `userProperties:blender:*` on the light) are read the way Blender renders the scene, each
correction noted:

- Soft Falloff on point and spot lights with a radius (Blender's default; not written).
- Lights hidden from camera rays (Blender's default; its exporter writes no camera
  visibility), unless the light says otherwise (`camera_visibility_opinion`).
- A sun's `angle` doubled where Blender's exporter is known to write half its Angle (5.0).
  Its intensity, S/4 for a sun of strength S, is read per UsdLux.

| UsdLux | IR |
|---|---|
| RectLight (width x height, emits along -Z) | `rect` |
| DiskLight | `disk` |
| SphereLight | `sphere` (`point` with treatAsPoint); with ShapingAPI cone: `spot` |
| CylinderLight | `sphere` of equal area (approximation, warned) |
| DistantLight (angle, degrees) | `distant` (angle in radians) |
| DomeLight (color, inputs:texture:file lat-long) | `environment` |
"""

from __future__ import annotations

import math
import re

import numpy as np
from pxr import UsdGeom, UsdLux

from .textures import resolve_asset
from .xform import ir_matrix, split_scale


def _get(prim, name, default, time):
    for attr_name in (f"inputs:{name}", name):
        a = prim.GetAttribute(attr_name)
        if a and a.HasAuthoredValue():
            v = a.Get(time)
            if v is not None:
                return v
    return default


def radiance(prim, time, diag):
    """(scalar radiance, rgb tint, normalize) before any area normalisation."""
    intensity = float(_get(prim, "intensity", 1.0, time))
    exposure = float(_get(prim, "exposure", 0.0, time))
    color = np.array(_get(prim, "color", (1.0, 1.0, 1.0), time), dtype=np.float64)
    if not (math.isfinite(intensity) and math.isfinite(exposure) and np.all(np.isfinite(color))):
        raise diag.error(prim, "light intensity, exposure or color is not finite")
    if intensity < 0 or np.any(color < 0):
        raise diag.error(prim, "negative light intensity or color")
    if bool(_get(prim, "enableColorTemperature", False, time)):
        t = float(_get(prim, "colorTemperature", 6500.0, time))
        rgb = np.array(UsdLux.BlackbodyTemperatureAsRgb(t), dtype=np.float64)
        color = color * rgb
        diag.note(prim, f"colour temperature {t:g} K applied (tint {np.round(rgb, 3).tolist()})")
    normalize = bool(_get(prim, "normalize", False, time))
    return intensity * 2.0 ** exposure, color, normalize


def area_power(L: float, area: float, normalize: bool) -> float:
    """IR power of an emitter of world-space area A and radiance L (divided by A when
    normalize is on): P = L pi A, so P = L pi with normalize (for any area, even zero)."""
    return L * math.pi if normalize else L * math.pi * area


def _layer_writer(layer) -> str | None:
    """"Blender v5.0.1" when the layer says Blender wrote it (its `doc`, or the `creator` of
    its customLayerData), else None."""
    creator = layer.customLayerData.get("creator", "") if layer.customLayerData else ""
    for s in (layer.documentation or "", creator if isinstance(creator, str) else ""):
        if s.startswith("Blender"):
            return s.strip()
    return None


def blender_writer(prim) -> str | None:
    """The Blender that wrote the prim: "Blender v5.0.1" from a layer of its prim stack or the
    root layer, "Blender" when only its `userProperties:blender:*` say so; None otherwise."""
    for spec in prim.GetPrimStack():
        w = _layer_writer(spec.layer)
        if w:
            return w
    w = _layer_writer(prim.GetStage().GetRootLayer())
    if w:
        return w
    if any(n.startswith("userProperties:blender:") for n in prim.GetPropertyNames()):
        return "Blender"
    return None


def _blender_authored(prim) -> bool:
    return blender_writer(prim) is not None


def _value_writer(prim, name, time) -> str | None:
    """The Blender that wrote the value of input `name` that is read (the layer of its
    strongest opinion), or None."""
    for attr_name in (f"inputs:{name}", name):
        a = prim.GetAttribute(attr_name)
        if a and a.HasAuthoredValue():
            stack = a.GetPropertyStack(time)
            return _layer_writer(stack[0].layer) if stack else None
    return None


def blender_version(writer: str | None) -> tuple[int, int] | None:
    """(major, minor) of "Blender v5.0.1" (or "Blender 4.2.3 LTS"); None if it has none."""
    m = re.match(r"Blender\s+v?(\d+)\.(\d+)", writer or "")
    return (int(m.group(1)), int(m.group(2))) if m else None


#: Blender versions (major, minor) whose USD exporter writes a sun's `inputs:angle` as half of
#: its Angle (5.0.1: Angle 10 deg written as `float inputs:angle = 5`). Other versions are read
#: per UsdLux (noted).
HALVED_SUN_ANGLE = {(5, 0)}


def _camera_visibility_attrs(prim):
    """The attributes that may say whether camera rays see a light, in the order read: the
    renderer's `primvars:photonmap:camera_visible`, Karma's `karma:light:renderlightgeo`,
    RenderMan's `primvars:ri:attributes:visibility:camera` (primvars inherited down the
    namespace)."""
    primvars = UsdGeom.PrimvarsAPI(prim)
    yield primvars.FindPrimvarWithInheritance("photonmap:camera_visible").GetAttr()
    yield prim.GetAttribute("karma:light:renderlightgeo")
    yield primvars.FindPrimvarWithInheritance("ri:attributes:visibility:camera").GetAttr()


def camera_visibility_opinion(prim, time) -> tuple[bool, str] | None:
    """(visible, the attribute's path) from the first authored camera-visibility opinion (a
    bool or number, non-zero: visible); None when the stage has none for this light."""
    for a in _camera_visibility_attrs(prim):
        if a and a.HasAuthoredValue():
            v = a.Get(time)
            if isinstance(v, (bool, int, float)):
                return bool(v), str(a.GetPath())
    return None


def camera_visible(prim, time, diag) -> bool:
    """Whether camera rays see the light: an authored opinion (`camera_visibility_opinion`)
    decides; without one, Blender's stages hide their lights (as Blender renders them: hidden
    from the camera by default, and its exporter writes no visibility), others show them
    (USD's default)."""
    opinion = camera_visibility_opinion(prim, time)
    if opinion is not None:
        return opinion[0]
    writer = blender_writer(prim)
    if writer is None:
        return True
    diag.note(prim, f"written by {writer}: hidden from the camera, as Blender renders its "
                    f"lights by default (its exporter writes no camera visibility; "
                    f"primvars:photonmap:camera_visible = 1 shows it)")
    return False


def read_light(prim, world: np.ndarray, time, diag, up_axis: str, textures):
    """(kind, IR light dict or environment dict), or None for unsupported lights (warned)."""
    t = prim.GetTypeName()
    name = str(prim.GetPath())
    rigid, scale = split_scale(world)
    pos = [float(v) for v in world[:3, 3]]
    forward = -rigid[:3, 2]
    if t in ("RectLight", "DiskLight", "SphereLight", "CylinderLight", "DistantLight", "DomeLight", "DomeLight_1"):
        L, color, normalize = radiance(prim, time, diag)
    else:
        diag.warn(prim, f"unsupported light type `{t}`; skipped")
        return None
    # Lights at infinity are never seen by camera rays in the IR: no visibility to read.
    at_infinity = t in ("DistantLight", "DomeLight", "DomeLight_1")
    visible = True if at_infinity else camera_visible(prim, time, diag)
    shaping = prim.HasAPI(UsdLux.ShapingAPI) or prim.GetAttribute("inputs:shaping:cone:angle").HasAuthoredValue()
    if shaping and t not in ("SphereLight",):
        diag.warn(prim, "ShapingAPI is supported on sphere lights only; ignored")
    if t == "RectLight":
        w = float(_get(prim, "width", 1.0, time)) * scale[0]
        h = float(_get(prim, "height", 1.0, time)) * scale[1]
        area = w * h
        if _get(prim, "texture:file", None, time):
            diag.warn(prim, "textured rect lights are not supported; the light's colour is used")
        return "light", {"type": "rect", "name": name, "transform": ir_matrix(rigid), "width": w,
                         "height": h, "power": area_power(L, area, normalize), "color": color.tolist(),
                         "camera_visible": visible}
    if t == "DiskLight":
        r = float(_get(prim, "radius", 0.5, time))
        rr = r * math.sqrt(abs(scale[0] * scale[1]))
        if abs(scale[0] - scale[1]) > 1e-4 * max(scale[0], scale[1]):
            diag.warn(prim, "non-uniformly scaled disk light: a disk of equal area is used")
        area = math.pi * rr * rr
        return "light", {"type": "disk", "name": name, "transform": ir_matrix(rigid), "radius": rr,
                         "power": area_power(L, area, normalize), "color": color.tolist(),
                         "camera_visible": visible}
    if t in ("SphereLight", "CylinderLight"):
        s = float(np.mean(scale))
        if np.ptp(scale) > 1e-4 * s:
            diag.warn(prim, "non-uniformly scaled light: the mean scale is used")
        if t == "SphereLight":
            r = float(_get(prim, "radius", 0.5, time)) * s
        else:
            cr = float(_get(prim, "radius", 0.5, time)) * s
            ln = float(_get(prim, "length", 1.0, time)) * s
            r = math.sqrt(cr * ln / 2.0)  # 4 pi R^2 = 2 pi r l
            diag.warn(prim, f"cylinder light approximated by a sphere light of equal area (radius {r:.4g})")
        # P = L 4 pi^2 r^2 = L pi A with A = 4 pi r^2: the same rule as area lights.
        power = area_power(L, 4.0 * math.pi * r * r, normalize)
        treat_as_point = bool(_get(prim, "treatAsPoint", False, time))
        radius = 0.0 if treat_as_point or r <= 0 else r
        # Blender's point and spot lights have Soft Falloff on by default and its exporter
        # does not write the setting: read its stages' sphere lights the way Blender draws them.
        soft = radius > 0.0 and t == "SphereLight" and _blender_authored(prim)
        if soft:
            diag.note(prim, "written by Blender: read with Blender's Soft Falloff (its default; "
                            "the exporter does not write the setting)")
        if shaping and t == "SphereLight":
            angle = float(_get(prim, "shaping:cone:angle", 90.0, time))
            softness = float(_get(prim, "shaping:cone:softness", 0.0, time))
            if _get(prim, "shaping:focus", 0.0, time) or _get(prim, "shaping:ies:file", None, time):
                diag.warn(prim, "shaping focus and IES profiles are not supported; ignored")
            if angle < 90.0:
                return "light", {"type": "spot", "name": name, "position": pos,
                                 "direction": forward.tolist(), "power": power,
                                 "color": color.tolist(), "cone_angle": math.radians(2 * angle),
                                 "blend": min(1.0, max(0.0, softness)), "radius": radius,
                                 "soft_falloff": soft, "camera_visible": visible}
        if radius == 0.0:
            if power == 0.0 and L > 0:
                diag.warn(prim, "point light of zero radius without normalize emits nothing")
            return "light", {"type": "point", "name": name, "position": pos, "power": power,
                             "color": color.tolist(), "camera_visible": visible}
        if soft:
            return "light", {"type": "point", "name": name, "position": pos, "radius": radius,
                             "power": power, "color": color.tolist(), "soft_falloff": True,
                             "camera_visible": visible}
        return "light", {"type": "sphere", "name": name, "position": pos, "radius": radius,
                         "power": power, "color": color.tolist(), "camera_visible": visible}
    if t == "DistantLight":
        angle = float(_get(prim, "angle", 0.53, time))
        writer = blender_writer(prim)
        if writer is not None:
            # The Blender that wrote the angle read (its strongest opinion's layer) decides.
            angle_writer = _value_writer(prim, "angle", time)
            if angle_writer is not None and blender_version(angle_writer) in HALVED_SUN_ANGLE:
                diag.note(prim, f"written by {angle_writer}, whose exporter writes a sun's angle "
                                f"halved: angle {angle:g} deg read as {2 * angle:g} deg (Blender's "
                                f"Angle)")
                angle *= 2.0
            elif angle_writer is not None:
                diag.note(prim, f"written by {angle_writer}: angle {angle:g} deg read per UsdLux "
                                f"(the angular diameter); Blender 5.0's exporter writes half the "
                                f"Angle, this version is not known to")
            diag.note(prim, f"irradiance {L:g} read per UsdLux; Blender's exporter writes a sun of "
                            f"strength S as intensity S/4 (in Blender: strength {4 * L:g})")
        return "light", {"type": "distant", "name": name, "direction": forward.tolist(),
                         "irradiance": L, "color": color.tolist(),
                         "angle": math.radians(max(0.0, angle))}
    # DomeLight: lat-long in the light's frame; our environment maps +Z up.
    env = {"color": color.tolist(), "strength": L}
    up_fix = np.eye(4)
    if up_axis == "Y":  # environment +Z -> world +Y
        up_fix = np.array([[1, 0, 0, 0], [0, 0, 1, 0], [0, -1, 0, 0], [0, 0, 0, 1]], dtype=np.float64)
    env["transform"] = ir_matrix(rigid @ up_fix)
    tex = _get(prim, "texture:file", None, time)
    if tex is not None and (getattr(tex, "path", "") or str(tex)):
        fmt = str(_get(prim, "texture:format", "automatic", time))
        if fmt not in ("automatic", "latlong"):
            diag.warn(prim, f"dome texture format `{fmt}` unsupported; read as lat-long")
        idx = textures.add(prim, resolve_asset(tex, prim), "auto", "repeat")
        if idx is None:
            env["color"] = [1.0, 0.0, 1.0]
        else:
            env["texture"] = idx
    return "environment", env
