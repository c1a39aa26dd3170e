"""What Blender 5.0.1's USD exporter changes in a corpus scene by a known factor, and the Cycles
reference corrected by it (needs usd-core; no bpy).

Two of the exporter's bugs change the light of a whole scene by a factor that the importer,
following the UsdLux spec, deliberately carries into the render:

- every light it writes has ``enableColorTemperature = 1`` while the Blender light uses no
  temperature; ``colorTemperature`` is left unauthored, so UsdLux tints the light by the
  blackbody colour of its 6500 K default, normalised to luminance 1: about
  (1.043, 0.984, 1.035). Luminance is kept; the colour is not;
- a sun of strength S (the irradiance, W/m^2) is written as a DistantLight of intensity S/4,
  with ``normalize``: per UsdLux an irradiance of S/4. (Its angle A is written as A/2, which
  no factor undoes; the importer doubles it back for Blender 5.0's stages.)

Light transport is linear in the emitters, so when every emitter of a stage is a light whose
change is the same per-channel factor f, the render of the stage is f times the render of the
scene as Blender has it, exactly: the USD comparison compares with the reference times f, and
still sees everything else (a wrong factor, a wrong shape, a wrong material) as the add-on
comparison does. f is computed from the stage with UsdLux's own blackbody function, never from
the importer's IR, so an importer that dropped the tint or misread the intensity still fails.
A stage whose emitters would need different factors (lights and emissive surfaces or a dome
together) gets no correction: ``factor`` says why.
"""

from __future__ import annotations

import numpy as np

#: UsdLux's default colorTemperature (K).
DEFAULT_TEMPERATURE = 6500.0
#: Blender writes a sun of strength S as intensity S/4.
SUN_INTENSITY = 0.25

_LIGHTS = ("RectLight", "DiskLight", "SphereLight", "CylinderLight", "DistantLight",
           "DomeLight", "DomeLight_1")


def _value(prim, name, default):
    a = prim.GetAttribute(f"inputs:{name}")
    if a and a.HasAuthoredValue():
        v = a.Get()
        if v is not None:
            return v
    return default


def _emissive_surfaces(stage) -> list[str]:
    """Shaders with a non-zero emission (OpenPBR ``emission_luminance`` or UsdPreviewSurface
    ``emissiveColor``)."""
    out = []
    for prim in stage.Traverse():
        if prim.GetTypeName() != "Shader":
            continue
        lum = _value(prim, "emission_luminance", 0.0)
        col = _value(prim, "emissiveColor", (0.0, 0.0, 0.0))
        if float(lum) > 0 or any(float(c) > 0 for c in col):
            out.append(str(prim.GetPath()))
    return out


def factor(path: str) -> tuple[np.ndarray | None, str]:
    """(per-channel factor, explanation) by which the stage at ``path`` renders brighter than
    the Blender scene it was exported from, from the exporter's known bugs; (None, why) when
    no single factor holds. A stage that none of the bugs touch has factor (1, 1, 1)."""
    from pxr import Usd, UsdLux

    stage = Usd.Stage.Open(path)
    blender = (stage.GetRootLayer().documentation or "").startswith("Blender")
    factors, why = [], []
    for prim in stage.Traverse():
        t = prim.GetTypeName()
        if t not in _LIGHTS:
            continue
        f = np.ones(3)
        parts = []
        if bool(_value(prim, "enableColorTemperature", False)):
            k = float(_value(prim, "colorTemperature", DEFAULT_TEMPERATURE))
            tint = np.array(UsdLux.BlackbodyTemperatureAsRgb(k), dtype=np.float64)
            f = f * tint
            parts.append(f"colour temperature {k:g} K enabled: tint "
                         f"({tint[0]:.3f}, {tint[1]:.3f}, {tint[2]:.3f})")
        if t == "DistantLight" and blender:
            f = f * SUN_INTENSITY
            parts.append("sun strength S written as intensity S/4")
        factors.append(f)
        why.append(f"{prim.GetPath()}: " + ("; ".join(parts) or "unchanged"))
    emissive = _emissive_surfaces(stage)
    if not factors and not emissive:
        return None, "no emitters"
    if emissive:
        factors.extend([np.ones(3)] * len(emissive))
        why.extend(f"{p}: emissive surface, unchanged" for p in emissive)
    if any(not np.allclose(f, factors[0], rtol=1e-6) for f in factors):
        return None, "emitters changed by different factors: " + "; ".join(why)
    return factors[0], "; ".join(why)


def corrected(path: str, ref: tuple) -> tuple[tuple, np.ndarray, str]:
    """The reference ``(r1, r2)`` times the stage's factor (unchanged when there is none), the
    factor (ones when none) and its explanation."""
    f, why = factor(path)
    if f is None:
        return ref, np.ones(3), f"no correction ({why})"
    if np.allclose(f, 1.0):
        return ref, f, why
    return tuple(np.asarray(r, dtype=np.float64) * f for r in ref), f, why
