"""Render settings of the corpus comparisons, shared by both paths (no bpy).

Each setting is the keywords of ``photonmap.render`` (the add-on's ``scene.photonmap`` fields
of the same names): a quality preset, optionally with some of its numbers changed. Every
corpus render uses the box filter of the references (Cycles' Box filter, 1 px).
"""

from __future__ import annotations

FILTER = "box"

SETTINGS: dict[str, dict] = {
    # The CI setting: the draft preset with 4x its global photons, two seeds per scene; scenes
    # with fog (ray marching dominates their time) with fewer camera samples. With draft's
    # 50,000 photons the global map's density estimates at the secondary hits of final
    # gathering leave the room's concave corners 4-8% dark per 8x8 block (room_empty: -8.2%,
    # 5.9 sigma), a bias the noise floors do not hold; 200,000 photons bring it under the
    # tolerance (-3.3%) for ~10% more time. The fog scenes carry more photons still: with
    # draft's 20,000 volume photons the spot's beam in fog_spot_out blurs into the dim fog
    # beside it (+9-11% per block, ~5 sigma), and with 200,000 global photons the back wall
    # above its fog, lit only by light the fog scatters, is -5% (six seeds) per block; 200,000
    # volume and 600,000 global photons bring both under the tolerance (+2.5%, -1%). With
    # draft's 20,000 caustic photons the glass sphere's caustic on the floor (glass_r0,
    # glass_bsdf) is blurred: block (5,12) +8% and (4,9) -8% over six seeds, hidden by the
    # noise floor until adaptive sampling lowered it there; 100,000 bring them to +3.5% and
    # -4.5% (four seeds). Both paths render the corpus in a few minutes on two cores.
    # A sun's photons leave over the whole scene's bounding disc, so the courtyard's walls
    # get fewer of them than a room's walls get from a lamp: at 200,000 the concave corner of
    # sun_angle's left and back walls, block (4,4), is -3.8% (standard error 1.1%, 16 seeds),
    # at 1,000,000 -0.75% (1.0%, eight seeds); the irradiance cache is not the cause (-3.5%
    # without it).
    # Under a dark sphere on a dark floor (nodes_coat_normal, albedo 0.5/0.06/0.04), where the
    # floor is lit almost only by light the sphere and the floor pass between them, draft's 64
    # final-gathering rays leave block (13,13) +10.3% (+6.0 sigma, tolerance 9.2%, four
    # seeds); with 600,000 photons +10.9%, without the irradiance cache +10.0%, with 128 rays
    # it passes (medium too), so such scenes ("gather") take 128.
    "ci": {"quality": "draft", "photons": 200_000, "caustic_photons": 100_000,
           "by_tag": {"fog": {"spp": 2, "photons": 600_000, "volume_photons": 200_000},
                      "sun": {"photons": 1_000_000},
                      "gather": {"final_gather_rays": 128}}},
    "draft": {"quality": "draft"},
    "medium": {"quality": "medium"},
    "high": {"quality": "high"},
    "final": {"quality": "final"},
}


def settings(name: str, tags=()) -> dict:
    """``photonmap.render`` keywords of the setting ``name`` for a scene of ``tags`` (with the
    box filter)."""
    try:
        s = dict(SETTINGS[name])
    except KeyError:
        raise ValueError(f"unknown corpus setting {name!r}; one of {sorted(SETTINGS)}") from None
    by_tag = s.pop("by_tag", {})
    for tag in tags:
        s.update(by_tag.get(tag, {}))
    s["filter"] = FILTER
    return s
