"""What the compositing AOVs cost, and what denoising buys at equal time (BENCHMARKS.md,
"Compositing passes").

    python benches/compositing.py costs      # time and memory of each optional AOV
    python benches/compositing.py denoise    # denoised against raw error at equal time

``costs`` renders the default scene (Cornell box, glass and mirror spheres) at 256x256 with the
`medium` preset, without and with each optional AOV, `--repeat` times each (the median is
reported), and reads the AOVs' memory from the stats (``aov_memory_bytes``).

``denoise`` renders the test scenes that have Mitsuba references (tests/data/references) at
each preset with ``denoise=True``, then without denoising with the camera samples scaled so
that the render takes the denoised render's time (render and denoising). Error: relMSE
against Mitsuba's reference over the pixels where a converged render of ours (the `high`
preset at 512 spp) agrees with it (its worst 1% left out: the light's edges and its image in
the mirror sphere, a few pixels of aliasing that swamp every other pixel), the same pixels
for every render; and, where the scene has a caustic, the relMSE of 4x4-pixel block means in
the caustic's region (8x8 blocks where the converged render's caustic term exceeds a quarter
of its brightest) against the converged render; over 4 seeds, the ratio of that error after
and before denoising, and the caustic term's edge strength there (mean |dx| + |dy| of the
pixels), which a blur of its edges would lower.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time

import numpy as np

import photonmap

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
SCENES = os.path.join(ROOT, "tests", "data", "scenes")
REFS = os.path.join(ROOT, "tests", "data", "references")


def _default_with_groups() -> dict:
    """The default scene with its ceiling light in a group `key` and a second, warm light in
    `fill`."""
    ir = json.loads(photonmap._core.DEFAULT_SCENE_JSON)
    ir["lights"].append({"type": "point", "name": "lamp", "position": [-0.6, -0.5, 0.3],
                         "power": 6.0, "color": [1.0, 0.8, 0.5]})
    ir["lightgroups"] = [{"name": "key", "lights": [0]}, {"name": "fill", "lights": [1]}]
    return ir


def costs(args) -> None:
    base = json.loads(photonmap._core.DEFAULT_SCENE_JSON)
    base["film"] = {"width": args.size, "height": args.size}
    grouped = _default_with_groups()
    grouped["film"] = dict(base["film"])
    plain_two = dict(grouped, lightgroups=[])
    cases = [
        ("none", base, {}),
        ("denoising_data", base, {"denoising_data": True}),
        ("cryptomatte=object, 6 levels", base, {"cryptomatte": "object"}),
        ("cryptomatte=both, 6 levels", base, {"cryptomatte": "both"}),
        ("two lights, no groups", plain_two, {}),
        ("two lights, 2 groups (+default)", grouped, {}),
        ("denoise (pyoidn)", base, {"denoise": True}),
    ]
    # The cases take turns, `repeat` rounds: a machine shared with other work slows them
    # alike. CPU seconds (user + system, all threads) vary less with the load than the wall
    # clock does; the median of the rounds is reported.
    import resource

    def cpu() -> float:
        r = resource.getrusage(resource.RUSAGE_SELF)
        return r.ru_utime + r.ru_stime

    meas = {name: {"wall": [], "cpu": [], "stats": None} for name, _, _ in cases}
    for r in range(args.repeat):
        for name, scene, kw in cases:
            t0, c0 = time.perf_counter(), cpu()
            out = photonmap.render(scene, quality="medium", seed=1, threads=args.threads, **kw)
            meas[name]["wall"].append(time.perf_counter() - t0)
            meas[name]["cpu"].append(cpu() - c0)
            meas[name]["stats"] = out["stats"]
        print(f"round {r + 1} done", file=sys.stderr, flush=True)
    base_cpu = statistics.median(meas["none"]["cpu"])
    print("| AOVs | CPU s (median) | vs none | wall s (median) | AOV memory MiB | "
          "memory MiB |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, _, _ in cases:
        m = meas[name]
        st = m["stats"]
        c = statistics.median(m["cpu"])
        print(f"| {name} | {c:.2f} | {c / base_cpu:.3f} | {statistics.median(m['wall']):.2f} | "
              f"{st['aov_memory_bytes'] / 2**20:.1f} | {st['memory_bytes'] / 2**20:.1f} |",
              flush=True)


def _read(path):
    import OpenImageIO as oiio

    return oiio.ImageBuf(path).get_pixels(oiio.FLOAT)[..., :3]


def _pixel_error(img, ref):
    return (((img - ref) ** 2) / (ref ** 2 + 1e-2)).mean(-1)


def _blocks(img, k):
    h, w = img.shape[:2]
    return img.reshape(h // k, k, w // k, k, -1).mean((1, 3))


def denoise(args) -> None:
    presets = args.presets.split(",")
    print("| scene | preset | raw s | raw relMSE | raw equal-time s | raw equal-time relMSE | "
          "denoised s | denoised relMSE | caustic blocks raw / equal-time / denoised |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---|")
    caustic_rows = []
    for scene_name, ref_name in (("cornell_spheres", "cornell_spheres_full"),
                                 ("cornell_diffuse", "cornell_diffuse_full")):
        path = os.path.join(SCENES, f"{scene_name}.json")
        ref = _read(os.path.join(REFS, f"{ref_name}.exr"))
        conv = photonmap.render(path, quality="high", spp=512, seed=7, threads=args.threads)
        e_conv = _pixel_error(conv["combined"], ref)
        keep = e_conv <= np.quantile(e_conv, 0.99)
        caus = _blocks(conv["caustic"], 8).mean(-1)
        region = caus > 0.25 * caus.max() if caus.max() > 0 else np.zeros_like(caus, bool)
        mask = np.repeat(np.repeat(region, 2, 0), 2, 1)

        def err(img):
            return float(_pixel_error(img, ref)[keep].mean())

        def caustic(img):
            if not mask.any():
                return float("nan")
            return float(_pixel_error(_blocks(img, 4), _blocks(conv["combined"], 4))[mask].mean())

        def edges(img):
            c = img.mean(-1)
            g = np.abs(np.diff(c, axis=1))[:-1, :] + np.abs(np.diff(c, axis=0))[:, :-1]
            return float(g[np.repeat(np.repeat(region, 8, 0), 8, 1)[:-1, :-1]].mean())

        for q in presets:
            if mask.any():
                # The caustic over 4 seeds: the block error of the denoised render over its
                # own noisy render's, and the caustic term's edge strength.
                ratios, e_noisy, e_den = [], [], []
                for seed in range(1, 5):
                    o = photonmap.render(path, quality=q, seed=seed, threads=args.threads,
                                         denoise=True)
                    noisy = o["emission"] + sum(o[f"{t}_noisy"] for t in
                                                photonmap.DENOISED_TERMS)
                    ratios.append(caustic(o["combined"]) / caustic(noisy))
                    e_noisy.append(edges(o["caustic_noisy"]))
                    e_den.append(edges(o["caustic"]))
                caustic_rows.append(
                    f"| {scene_name} | {q} | {statistics.mean(ratios):.2f} "
                    f"({min(ratios):.2f}-{max(ratios):.2f}) | {statistics.mean(e_noisy):.4f} | "
                    f"{statistics.mean(e_den):.4f} | {edges(conv['caustic']):.4f} |")
            spp = photonmap.preset(q)["spp"]
            t0 = time.perf_counter()
            raw = photonmap.render(path, quality=q, seed=1, threads=args.threads)
            t_raw = time.perf_counter() - t0
            t0 = time.perf_counter()
            den = photonmap.render(path, quality=q, seed=1, threads=args.threads, denoise=True)
            t_den = time.perf_counter() - t0
            scale = max(t_den / t_raw, 1.0)
            spp_eq = max(int(round(spp * scale)), spp)
            t0 = time.perf_counter()
            eq = photonmap.render(path, quality=q, seed=2, spp=spp_eq,
                                  max_spp=photonmap.preset(q)["max_spp"] * spp_eq // spp,
                                  threads=args.threads)
            t_eq = time.perf_counter() - t0
            print(f"| {scene_name} | {q} | {t_raw:.2f} | {err(raw['combined']):.2e} | "
                  f"{t_eq:.2f} ({spp_eq} spp) | {err(eq['combined']):.2e} | {t_den:.2f} | "
                  f"{err(den['combined']):.2e} | {caustic(raw['combined']):.2e} / "
                  f"{caustic(eq['combined']):.2e} / {caustic(den['combined']):.2e} |", flush=True)
    print("\n| scene | preset | caustic blocks, denoised / noisy (4 seeds: mean, range) | "
          "edge strength noisy | denoised | converged |")
    print("|---|---|---|---:|---:|---:|")
    for row in caustic_rows:
        print(row)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("what", choices=["costs", "denoise"])
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--size", type=int, default=256)
    p.add_argument("--presets", default="draft,medium,high")
    args = p.parse_args(argv)
    {"costs": costs, "denoise": denoise}[args.what](args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
