"""Corpus scenes known to fail their comparison, per path, with the reason (no bpy).

The tests mark these ``xfail(strict=True)``: the suite stays green while they fail and turns
red when they start to pass, so that the entry is removed with the fix. Figures for each are
in the test's message (compare.py) and in scripts/corpus_compare.py's table.
"""

from __future__ import annotations

# Differences in the core, by scene, with what the "ci" comparison measured (both paths unless
# named). Each is a real difference from Cycles, left for a fix in the core.
EMISSIVE_SPHERE = ("core: one floor block near the glowing sphere, (12,14), is high through the "
                   "add-on (+27%, +7.1 sigma); pooled within 0.4%; the USD path passes")
METAL_ROUGH_USD = ("core: one block at the right wall's foot (19,11) -4.3% (-7.1 sigma, tolerance "
                   "4.2%); pooled -0.4%; the add-on path passes")
# Single blocks a few percent beyond tolerance, each deviating in the same direction before
# gather hits took their direct light by next-event estimation (then within the tolerance on
# that render's noise): the ceiling's top row by the walls, dark corners lit only indirectly.
CEILING_EDGE = "core: the ceiling's top-row block {}, by the wall; {} before, within its noise"
CUBE_FOOT = ("core: the floor block (6,10) by the cube's foot is 4-5% dark in the default room, "
             "at the tolerance's edge: -4.75% (-6.7 sigma, tolerance 4.71%) here; -4.35% "
             "(tolerance 4.57%) in light_exposure through the add-on")
CUBE_FOOT_EXPOSURE = ("core: the floor block (6,10) by the cube's foot is 5% dark in the default "
                      "room at exposure 1, at the tolerance's edge: -5.48% (-6.3 sigma, tolerance "
                      "5.38%); the add-on path passes")
POINT_WALL_BLOCK = ("core: the right wall's block (17,4) by the ceiling is 7-8% bright in both "
                    "point_r01 scenes, at the tolerance's edge: +7.95% (+5.6 sigma, tolerance "
                    "7.90%) here, +7.03% (tolerance 7.88%) with soft falloff")
SPOT_DARK_FLOOR = ("core: the floor the spot's pool lights only indirectly is dark at the image's "
                   "bottom edge: {}; at medium with 300,000 photons still -7.8% (-6.0 sigma)")
# A spot whose sphere (radius 0.2) pierces the ceiling. The left wall's foot at the image's edge
# is dark, a concave corner lit only indirectly (not yet told apart: the cache's dark bias or
# the global map's density there); the rest of the image is within its noise.
SPOT_RADIUS_CORNER = ("core: the left wall's foot at the image's edge, blocks (0,11) -24.3% "
                      "(-11.9 sigma) and (0,12) -15.2% (-7.0 sigma); pixel relMSE within the "
                      "noise (0.97 of it)")

# Noise that one pair of seeds understates: the irradiance cache's records differ by seed, and
# their error is shared by every pixel of a block.
EMISSION_CACHE_NOISE = ("noise: block (14,12) -10.0% against a tolerance of 9.98%: seeds 1 and 2 "
                        "both land low there (-10.7%, -9.3%; seeds 3-6: +1.6%, +0.1%, -7.0%, "
                        "+15.8%; the same with 400,000 photons), the irradiance cache's "
                        "seed-to-seed spread; it passes with adaptive sampling off, whose "
                        "lower noise in the neighbouring blocks narrows the tolerance")

# Blender 5.0.1's USD exporter writes something else than the scene has; the USD render then
# differs from Cycles' render of the Blender scene by more than the comparison allows. Each
# names the stage's line (tests/blender/corpus/usd/<scene>.usda).
ELLIPSE = ("exporter: an ellipse area light (0.8 x 0.3) is written as a DiskLight of radius "
           "(0.8 + 0.3) / 4, 'float inputs:radius = 0.275', and its camera visibility (on) is "
           "not written: the importer hides it as Blender does by default, where Cycles shows "
           "the ellipse: block (12,1) -98.1% (-190 sigma), pooled -6.4%")
# Camera visibility (Object > Visibility > Camera) is not written: the light's prim is the same
# as area_hidden's, whose light Blender hides. The importer hides Blender's lights from the
# camera, as Blender does by default; these scenes turn it on, and Cycles shows the light.
CAMERA_VISIBLE = ("exporter: the light's camera visibility (on here) is not written: "
                  "'def {}' has no visibility attribute; the importer hides Blender's lights "
                  "from the camera (its default), so the light is missing from frame: {}")
SPREAD = ("exporter: an area light's Spread is not written: the stage's light is area_spread180's "
          "('float inputs:width = 0.6', 'float inputs:height = 0.6', no shaping:cone:angle), "
          "and the 60 deg light emits into the hemisphere: blocks to -82%, pooled -38%")
HARD_FALLOFF = ("exporter: neither Soft Falloff (off here) nor camera visibility (on here) is "
                "written, only 'float inputs:radius = 0.1': the importer reads Blender's "
                "defaults, Soft Falloff on and the light hidden from the camera, so the sphere "
                "is missing from frame: block (8,2) -90.4% (-308 sigma), pooled -7.5%")
SUN_HALF_ANGLE = ("exporter: the sun's angle is written halved: penumbrae twice as sharp, "
                  "blocks to -34%")

#: scene -> reason, for the add-on path (tests/blender/test_corpus.py).
ADDON: dict[str, str] = {
    "area_disk": CEILING_EDGE.format("(17,0) -6.2% (-7.3 sigma)", "-2.3%"),
    "emission_principled": EMISSIVE_SPHERE,
    "point_r01_hard": POINT_WALL_BLOCK,
    "spot_offaxis": SPOT_DARK_FLOOR.format("block (8,14) -13.3% (-5.3 sigma), -12.5% before"),
}

#: scene -> reason, for the USD path (tests/python/test_corpus_usd.py).
USD: dict[str, str] = {
    "area_disk": CAMERA_VISIBLE.format('DiskLight "Area"', "block (9,2) -99.3% (-436 sigma), "
                                                          "pooled -19.9%"),
    "area_ellipse": ELLIPSE,
    "area_rect": CAMERA_VISIBLE.format('RectLight "Area"', "block (12,2) -99.1% (-172 sigma), "
                                                          "pooled -5.4%"),
    "area_spread60": SPREAD,
    "area_square": CAMERA_VISIBLE.format('RectLight "Area"', "block (9,1) -99.2% (-439 sigma), "
                                                            "pooled -29.0%"),
    "emission_principled": EMISSION_CACHE_NOISE,
    "light_exposure": CUBE_FOOT_EXPOSURE,
    "mat_default": CUBE_FOOT,
    "metal_rough": METAL_ROUGH_USD,
    "point_r01_hard": HARD_FALLOFF,
    "point_r01_soft": CAMERA_VISIBLE.format('SphereLight "Point"', "block (8,2) -90.2% (-299 "
                                                                  "sigma), pooled -4.5%"),
    "spot_offaxis": SPOT_DARK_FLOOR.format("blocks (19,13) and (19,14) -20% (-6.6 sigma)"),
    "spot_radius": SPOT_RADIUS_CORNER,
    "sun_angle": SUN_HALF_ANGLE,
}


def reason(path: str, name: str) -> str | None:
    return {"addon": ADDON, "usd": USD}[path].get(name)


def marks(path: str, name: str) -> list:
    """pytest marks for scene ``name`` on ``path`` ("addon" or "usd")."""
    import pytest

    why = reason(path, name)
    return [pytest.mark.xfail(strict=True, reason=why)] if why else []
