"""Settings under ``scene.photonmap``: the CLI's names, defaults and quality presets (the
numbers come from ``photonmap.preset`` and ``photonmap.defaults``)."""

from __future__ import annotations

import bpy
import photonmap
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

_D = photonmap.defaults()
_DEFAULT_QUALITY = _D["quality"]
_P = photonmap.preset(_DEFAULT_QUALITY)
_QUALITY_ITEMS = [(q, q.capitalize(), f"The {q} preset of the core") for q in photonmap.QUALITIES]
#: The fields a preset fills.
PRESET_FIELDS = tuple(_P.keys())


def _apply_preset(self, _context):
    for key, value in photonmap.preset(self.quality).items():
        if hasattr(self, key):
            setattr(self, key, value if value is not None else 0)


class PhotonMapSettings(bpy.types.PropertyGroup):
    quality: EnumProperty(name="Quality", items=_QUALITY_ITEMS, default=_DEFAULT_QUALITY,
                          update=_apply_preset,
                          description="Preset; choosing one fills the settings below")
    spp: IntProperty(name="Samples", default=_P["spp"], min=1, soft_max=4096,
                     description="Camera samples per pixel")
    photons: IntProperty(name="Photons", default=_P["photons"], min=0,
                         description="Photons to store in the global map")
    caustic_photons: IntProperty(name="Caustic Photons", default=_P["caustic_photons"], min=0,
                                 description="Photons to store in the caustic map")
    volume_photons: IntProperty(name="Volume Photons", default=_P["volume_photons"], min=0,
                                description="Photons to store in the volume map (media)")
    volume_step: FloatProperty(name="Volume Step", default=0.0, min=0.0, subtype="DISTANCE",
                               description="Ray-marching step through media (0 = from the scene size)")
    gather: IntProperty(name="Gather", default=_P["gather"], min=1,
                        description="Photons per radiance estimate (k nearest)")
    radius: FloatProperty(name="Radius", default=_P["radius"] or 0.0, min=0.0, subtype="DISTANCE",
                          description="Largest photon search radius (0 = from the scene size)")
    final_gather_rays: IntProperty(name="Final Gather Rays", default=_P["final_gather_rays"], min=0,
                                   description="Final-gathering rays per irradiance-cache record")
    irradiance_cache: BoolProperty(name="Irradiance Cache", default=_P["irradiance_cache"],
                                   description="Ward's irradiance cache for final gathering")
    cache_tolerance: FloatProperty(name="Cache Tolerance", default=_P["cache_tolerance"],
                                   min=0.001, soft_max=1.0,
                                   description="Irradiance-cache error tolerance (Ward's a)")
    max_specular_depth: IntProperty(name="Max Specular Depth", default=_P["max_specular_depth"],
                                    min=0, soft_max=64,
                                    description="Perfectly specular bounces followed from the eye")
    mode: EnumProperty(
        name="Mode", default=_D["mode"],
        items=[("jensen", "Jensen", "Photon maps built once; final gathering with the "
                "irradiance cache"),
               ("sppm", "Progressive", "Stochastic progressive photon mapping: Samples passes, "
                "each with a fresh map of Photons photons and a shrinking search radius; "
                "converges to the exact image")],
        description="How caustics and indirect light are estimated")
    alpha: FloatProperty(name="Alpha", default=_D["alpha"], min=0.01, max=0.99,
                         description="Progressive mode: fraction of each pass's photons a pixel "
                         "keeps as its radius shrinks")
    initial_photons: IntProperty(name="Initial Photons", default=_D["initial_photons"], min=1,
                                 description="Progressive mode: photons within a pixel's first "
                                 "search radius, which shrinks from there")
    time_budget: FloatProperty(name="Time Budget", default=0.0, min=0.0,
                               description="Seconds the whole render should take; photon counts "
                               "and camera passes are planned to fill it (0 = off)")
    memory_limit: StringProperty(name="Memory Limit", default="",
                                 description="Largest memory the photon maps and the BVH may "
                                 "take, in bytes or as 512M, 8G (empty = the available memory); "
                                 "a render that would need more stops up front")
    filter: EnumProperty(
        name="Pixel Filter", default=_D["filter"],
        items=[("gaussian", "Gaussian", "Gaussian of standard deviation 0.5 px (the core's "
                "default)"),
               ("box", "Box", "Uniform over the pixel (Cycles' Box filter of width 1 px)"),
               ("tent", "Tent", "Triangle of radius 1 px")],
        description="Pixel reconstruction filter (as --filter)")
    photon_power: EnumProperty(
        name="Photon Power", default=_D["photon_power"],
        items=[("rgbe", "RGBE", "20-byte photons, the power in Ward's shared exponent"),
               ("f32", "Float", "28-byte photons, the power unquantised")],
        description="How a stored photon's power is encoded (as --photon-power)")
    progressive: BoolProperty(name="Whole Passes", default=_D["progressive"],
                              description="Jensen mode: take the camera samples in whole passes "
                              "over the image, as a time budget does (to replay a budgeted "
                              "render's recorded plan)")
    gather_rays_per_sample: IntProperty(
        name="Gather Rays per Sample", default=0, min=0,
        description="Final-gathering rays per camera sample where the irradiance cache does "
        "not apply (0 = Final Gather Rays / Samples, at least 4)")
    seed: IntProperty(name="Seed", default=_D["seed"], min=0, description="Random seed")
    threads: IntProperty(name="Threads", default=_D["threads"], min=0, description="Worker threads (0 = all)")


def render_settings(s: PhotonMapSettings) -> dict:
    """Keyword arguments of ``photonmap.render`` for these settings."""
    return {
        "quality": s.quality, "spp": s.spp, "photons": s.photons,
        "caustic_photons": s.caustic_photons, "volume_photons": s.volume_photons,
        "volume_step": s.volume_step if s.volume_step > 0 else None, "gather": s.gather,
        "radius": s.radius if s.radius > 0 else None, "final_gather_rays": s.final_gather_rays,
        "irradiance_cache": s.irradiance_cache, "cache_tolerance": s.cache_tolerance,
        "max_specular_depth": s.max_specular_depth, "filter": s.filter, "seed": s.seed,
        "threads": s.threads,
        "time_budget": s.time_budget if s.time_budget > 0 else None,
        "mode": s.mode, "alpha": s.alpha, "initial_photons": s.initial_photons,
        "memory_limit": s.memory_limit.strip() or None,
        "photon_power": s.photon_power, "progressive": s.progressive,
        "gather_rays_per_sample": s.gather_rays_per_sample or None,
    }


def register():
    bpy.utils.register_class(PhotonMapSettings)
    bpy.types.Scene.photonmap = bpy.props.PointerProperty(type=PhotonMapSettings)


def unregister():
    del bpy.types.Scene.photonmap
    bpy.utils.unregister_class(PhotonMapSettings)
