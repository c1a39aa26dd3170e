"""Renders the Cycles references of the brightness tests (tests/blender/data/cycles_*.exr).

    /path/to/bpy-venv/bin/python tests/blender/make_cycles_references.py [--samples 2048]

Cycles on the CPU, no denoising, no clamping, full bounces, Gaussian filter of the core's
width; the scenes are those of scenes.py. The EXRs are small (64x64, RGBA float).
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import scenes  # noqa: E402


def setup_cycles(sc, samples: int) -> None:
    sc.render.engine = "CYCLES"
    c = sc.cycles
    c.device = "CPU"
    c.samples = samples
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
    c.seed = 1
    # The core's default pixel filter is a Gaussian; Cycles' Gaussian width is in pixels.
    c.pixel_filter_type = "GAUSSIAN"
    c.filter_width = 1.0
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    sc.render.image_settings.exr_codec = "ZIP"
    sc.render.image_settings.color_management = "FOLLOW_SCENE"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=2048)
    ap.add_argument("--only", nargs="*", default=list(scenes.SCENES))
    a = ap.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
    os.makedirs(os.path.join(HERE, "data"), exist_ok=True)
    for name in a.only:
        sc = scenes.SCENES[name]()
        setup_cycles(sc, a.samples)
        sc.render.filepath = os.path.join(HERE, "data", f"cycles_{name}.exr")
        t = time.time()
        bpy.ops.render.render(write_still=True)
        print(f"{name}: {time.time() - t:.1f}s -> {sc.render.filepath}", flush=True)


if __name__ == "__main__":
    main()
