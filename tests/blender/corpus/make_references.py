"""Renders the Cycles references of the parity corpus and exports its USD stages.

    nice -n 10 .venv-bpy/bin/python tests/blender/corpus/make_references.py            # all
    .venv-bpy/bin/python tests/blender/corpus/make_references.py --only area_back --spp 64
    .venv-bpy/bin/python tests/blender/corpus/make_references.py --usd-only
    .venv-bpy/bin/python tests/blender/corpus/make_references.py --preview DIR --spp 32

Needs the `bpy` module (5.0.1) and OpenImageIO. Steps:

1. ``textures/``: the small generated inputs, written when missing: ``checker.png`` (64x64
   sRGB checker), ``texels.png`` (12x12 random colours), ``uv_ramp.png`` (64x64, no symmetry: red along u, green along v, a grid
   and one marked corner tile), ``tiles_normal.png`` and ``sky.exr`` (128x64 half-float equirectangular sky with a sun).
2. ``refs/<scene>_s1.exr`` and ``_s2.exr``: Cycles on the CPU with seeds 1 and 2, no
   denoising, no clamping, no adaptive sampling, bounces 128 (every kind), caustics on, no
   glossy blur, a Box pixel filter of width 1 px (PhotonMap's ``filter="box"``: uniform over
   the pixel). Two seeds give a per-pixel noise floor. Stored as RGB half float (PIZ) with
   the mantissa rounded to 7 of its 10 bits, to keep the files small: a relative rounding
   of at most 0.39% per pixel (0.23% rms, zero mean), far below the references' own noise.
3. ``refs/manifest.json``: per scene its description, spp, render seconds per seed, and its
   USD stage (or why there is none).
4. ``usd/<scene>.usda``: Blender's USD exporter (``generate_materialx_network`` and
   ``generate_preview_surface``, as tests/python/make_blender_stages.py), textures kept at
   their committed paths (relative to the stage). Scenes whose content the exporter drops
   (mesh volumes) get no stage.

Spp per scene: ``SPP`` below, chosen so that the references' per-block noise is a small part
of the comparison's tolerance (compare.py); ``--spp`` overrides it.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
from corpus import scenes  # noqa: E402

REFS = os.environ.get("PHOTONMAP_CORPUS_REFS") or os.path.join(HERE, "refs")
USD = os.path.join(HERE, "usd")
MANIFEST = os.path.join(REFS, "manifest.json")
SEEDS = (1, 2)
DEFAULT_SPP = 1024
#: Samples per pixel per scene, from a calibration at 256 spp: the least power of two (1024 to
#: 4096) that brings the median 8x8-block standard error of the two seeds' mean to about
#: 0.25%; 2048 for the sensitivity tests' scenes (corpus/sensitivity.py), whose noise must be
#: lowest.
SPP: dict[str, int] = {
    "area_edge": 2048, "area_spread60": 4096, "fog_spot_in": 4096, "fog_spot_out": 4096,
    "glass_bsdf": 2048, "glass_r0": 2048, "glossy_bsdf": 2048, "metal_smooth": 2048,
    "mirror_light": 4096, "spot_blend": 4096, "spot_offaxis": 4096, "spot_radius": 4096,
    "room_empty": 2048, "mat_default": 2048,
}


def make_textures(force: bool = False) -> None:
    import OpenImageIO as oiio

    os.makedirs(scenes.TEXTURES, exist_ok=True)
    checker = scenes.checker_path()
    if force or not os.path.exists(checker):
        n, k = 64, 8
        yy, xx = np.mgrid[0:n, 0:n]
        odd = ((xx // k + yy // k) % 2).astype(bool)
        px = np.empty((n, n, 3), np.uint8)
        px[~odd] = (230, 220, 200)
        px[odd] = (40, 70, 160)
        out = oiio.ImageOutput.create(checker)
        out.open(checker, oiio.ImageSpec(n, n, 3, oiio.UINT8))
        out.write_image(px)
        out.close()
    tiles = os.path.join(scenes.TEXTURES, "tiles_normal.png")
    if force or not os.path.exists(tiles):
        # A tangent-space normal map of 4 x 4 tiles with bevelled edges (8-bit, rows top to
        # bottom, v up): the height rises over 5 texels from each tile's border.
        n, k, bevel = 128, 32, 5.0
        yy, xx = np.mgrid[0:n, 0:n].astype(np.float64) + 0.5
        d = np.minimum.reduce([xx % k, k - xx % k, yy % k, k - yy % k])
        h = np.minimum(d, bevel) / bevel
        dh_drow, dh_dx = np.gradient(h)
        strength = 4.0
        nrm = np.stack([-dh_dx * strength, dh_drow * strength, np.ones_like(h)], -1)
        nrm /= np.linalg.norm(nrm, axis=-1, keepdims=True)
        px = np.round((nrm * 0.5 + 0.5) * 255).astype(np.uint8)
        out = oiio.ImageOutput.create(tiles)
        out.open(tiles, oiio.ImageSpec(n, n, 3, oiio.UINT8))
        out.write_image(px)
        out.close()
    ramp = os.path.join(scenes.TEXTURES, "uv_ramp.png")
    if force or not os.path.exists(ramp):
        # An image no flip or rotation maps onto itself: red rises along u, green along v, and
        # a dark 4 x 4 grid with one white tile near the (0, 0) corner (rows top to bottom).
        n = 64
        yy, xx = np.mgrid[0:n, 0:n]
        u, v = (xx + 0.5) / n, 1.0 - (yy + 0.5) / n
        px = np.stack([0.15 + 0.8 * u, 0.15 + 0.8 * v, np.full_like(u, 0.3)], -1)
        px[(xx % 16 == 0) | (yy % 16 == 0)] *= 0.3
        px[(u > 0.0625) & (u < 0.1875) & (v > 0.0625) & (v < 0.1875)] = 1.0
        px = np.round(px * 255).astype(np.uint8)
        out = oiio.ImageOutput.create(ramp)
        out.open(ramp, oiio.ImageSpec(n, n, 3, oiio.UINT8))
        out.write_image(px)
        out.close()
    texels = os.path.join(scenes.TEXTURES, "texels.png")
    if force or not os.path.exists(texels):
        # 12 x 12 random colours (8-bit sRGB), large on screen: how an image is read between
        # its texels (Closest, Linear, Cubic) shows directly.
        px = np.random.default_rng(12).integers(20, 236, (12, 12, 3)).astype(np.uint8)
        out = oiio.ImageOutput.create(texels)
        out.open(texels, oiio.ImageSpec(12, 12, 3, oiio.UINT8))
        out.write_image(px)
        out.close()
    sky = scenes.hdri_path()
    if force or not os.path.exists(sky):
        w, h = 128, 64
        # Blender's equirectangular mapping (Cycles' direction_to_equirectangular):
        # u = 0.5 - atan2(dir.y, dir.x) / 2pi, v = 0.5 + asin(dir.z) / pi; rows top (v = 1)
        # to bottom.
        v = 1.0 - (np.arange(h) + 0.5) / h
        u = (np.arange(w) + 0.5) / w
        el = (v - 0.5) * np.pi
        az = (u - 0.5) * 2 * np.pi
        el, az = np.meshgrid(el, az, indexing="ij")
        d = np.stack([np.cos(el) * np.cos(az), -np.cos(el) * np.sin(az), np.sin(el)], -1)
        t = np.clip(np.sin(el), 0, 1)[..., None]
        horizon = np.array([0.9, 0.85, 0.75])
        zenith = np.array([0.25, 0.4, 0.85])
        ground = np.array([0.18, 0.15, 0.12])
        img = np.where(el[..., None] >= 0, horizon * (1 - t) + zenith * t, ground)
        # A small sun (5 deg across) to the front left (behind the camera), 40 deg up, and a
        # faint warm glow around it.
        sun_el, sun_az = np.radians(40), np.radians(235)
        sd = np.array([np.cos(sun_el) * np.cos(sun_az), np.cos(sun_el) * np.sin(sun_az),
                       np.sin(sun_el)])
        cosang = np.clip(d @ sd, -1, 1)
        ang = np.degrees(np.arccos(cosang))
        img = img + np.where(ang < 2.5, 60.0, 0.0)[..., None] * np.array([1.0, 0.9, 0.75])
        img = img + (0.6 * np.exp(-(ang / 15.0) ** 2))[..., None] * np.array([1.0, 0.8, 0.5])
        spec = oiio.ImageSpec(w, h, 3, oiio.HALF)
        spec.attribute("compression", "zip")
        out = oiio.ImageOutput.create(sky)
        out.open(sky, spec)
        out.write_image(img.astype(np.float32))
        out.close()


def setup_cycles(sc, spp: int, seed: int) -> None:
    sc.render.engine = "CYCLES"
    c = sc.cycles
    c.device = "CPU"
    c.samples = spp
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    for attr in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                 "transparent_max_bounces", "volume_bounces"):
        setattr(c, attr, 128)
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.blur_glossy = 0.0
    c.seed = seed
    c.use_animated_seed = False
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    sc.view_settings.view_transform = "Standard"
    im = sc.render.image_settings
    im.file_format = "OPEN_EXR"
    im.color_mode = "RGB"
    im.color_depth = "16"
    im.exr_codec = "ZIP"


MANTISSA_BITS_DROPPED = 3


def store(src: str, dst: str, meta: dict) -> None:
    """Rewrites Cycles' EXR ``src`` as ``dst``: RGB half, mantissa rounded, PIZ, metadata."""
    import OpenImageIO as oiio

    px = oiio.ImageBuf(src).get_pixels(oiio.FLOAT)[..., :3]
    h = np.ascontiguousarray(px, dtype=np.float16).view(np.uint16)
    k = MANTISSA_BITS_DROPPED
    rounded = ((h.astype(np.uint32) + (1 << (k - 1))) & ~np.uint32((1 << k) - 1))
    q = rounded.astype(np.uint16).view(np.float16).astype(np.float32)
    spec = oiio.ImageSpec(px.shape[1], px.shape[0], 3, oiio.HALF)
    spec.attribute("compression", "piz")
    for key, value in meta.items():
        spec.attribute(f"photonmap:{key}", str(value))
    out = oiio.ImageOutput.create(dst)
    out.open(dst, spec)
    out.write_image(np.ascontiguousarray(q))
    out.close()


