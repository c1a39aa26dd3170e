#!/usr/bin/env python3
"""What a distributed render moves and merges, measured: the figures behind the estimate of
scaling to many nodes in BENCHMARKS.md ("Rendering on a farm").

- the size of a pppm block's partial sums per pixel, and the time to merge them;
- the size of a Jensen tile's film, of its first stage's means and errors and of the
  pixels' state it keeps on its worker;
- the size of the photon-map file broadcast to every worker, per preset;
- the fixed cost of a task: reading the scene and building it (BVH), and r_1.

    python benches/farm_costs.py [--width 320 --height 240]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np

import photonmap
from photonmap import _core

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "tests", "data", "scenes", "cornell_spheres.json")


def best(f, n=3):
    ts = []
    for _ in range(n):
        t0 = time.perf_counter()
        r = f()
        ts.append(time.perf_counter() - t0)
    return min(ts), r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=240)
    a = ap.parse_args()
    w, h = a.width, a.height
    px = w * h
    size = ["--width", str(w), "--height", str(h)]
    out = {"width": w, "height": h}

    # pppm: a block's partial sums, and merging them.
    scene = photonmap.Scene.from_file(SCENE)
    desc = json.loads(scene.to_json())
    desc["film"] = {"width": w, "height": h}
    scene = photonmap.Scene.from_json(json.dumps(desc))
    kw = dict(mode="pppm", spp=8, photons=2000, seed=1, initial_radius=0.05)
    parts = [photonmap.render(scene, pass_range=(i, i + 1), **kw)["partial"] for i in range(8)]
    t, _ = best(lambda: photonmap.merge_partials(parts))
    out["partial_bytes"] = len(parts[0])
    out["partial_bytes_per_pixel"] = len(parts[0]) / px
    out["merge_8_partials_seconds"] = t
    out["merge_seconds_per_partial_megapixel"] = t / 8 / (px / 1e6)

    # Jensen: the photon-map file per preset, and a tile's traffic.
    argv = ["render", SCENE, "-o", "/dev/null", *size, "--quiet"]
    for q in ("draft", "medium", "high"):
        job = _core.Job(argv + ["--quality", q])
        sc, _ = job.scene(None, None)
        t, maps = best(lambda: job.build_maps(sc), n=1)
        out[f"maps_{q}_bytes"] = len(maps)
        out[f"maps_{q}_seconds"] = t
    job = _core.Job(argv + ["--quality", "draft"])
    sc, _ = job.scene(None, None)
    maps = job.build_maps(sc)
    rect = (0, 0, w, h)
    means, errors, state = job.tile_first(sc, maps, rect)
    rounds = job.adaptive_rounds(means, errors, w, h)
    film, _ = job.tile_finish(sc, maps, rect, rounds, state)
    out["tile_means_errors_bytes_per_pixel"] = (len(means) + len(errors)) / px
    out["tile_state_bytes_per_pixel"] = len(state) / px
    out["tile_film_bytes_per_pixel"] = len(film) / px

    # The fixed cost of a task: the command parsed, the scene read and built, r_1.
    t, _ = best(lambda: _core.Job(argv + ["--mode", "pppm"]).scene(None, None))
    out["task_scene_read_seconds"] = t
    job = _core.Job(argv + ["--mode", "pppm", "--photons", "20000"])
    t, _ = best(lambda: job.pppm_radius(sc), n=1)
    out["pppm_radius_seconds"] = t
    json.dump(out, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
