#!/usr/bin/env python3
"""Equal-time error of photonmap against Mitsuba 3's path tracer.

For each scene and each of our quality presets (all with --filter box):
  1. render with photonmap and time the whole process (scene build, photon passes,
     irradiance cache, camera pass, EXR write): T;
  2. render the same scene with Mitsuba `path` (max_depth -1, rr_depth 5, independent sampler,
     1-pixel box filter, same resolution) at the spp whose time matches T. Calibration: two
     runs at small spp give the fixed cost and the cost per spp; the matched spp is
     (T - fixed) / per-spp; then one run at that spp, whose actual time is recorded (if it is
     off T by more than --tolerance, the per-spp cost is re-estimated from it and Mitsuba
     renders once more; only the last run is scored, all are in the JSON);
  3. score both against the high-spp Mitsuba reference of tests/data/references/:
     relMSE = mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2), per pixel and
     on 8x8-pixel block means, and the ratio ours / Mitsuba.

Timing of Mitsuba: every Mitsuba run is a fresh Python process (this script with --worker).
The matched time is scene load (mi.load_dict) + mi.render + the copy to numpy, so it includes
Dr.Jit's tracing and kernel compilation (or a hit in Dr.Jit's on-disk kernel cache); it
excludes the Python interpreter start and `import mitsuba` / set_variant, which are reported
separately (`process_seconds`). Our time is the whole `photonmap render` process.

The reference is itself a path tracer with finite samples. Against a reference with per-pixel
standard error s, an exact image scores relMSE ~ mean(s^2 / (ref^2 + 1e-2)): the noise floor
(tests/data/references/<name>.json; for block means it is recomputed here from the
.stderr.exr, pixels being independent). We report raw relMSE, the floor, and
relMSE - floor (an estimate of the error against the true image), and ratios of both.

Usage (repository root; needs numpy, OpenImageIO, mitsuba==3.9.*, libLLVM for llvm_ad_rgb):

    python3 scripts/equal_time.py --bin target/release/photonmap > equal_time.json
    python3 scripts/equal_time.py --scenes cornell_spheres --qualities draft medium

JSON results go to stdout, the Markdown table to stderr (and to --markdown FILE if given).
"""
import argparse
import json
import math
import shlex
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REF_DIR = os.path.join(ROOT, "tests", "data", "references")
LLVM19 = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"
BLOCK = 8
EPS = 1e-2


