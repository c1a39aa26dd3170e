#!/usr/bin/env python3
"""Photon shooting beside LuxCore: PhotonGI's photon pass on the default scene
(tests/data/scenes/cornell_spheres.json), translated here from our IR.

Run with a venv holding pyluxcore 2.11 (PyPI, cp311) and numpy, pinned to one core (PhotonGI's
photon pass ignores `native.threads.count` and takes every core):

    taskset -c 0 python benches/luxcore_photons.py [--runs 3]

Prints, per run, the paths PhotonGI traced, the photons it stored, and the seconds of its
tracing phase, read from LuxCore's log: from "PhotonGI tracing indirect cache photons" to
"PhotonGI additional indirect photon stored". Our side is `cargo bench --bench photons` (its
1-thread row, under the same `taskset`). The figures go to BENCHMARKS.md.

The translation: diffuse -> matte (kd), mirror -> mirror (kr), dielectric -> glass (kr = kt
= 1, interiorior); meshes with their transforms applied; the rect light -> a quad emitting
down (matte, kd 0, emission power 10 W) at its place; PATHCPU with PhotonGI's indirect cache
(1,000,000 photons at most, photon depth 64) and no caustic cache.
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np
import pyluxcore

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LOG = []


def scene_of(ir):
    scn = pyluxcore.Scene()
    p = pyluxcore.Properties()

    def put(k, v):
        p.Set(pyluxcore.Property(k, v))

    for i, m in enumerate(ir["materials"]):
        n = f"scene.materials.m{i}"
        if m["type"] == "diffuse":
            put(f"{n}.type", "matte")
            put(f"{n}.kd", m["color"])
        elif m["type"] == "mirror":
            put(f"{n}.type", "mirror")
            put(f"{n}.kr", m["color"])
        elif m["type"] == "dielectric":
            put(f"{n}.type", "glass")
            put(f"{n}.kr", [1, 1, 1])
            put(f"{n}.kt", [1, 1, 1])
            put(f"{n}.interiorior", m["ior"])
        else:
            raise SystemExit(f"/materials/{i}: type {m['type']!r} is not translated")
    put("scene.materials.light.type", "matte")
    put("scene.materials.light.kd", [0, 0, 0])
    put("scene.materials.light.emission", [1, 1, 1])
    put("scene.materials.light.emission.power", 10.0)
    put("scene.materials.light.emission.efficency", 1.0)
    put("scene.materials.light.emission.normalizebycolor", 0)
    for i, m in enumerate(ir["meshes"]):
        P = np.array(m["positions"], dtype=np.float64)
        if "transform" in m:
            M = np.array(m["transform"])
            P = (np.c_[P, np.ones(len(P))] @ M.T)[:, :3]
        F = [tuple(int(x) for x in f) for f in m["indices"]]
        scn.DefineMesh(f"shape{i}", [tuple(v) for v in P.tolist()], F, None, None, None, None)
        put(f"scene.objects.o{i}.shape", f"shape{i}")
        put(f"scene.objects.o{i}.material", f"m{m['material']}")
    (light,) = ir["lights"]
    if light["type"] != "rect":
        raise SystemExit("/lights/0: only the default scene's rect light is translated")
    w, h, y = light["width"] / 2, light["height"] / 2, light["transform"][1][3]
    quad = [(-w, y, -h), (w, y, -h), (w, y, h), (-w, y, h)]
    scn.DefineMesh("lightshape", quad, [(0, 1, 2), (0, 2, 3)], None, None, None, None)
    put("scene.objects.light.shape", "lightshape")
    put("scene.objects.light.material", "light")
    put("scene.camera.type", "perspective")
    put("scene.camera.lookat.orig", [0, 0, 4])
    put("scene.camera.lookat.target", [0, 0, 0])
    put("scene.camera.up", [0, 1, 0])
    put("scene.camera.fieldofview", math.degrees(ir["camera"]["fov"]))
    scn.Parse(p)
    return scn


def photon_pass(scn):
    c = pyluxcore.Properties()
    for k, v in [("renderengine.type", "PATHCPU"), ("sampler.type", "SOBOL"),
                 ("film.width", 128), ("film.height", 128), ("path.maxdepth", 64),
                 ("path.photongi.enable", 1), ("path.photongi.indirect.enabled", 1),
                 ("path.photongi.caustic.enabled", 0),
                 ("path.photongi.photon.maxcount", 1_000_000),
                 ("path.photongi.photon.maxdepth", 64),
                 ("path.photongi.indirect.maxsize", 1_000_000)]:
        c.Set(pyluxcore.Property(k, v))
    LOG.clear()
    session = pyluxcore.RenderSession(pyluxcore.RenderConfig(c, scn))
    session.Start()
    session.Stop()
    start = stored = traced = end = None
    for t, m in LOG:
        if "PhotonGI tracing indirect cache photons" in m:
            start = t
        elif "PhotonGI additional indirect photon stored:" in m:
            end, stored = t, int(m.rsplit(":", 1)[1])
        elif "PhotonGI total photon traced:" in m:
            traced = int(m.rsplit(":", 1)[1])
    if None in (start, end, stored, traced):
        raise SystemExit("LuxCore's log did not report PhotonGI's photon pass")
    return traced, stored, end - start


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", type=int, default=3)
    a = ap.parse_args()
    pyluxcore.Init(lambda msg: LOG.append((time.time(), msg)))
    ir = json.load(open(os.path.join(ROOT, "tests/data/scenes/cornell_spheres.json")))
    scn = scene_of(ir)
    print(f"LuxCore {pyluxcore.Version()} PhotonGI, default scene, cores: "
          f"{len(os.sched_getaffinity(0))}")
    print("| run | paths | photons stored | seconds | paths/s | photons stored/s |")
    print("|---|---|---|---|---|---|")
    for r in range(a.runs):
        traced, stored, secs = photon_pass(scn)
        print(f"| {r + 1} | {traced} | {stored} | {secs:.3f} | {traced / secs:.0f} | "
              f"{stored / secs:.0f} |", flush=True)


if __name__ == "__main__":
    main()
    # pyluxcore 2.11 can crash in its own teardown at interpreter exit, after every figure is
    # printed: leave without it.
    sys.stdout.flush()
    os._exit(0)
