#!/usr/bin/env python3
"""Speed of a Dask render against one process, per way of splitting the work.

The caustic Cornell box (``tests/data/scenes/cornell_spheres.json``) as a USD stage whose
camera moves, rendered by the ``photonmap`` command three ways, each as one process and on a
``LocalCluster`` of 1 and of 2 workers (``--cluster local:N``: each worker takes cores / N
threads, so every run has the machine's cores):

- ``frames``: a camera animation of ``--frames`` frames, Jensen's mode (the first frame's
  photon maps and cache built once and broadcast);
- ``pppm``: one frame of ``--passes`` pppm passes, in blocks merged pairwise on the workers;
- ``tiles``: one Jensen frame in tiles over one broadcast set of maps and cache.

Each run is a whole process (Python start, USD import, the cluster's start, rendering,
writing), timed by its wall clock, ``--repeat`` times in turns (one process, 1 worker,
2 workers, then again); the table gives the median seconds and the speed-up over one process.
The images are the same bits in all three (the tests check that); this measures time only.

    python benches/farm_speedup.py --out farm_speedup.json
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "python"))


def run(args: list[str]) -> float:
    t0 = time.monotonic()
    r = subprocess.run([sys.executable, "-m", "photonmap.cli", *args], capture_output=True,
                       text=True)
    if r.returncode != 0:
        sys.exit(f"photonmap {' '.join(args)}\n{r.stderr}")
    return time.monotonic() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=240)
    ap.add_argument("--quality", default="medium")
    ap.add_argument("--frames", type=int, default=4)
    ap.add_argument("--passes", type=int, default=32)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--out", default=None, help="JSON of the figures")
    a = ap.parse_args()

    from conftest import write_scene_usda

    work = tempfile.mkdtemp(prefix="farm-speedup-")
    desc = json.load(open(os.path.join(ROOT, "tests", "data", "scenes", "cornell_spheres.json")))
    stage = write_scene_usda(os.path.join(work, "move.usda"), desc,
                             camera_x=tuple(0.01 * i for i in range(a.frames)))
    size = ["--width", str(a.width), "--height", str(a.height), "--quiet", "--seed", "3"]
    cases = {
        "frames": [stage, *size, "--quality", a.quality, "--frames", f"1:{a.frames}"],
        "pppm": [stage, *size, "--frames", "1", "--mode", "pppm", "--spp", str(a.passes)],
        "tiles": [stage, *size, "--quality", a.quality, "--frames", "1"],
    }
    ways = {"one process": [], "1 worker": ["--cluster", "local:1"],
            "2 workers": ["--cluster", "local:2"]}
    out = {"size": [a.width, a.height], "quality": a.quality, "frames": a.frames,
           "passes": a.passes, "repeat": a.repeat, "cpus": os.cpu_count(), "seconds": {}}
    for case, argv in cases.items():
        times = {w: [] for w in ways}
        for _ in range(a.repeat):
            for w, extra in ways.items():
                o = os.path.join(work, f"{case}.{w.replace(' ', '_')}.#.exr")
                times[w].append(run(["render", *argv, *extra, "-o", o]))
        out["seconds"][case] = times
        one = statistics.median(times["one process"])
        for w in ways:
            m = statistics.median(times[w])
            print(f"{case:7s} {w:12s} {m:7.2f} s  speed-up {one / m:.2f}  "
                  f"(runs {', '.join(f'{t:.2f}' for t in times[w])})", flush=True)
    if a.out:
        json.dump(out, open(a.out, "w"), indent=1)


if __name__ == "__main__":
    main()
