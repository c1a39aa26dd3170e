"""Small errors put into a corpus scene's IR, which the comparison must see (no bpy).

Each case renders a scene's IR as read (it must pass) and with one error put in (it must
fail), both at the corpus' "ci" setting and with the same seeds as the corpus tests, so that
what is shown is the power of the comparison CI runs. Both signs of each error are tried.

A catch's margin is how far its most decisive statistic lies beyond its tolerance, as a
fraction of that tolerance: max over the block test (|d_b| / tol_b), the pooled test
(|D| / tol_D) and the pixel test (relMSE / tol) of the ratio, minus 1. A catch by less than
``THIN`` is reported as thin in the table.
"""

from __future__ import annotations

import math

#: A catch whose margin is below this fraction of the tolerance is reported as thin.
THIN = 0.2
#: The table's rows as the cases run (printed at the end of the session by the conftest).
TABLE: list[str] = []


def _scale_lights(f: float):
    def modify(ir):
        for light in ir["lights"]:
            key = "irradiance" if light["type"] == "distant" else "power"
            light[key] = _scaled(light[key], f)
        return ir
    return modify


def _scaled(v, f):
    return [f * x for x in v] if isinstance(v, (list, tuple)) else f * v


def _scale_colours(f: float):
    """Every surface's albedo (diffuse colour or Principled base colour) times ``f``."""
    def modify(ir):
        for m in ir["materials"]:
            for key in ("base_color", "color"):
                if key in m and isinstance(m[key], (list, tuple)):
                    m[key] = [min(1.0, f * c) for c in m[key]]
        return ir
    return modify


def _turn_spots(deg: float):
    """Every spot turned by ``deg`` about the x axis."""
    a = math.radians(deg)

    def modify(ir):
        for light in ir["lights"]:
            if light["type"] == "spot":
                x, y, z = light["direction"]
                light["direction"] = [x, y * math.cos(a) - z * math.sin(a),
                                      y * math.sin(a) + z * math.cos(a)]
        return ir
    return modify


def _scale_light_radius(f: float):
    """Every light's radius (sphere, spot and point lights) times ``f``."""
    def modify(ir):
        for light in ir["lights"]:
            if light.get("radius"):
                light["radius"] *= f
        return ir
    return modify


def _two_sided(ir):
    for light in ir["lights"]:
        if light["type"] in ("rect", "disk"):
            light["two_sided"] = True
    return ir


def _lambert(ir):
    for i, m in enumerate(ir["materials"]):
        if m["type"] == "principled":
            ir["materials"][i] = {"type": "diffuse", "name": m.get("name", ""),
                                  "color": m["base_color"]}
    return ir


def _subsurface_dropped(ir):
    for m in ir["materials"]:
        m.pop("subsurface", None)
    return ir


#: case -> (scene, the error put in). Every case runs at "ci". A subsurface radius 10% off is
#: not among them: at "ci" neither sss_jade nor sss_backlit shows it (largest statistic 0.5-0.8
#: of its tolerance, as without it); those scenes' images depend weakly on the radius.
CASES = {
    "light_2pct_brighter": ("room_empty", _scale_lights(1.02)),
    "light_2pct_dimmer": ("room_empty", _scale_lights(0.98)),
    "colour_2pct_lighter": ("room_empty", _scale_colours(1.02)),
    "colour_2pct_darker": ("room_empty", _scale_colours(0.98)),
    "spot_turned_5deg_up": ("spot_blend", _turn_spots(5.0)),
    "spot_turned_5deg_down": ("spot_blend", _turn_spots(-5.0)),
    "light_radius_10pct_larger": ("spot_radius", _scale_light_radius(1.1)),
    "light_radius_10pct_smaller": ("spot_radius", _scale_light_radius(0.9)),
    "subsurface_light_2pct_brighter": ("sss_jade", _scale_lights(1.02)),
    "subsurface_light_2pct_dimmer": ("sss_jade", _scale_lights(0.98)),
    "subsurface_as_diffuse": ("sss_jade", _subsurface_dropped),
    "area_two_sided": ("room_empty", _two_sided),
    "principled_as_lambert": ("mat_default", _lambert),
}


def ratios(res) -> dict:
    """Each statistic of a comparison as a fraction of its tolerance (above 1: it fails)."""
    block = max((abs(b.dev) / b.tol for b in res.all_blocks), default=0.0)
    pooled = abs(res.pooled) / res.pooled_tol if res.pooled_tol > 0 else 0.0
    pixel = res.relmse / res.relmse_tol if res.relmse_tol > 0 else 0.0
    return {"block": block, "pooled": pooled, "pixel": pixel}


def margin(res) -> tuple[float, str]:
    """The catch's margin (largest ratio minus 1) and the statistic that gives it."""
    r = ratios(res)
    which = max(r, key=r.get)
    return r[which] - 1.0, which


def row(case: str, scene: str, control, res) -> str:
    """A line of the sensitivity table."""
    m, which = margin(res)
    c = ratios(control)
    r = ratios(res)
    verdict = "MISSED" if res.passed else ("THIN" if m < THIN else "caught")
    return (f"{case:32s} {scene:12s} {verdict:6s} margin {100 * m:+7.1f}% ({which:6s})  "
            f"block {r['block']:5.2f} pooled {r['pooled']:5.2f} pixel {r['pixel']:5.2f}"
            f"  | as read: block {c['block']:4.2f} pooled {c['pooled']:4.2f} "
            f"pixel {c['pixel']:4.2f}")


HEADER = (f"{'case':32s} {'scene':12s} verdict margin (statistic)   ratios to tolerance "
          f"with the error | without")
