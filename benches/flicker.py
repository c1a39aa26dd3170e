#!/usr/bin/env python3
"""Flicker of a camera move over a static scene, with and without photon-map reuse.

The caustic Cornell box (``tests/data/scenes/cornell_spheres.json``, glass and mirror
spheres) is written as a USD stage whose camera slides sideways by ``--step`` per frame, and
rendered by the ``photonmap`` command (Jensen's mode) in three ways:

- ``reuse``: ``--frames 1:N`` (the default): the first frame's photon maps and irradiance
  cache, extended per view, for every frame;
- ``rebuild``: ``--frame-photon-maps rebuild``: every frame builds its own maps and cache
  (the same seed, so the same photons; the cache's records move with the view);
- ``reseed``: every frame built with its own seed (``--seed`` = frame), as renderers that
  re-export each frame do.

Flicker between frames t-1 and t is what their difference holds beyond the true change of
the image: ``(F_t - F_t-1) - (R_t - R_t-1)``, with R a converged render of the same frames
(pppm, ``--ref-passes`` passes). It is reported as RMS over pixels relative to the mean
image (``pixel``), and over 8x8-pixel block means (``block``: the low-frequency flicker that
reads as crawling blotches), averaged over the frame pairs.

    python benches/flicker.py --frames 8 --width 160 --height 120 --out flicker.json
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "python"))


def beauty(path):
    import OpenImageIO as oiio

    return oiio.ImageBuf(path).get_pixels(oiio.FLOAT)[..., :3].astype(np.float64)


def run(args):
    t0 = time.monotonic()
    r = subprocess.run([sys.executable, "-m", "photonmap.cli", *args], capture_output=True,
                       text=True)
    if r.returncode != 0:
        sys.exit(r.stderr)
    return time.monotonic() - t0


def blocks(img, b=8):
    h, w = (img.shape[0] // b) * b, (img.shape[1] // b) * b
    return img[:h, :w].reshape(h // b, b, w // b, b, 3).mean(axis=(1, 3))


def flicker(frames, refs):
    px, bl = [], []
    scale = np.mean([r.mean() for r in refs])
    for t in range(1, len(frames)):
        d = (frames[t] - frames[t - 1]) - (refs[t] - refs[t - 1])
        px.append(np.sqrt(np.mean(d ** 2)) / scale)
        bl.append(np.sqrt(np.mean(blocks(d) ** 2)) / scale)
    return float(np.mean(px)), float(np.mean(bl))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--frames", type=int, default=8)
    ap.add_argument("--step", type=float, default=0.01, help="camera move per frame")
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=120)
    ap.add_argument("--quality", default="medium")
    ap.add_argument("--ref-passes", type=int, default=512)
    ap.add_argument("--ref-photons", type=int, default=50000)
    ap.add_argument("--work", default=None, help="directory for the renders (kept)")
    ap.add_argument("--out", default=None, help="JSON of the figures")
    a = ap.parse_args()

    from conftest import write_scene_usda

    work = a.work or tempfile.mkdtemp(prefix="flicker-")
    os.makedirs(work, exist_ok=True)
    desc = json.load(open(os.path.join(ROOT, "tests", "data", "scenes", "cornell_spheres.json")))
    stage = write_scene_usda(os.path.join(work, "move.usda"), desc,
                             camera_x=tuple(a.step * i for i in range(a.frames)))
    frames = f"1:{a.frames}"
    size = ["--width", str(a.width), "--height", str(a.height), "--quiet"]
    common = [stage, *size, "--quality", a.quality]
    seconds = {}
    seconds["reuse"] = run(["render", *common, "--frames", frames, "-o",
                            os.path.join(work, "reuse.#.exr")])
    seconds["rebuild"] = run(["render", *common, "--frames", frames, "--frame-photon-maps",
                              "rebuild", "-o", os.path.join(work, "rebuild.#.exr")])
    t = 0.0
    for f in range(1, a.frames + 1):
        t += run(["render", *common, "--frames", str(f), "--seed", str(f), "-o",
                  os.path.join(work, "reseed.#.exr")])
    seconds["reseed"] = t
    for f in range(1, a.frames + 1):
        ref = os.path.join(work, f"ref.{f:04d}.exr")
        if not os.path.exists(ref):
            run(["render", stage, *size, "--frames", str(f), "--mode", "pppm", "--spp",
                 str(a.ref_passes), "--photons", str(a.ref_photons), "-o",
                 os.path.join(work, "ref.#.exr")])
    refs = [beauty(os.path.join(work, f"ref.{f:04d}.exr")) for f in range(1, a.frames + 1)]
    out = {"frames": a.frames, "step": a.step, "size": [a.width, a.height],
           "quality": a.quality, "reference_passes": a.ref_passes, "seconds": seconds}
    for way in ("reuse", "rebuild", "reseed"):
        imgs = [beauty(os.path.join(work, f"{way}.{f:04d}.exr")) for f in range(1, a.frames + 1)]
        p, b = flicker(imgs, refs)
        err = float(np.mean([np.sqrt(np.mean((i - r) ** 2)) / r.mean()
                             for i, r in zip(imgs, refs)]))
        out[way] = {"flicker_pixel": p, "flicker_block": b, "rms_error": err}
        print(f"{way:8s} flicker: pixel {p:.4f}, 8x8 block {b:.4f}; error against the "
              f"reference {err:.4f}; {seconds[way]:.1f} s")
    if a.out:
        json.dump(out, open(a.out, "w"), indent=1)


if __name__ == "__main__":
    main()