def spp_of(name: str, override: int | None) -> int:
    return override or SPP.get(name, DEFAULT_SPP)


def render(name: str, spp: int, seed: int, path: str) -> float:
    sc = scenes.SCENES[name].build()
    setup_cycles(sc, spp, seed)
    raw = path + ".cycles.exr"
    sc.render.filepath = raw
    t = time.time()
    bpy.ops.render.render(write_still=True)
    secs = time.time() - t
    store(raw, path, {"scene": name, "spp": spp, "seed": seed,
                      "renderer": f"Cycles {bpy.app.version_string}"})
    os.remove(raw)
    return secs


def export_usd(name: str) -> str | None:
    entry = scenes.SCENES[name]
    if entry.no_usd:
        return None
    entry.build()
    os.makedirs(USD, exist_ok=True)
    path = os.path.join(USD, f"{name}.usda")
    bpy.ops.wm.usd_export(filepath=path, export_materials=True, generate_preview_surface=True,
                          generate_materialx_network=True, export_animation=False,
                          export_textures_mode="KEEP", relative_paths=True,
                          evaluation_mode="RENDER", convert_world_material=True)
    return os.path.relpath(path, HERE)


def load_manifest() -> dict:
    if os.path.exists(MANIFEST):
        with open(MANIFEST) as f:
            return json.load(f)
    return {}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--only", nargs="*", default=None, help="scene names (default: all)")
    ap.add_argument("--spp", type=int, default=None, help="override the per-scene spp")
    ap.add_argument("--usd-only", action="store_true", help="export the USD stages only")
    ap.add_argument("--no-usd", action="store_true", help="render the references only")
    ap.add_argument("--preview", default=None,
                    help="write single-seed renders to this folder instead of refs/")
    a = ap.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
    names = a.only or list(scenes.SCENES)
    unknown = [n for n in names if n not in scenes.SCENES]
    if unknown:
        sys.exit(f"unknown scenes: {unknown}")
    make_textures()
    if a.preview:
        os.makedirs(a.preview, exist_ok=True)
        for name in names:
            secs = render(name, spp_of(name, a.spp), 1, os.path.join(a.preview, f"{name}.exr"))
            print(f"{name}: {secs:.1f}s", flush=True)
        return
    os.makedirs(REFS, exist_ok=True)
    manifest = load_manifest()
    manifest.setdefault("renderer", f"Cycles {bpy.app.version_string}, CPU")
    manifest["settings"] = ("no denoising, no clamping, no adaptive sampling, bounces 128, "
                            "caustics on, no glossy blur, Box filter 1 px, seeds "
                            + ", ".join(map(str, SEEDS)))
    manifest["resolution"] = [scenes.WIDTH, scenes.HEIGHT]
    table = manifest.setdefault("scenes", {})
    for name in names:
        entry = scenes.SCENES[name]
        rec = table.setdefault(name, {})
        rec["description"] = entry.description
        rec["tags"] = list(entry.tags)
        if not a.usd_only:
            spp = spp_of(name, a.spp)
            secs = []
            for seed in SEEDS:
                secs.append(round(render(name, spp, seed,
                                         os.path.join(REFS, f"{name}_s{seed}.exr")), 1))
                print(f"{name} seed {seed}: {spp} spp, {secs[-1]}s", flush=True)
            rec["spp"] = spp
            rec["seconds"] = secs
        if not a.no_usd:
            rec["usd"] = export_usd(name)
            rec["no_usd"] = entry.no_usd
        with open(MANIFEST, "w") as f:  # after every scene: a long run can be resumed
            json.dump(manifest, f, indent=1, sort_keys=True)
    # Scenes no longer in the corpus leave the manifest.
    for gone in set(table) - set(scenes.SCENES):
        del table[gone]
    with open(MANIFEST, "w") as f:
        json.dump(manifest, f, indent=1, sort_keys=True)


if __name__ == "__main__":
    main()
    sys.stdout.flush()