def TRIM(n):
    return max(1, n // 1000)

SCENES = {
    "cornell_spheres": ("tests/data/scenes/cornell_spheres.json", "cornell_spheres_full"),
    "cornell_diffuse": ("tests/data/scenes/cornell_diffuse.json", "cornell_diffuse_full"),
}
INTEGRATOR = {"type": "path", "max_depth": -1, "rr_depth": 5}


def log(*a):
    print(*a, file=sys.stderr, flush=True)


# ----------------------------------------------------------------------------------------
# Images and error
# ----------------------------------------------------------------------------------------


def read_rgb(path):
    import OpenImageIO as oiio

    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    px = buf.get_pixels(oiio.FLOAT).reshape(spec.height, spec.width, spec.nchannels)
    names = list(spec.channelnames)
    return px[:, :, [names.index(c) for c in "RGB"]].astype(np.float64)


def block_means(img, b=BLOCK):
    h, w, c = img.shape
    return img[: h - h % b, : w - w % b].reshape(h // b, b, w // b, b, c).mean(axis=(1, 3))


def relmse(x, ref):
    return float(np.mean((x - ref) ** 2 / (ref ** 2 + EPS)))


def noise_floors(ref, stderr):
    """relMSE an exact image would score: per pixel, and on block means (independent pixels)."""
    pixel = float(np.mean(stderr ** 2 / (ref ** 2 + EPS)))
    h, w, c = stderr.shape
    var_block = (stderr[: h - h % BLOCK, : w - w % BLOCK] ** 2).reshape(
        h // BLOCK, BLOCK, w // BLOCK, BLOCK, c).sum(axis=(1, 3)) / BLOCK ** 4
    block = float(np.mean(var_block / (block_means(ref) ** 2 + EPS)))
    return pixel, block


def score(img, ref, floors):
    px, bl = relmse(img, ref), relmse(block_means(img), block_means(ref))
    per_pixel = np.sort(((img - ref) ** 2 / (ref ** 2 + EPS)).mean(axis=2).ravel())[::-1]
    return {
        # Share of the per-pixel relMSE in the 5 worst pixels (fireflies), and the relMSE
        # without the worst 0.1% of pixels.
        "top5_pixel_share": float(per_pixel[:5].sum() / per_pixel.sum()),
        "relmse_pixel_trimmed": float(per_pixel[TRIM(per_pixel.size):].mean()),
        "relmse_pixel": px,
        "relmse_block": bl,
        "relmse_pixel_minus_floor": px - floors[0],
        "relmse_block_minus_floor": bl - floors[1],
        "mean_pixel_value": float(img.mean()),
    }


# ----------------------------------------------------------------------------------------
# Renders
# ----------------------------------------------------------------------------------------


def render_ours(binary, scene, quality, seed, out_dir, extra=()):
    tag = "_".join(a.strip("-") for a in extra)
    exr = os.path.join(out_dir, f"ours_{os.path.basename(scene)}_{quality}{tag}.exr")
    stats = exr[:-4] + ".stats.json"
    cmd = [binary, "render", scene, "-o", exr, "--stats", stats, "--quality", quality,
           "--filter", "box", "--seed", str(seed), "--quiet", *extra]
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True)
    wall = time.perf_counter() - t0
    with open(stats) as f:
        st = json.load(f)
    passes = st.get("seconds", {})
    return read_rgb(exr), {
        "seconds": wall,
        "pass_seconds": passes,
        "pass_seconds_sum": float(sum(passes.values())),
        "spp": st.get("spp"),
        "photons_stored": st.get("photons_stored"),
        "irradiance_cache_records": st.get("irradiance_cache_records"),
        "command": " ".join(["photonmap"] + cmd[1:3] + ["-o", "out.exr"] + cmd[5:]),
    }


def render_mitsuba(scene, spp, seed, variant, out_dir):
    """One Mitsuba render in a fresh process; returns (image, timings)."""
    npy = os.path.join(out_dir, f"mitsuba_{os.path.basename(scene)}_{spp}_{seed}.npy")
    cmd = [sys.executable, os.path.abspath(__file__), "--worker", scene, str(spp), str(seed),
           variant, npy]
    t0 = time.perf_counter()
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    process = time.perf_counter() - t0
    t = json.loads(out.strip().splitlines()[-1])
    t["process_seconds"] = process
    t["spp"] = spp
    t["seed"] = seed
    return np.load(npy), t


def worker(scene, spp, seed, variant, npy):
    t0 = time.perf_counter()
    if "DRJIT_LIBLLVM_PATH" not in os.environ and os.path.exists(LLVM19):
        os.environ["DRJIT_LIBLLVM_PATH"] = LLVM19
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import mitsuba as mi
    from make_references import translate

    mi.set_variant(variant)
    t1 = time.perf_counter()
    with open(scene) as f:
        ir = json.load(f)
    sc = mi.load_dict(translate(ir, spp))
    integ = mi.load_dict(INTEGRATOR)
    t2 = time.perf_counter()
    img = np.array(mi.render(sc, integrator=integ, spp=spp, seed=seed), dtype=np.float64)
    t3 = time.perf_counter()
    np.save(npy, img)
    print(json.dumps({"import_seconds": t1 - t0, "load_seconds": t2 - t1,
                      "render_seconds": t3 - t2, "seconds": t3 - t1}))


def calibrate(scene, variant, out_dir, seed, spp_lo, spp_hi):
    """Fixed cost (s) and cost per spp (s) of Mitsuba's load + render, from two runs."""
    _, a = render_mitsuba(scene, spp_lo, seed, variant, out_dir)
    _, b = render_mitsuba(scene, spp_hi, seed + 1, variant, out_dir)
    per_spp = max((b["seconds"] - a["seconds"]) / (spp_hi - spp_lo), 1e-6)
    fixed = max(a["seconds"] - per_spp * spp_lo, 0.0)
    return {"fixed_seconds": fixed, "seconds_per_spp": per_spp, "runs": [a, b]}


# ----------------------------------------------------------------------------------------
# Report
# ----------------------------------------------------------------------------------------


def fmt(x):
    return f"{x:.2e}"


def ratio(a, b):
    return a / b if b > 0 else float("nan")


def markdown(results):
    rows = [
        "| scene | ours | T ours (s) | Mitsuba spp | T Mitsuba (s) | relMSE ours | relMSE Mitsuba "
        "| ratio | ratio, worst 0.1% px dropped | block relMSE ours | block relMSE Mitsuba "
        "| block ratio |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for s in results["scenes"]:
        fl = s["noise_floor"]
        for r in s["runs"]:
            o, m = r["ours"], r["mitsuba"]
            rows.append(
                f"| {os.path.basename(s['scene'])} | {r['quality']} {r.get('extra', '')} "
                f"({o['spp']} spp) | {o['seconds']:.2f} "
                f"| {m['spp']} | {m['seconds']:.2f} "
                f"| {fmt(o['relmse_pixel'])} | {fmt(m['relmse_pixel'])} "
                f"| {r['ratio_pixel']:.2f} ({r['ratio_pixel_minus_floor']:.2f}) "
                f"| {r['ratio_pixel_trimmed']:.2f} "
                f"| {fmt(o['relmse_block'])} | {fmt(m['relmse_block'])} "
                f"| {r['ratio_block']:.2f} ({r['ratio_block_minus_floor']:.2f}) |")
        rows.append(f"| {os.path.basename(s['scene'])} | reference noise floor | | {s['reference_spp']} | "
                    f"| {fmt(fl['pixel'])} | {fmt(fl['pixel'])} | | | {fmt(fl['block'])} "
                    f"| {fmt(fl['block'])} | |")
    return "\n".join(rows) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.environ.get("PHOTONMAP_BIN", "photonmap"),
                    help="photonmap binary (default: $PHOTONMAP_BIN or `photonmap`)")
    ap.add_argument("--scenes", nargs="*", default=list(SCENES), choices=list(SCENES))
    ap.add_argument("--qualities", nargs="*", default=["draft", "medium", "high"])
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--seed", type=int, default=1, help="our seed")
    ap.add_argument("--mitsuba-seed", type=int, default=1000,
                    help="first Mitsuba seed (one per run, counting up; the references use 0..63)")
    ap.add_argument("--calibrate-spp", type=int, nargs=2, default=[16, 128], metavar=("LO", "HI"))
    ap.add_argument("--tolerance", type=float, default=0.1,
                    help="re-render Mitsuba once if its time is off T by more than this fraction")
    ap.add_argument("--markdown", help="also write the Markdown table to this file")
    ap.add_argument("--extra", action="append", default=[],
                    help="more flags for our renderer, one configuration per use, e.g. "
                    "--extra='--mode sppm --photons 20000 --spp 256'; each runs with every "
                    "quality")
    ap.add_argument("--keep", help="keep the images in this directory")
    ap.add_argument("--worker", nargs=5, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.worker:
        scene, spp, seed, variant, npy = a.worker
        worker(scene, int(spp), int(seed), variant, npy)
        return 0

    out_dir = a.keep or tempfile.mkdtemp(prefix="equal_time_")
    os.makedirs(out_dir, exist_ok=True)
    try:
        load = os.getloadavg()
    except OSError:
        load = None
    results = {"cpus": os.cpu_count(), "loadavg_start": load, "variant": a.variant,
               "integrator": INTEGRATOR, "block": BLOCK, "eps": EPS,
               "relmse_definition": "mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2)",
               "mitsuba_seconds_definition": "mi.load_dict + mi.render + copy to numpy in a "
               "fresh process (JIT included); process_seconds adds interpreter start and import",
               "scenes": []}
    mseed = a.mitsuba_seed
    for name in a.scenes:
        scene_rel, ref_name = SCENES[name]
        scene = os.path.join(ROOT, scene_rel)
        ref = read_rgb(os.path.join(REF_DIR, ref_name + ".exr"))
        stderr = read_rgb(os.path.join(REF_DIR, ref_name + ".stderr.exr"))
        with open(os.path.join(REF_DIR, ref_name + ".json")) as f:
            ref_meta = json.load(f)
        floors = noise_floors(ref, stderr)
        log(f"{name}: reference {ref_name} ({ref_meta['spp']} spp), floor pixel {floors[0]:.3g} "
            f"block {floors[1]:.3g}")
        cal = calibrate(scene, a.variant, out_dir, mseed, *a.calibrate_spp)
        mseed += 2
        log(f"  Mitsuba calibration: {cal['fixed_seconds']:.2f} s fixed + "
            f"{cal['seconds_per_spp'] * 1e3:.1f} ms/spp")
        entry = {"scene": scene_rel, "reference": ref_name, "reference_spp": ref_meta["spp"],
                 "noise_floor": {"pixel": floors[0], "block": floors[1],
                                 "pixel_from_reference_json": ref_meta["relmse_noise_floor"]},
                 "mitsuba_calibration": cal, "runs": []}
        configs = [shlex.split(e) for e in a.extra] or [[]]
        for q, extra in [(q, e) for e in configs for q in a.qualities]:
            img_o, t_o = render_ours(a.bin, scene, q, a.seed, out_dir, extra)
            T = t_o["seconds"]
            spp = max(1, int(round((T - cal["fixed_seconds"]) / cal["seconds_per_spp"])))
            img_m, t_m = render_mitsuba(scene, spp, mseed, a.variant, out_dir)
            mseed += 1
            attempts = [dict(t_m)]
            if abs(t_m["seconds"] / T - 1) > a.tolerance:
                # Off by more than the tolerance (the machine's load changed): rescale the
                # per-spp cost by this run and render once more; the last run is the one scored.
                per_spp = max(t_m["seconds"] - cal["fixed_seconds"], 1e-3) / spp
                spp = max(1, int(round((T - cal["fixed_seconds"]) / per_spp)))
                img_m, t_m = render_mitsuba(scene, spp, mseed, a.variant, out_dir)
                mseed += 1
                attempts.append(dict(t_m))
            t_m["attempts"] = attempts
            so, sm = score(img_o, ref, floors), score(img_m, ref, floors)
            run = {
                "quality": q,
                "extra": " ".join(extra),
                "ours": {**t_o, **so},
                "mitsuba": {**t_m, **sm},
                "time_ratio_mitsuba_over_ours": t_m["seconds"] / T,
                # relMSE x time: the error of each at the other's exact time if relMSE ~ 1/time
                # (true for Mitsuba, optimistic for our biased estimates).
                "ratio_pixel_time_corrected": ratio(so["relmse_pixel"] * T,
                                                    sm["relmse_pixel"] * t_m["seconds"]),
                "ratio_pixel": ratio(so["relmse_pixel"], sm["relmse_pixel"]),
                "ratio_block": ratio(so["relmse_block"], sm["relmse_block"]),
                "ratio_pixel_trimmed": ratio(so["relmse_pixel_trimmed"],
                                             sm["relmse_pixel_trimmed"]),
                "ratio_pixel_minus_floor": ratio(so["relmse_pixel_minus_floor"],
                                                 sm["relmse_pixel_minus_floor"]),
                "ratio_block_minus_floor": ratio(so["relmse_block_minus_floor"],
                                                 sm["relmse_block_minus_floor"]),
            }
            entry["runs"].append(run)
            log(f"  {q} {' '.join(extra)}: ours {T:.2f} s relMSE {so['relmse_pixel']:.3g} / block "
                f"{so['relmse_block']:.3g}; Mitsuba {spp} spp {t_m['seconds']:.2f} s "
                f"(process {t_m['process_seconds']:.2f} s) relMSE {sm['relmse_pixel']:.3g} / "
                f"block {sm['relmse_block']:.3g}; ratio {run['ratio_pixel']:.2f} / "
                f"{run['ratio_block']:.2f}")
        results["scenes"].append(entry)
    try:
        results["loadavg_end"] = os.getloadavg()
    except OSError:
        pass
    md = markdown(results)
    results["markdown"] = md
    json.dump(results, sys.stdout, indent=2)
    sys.stdout.write("\n")
    log(md)
    if a.markdown:
        with open(a.markdown, "w") as f:
            f.write(md)
    return 0


if __name__ == "__main__":
    sys.exit(main())
