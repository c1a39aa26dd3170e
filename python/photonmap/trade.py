"""``photonmap trade``: what each setting buys, in error per second.

Renders a scene many times through the Python API, each time changing one setting of a base
preset (photon count, gather k, largest radius, final-gathering rays, irradiance-cache
tolerance, RGBE or f32 photon power, camera samples), plus the four quality presets; measures
the wall time of each render and its error against a reference image; and writes

- ``trade.json``: every run, with its settings, seconds and relMSE (per term when the
  reference has per-term layers);
- ``trade.png``: relMSE against seconds, log-log, one curve per swept setting, presets marked;
- ``trade_terms.png``: the same per term, when the reference has per-term layers.

The error is relMSE = mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2), as
``tests/common/mod.rs`` and ``scripts/equal_time.py`` define it, per pixel and on the means of
8x8-pixel blocks (which keeps a path-traced reference's own noise and our fireflies out of a
measure of low-frequency error).

A Mitsuba reference (``tests/data/references/*.exr``) holds only the beauty (``R,G,B``); our own
multilayer EXR (``photonmap render --quality final``) also holds ``<term>.R/G/B``, and then
every term is compared as well.

    photonmap trade tests/data/scenes/cornell_spheres.json \\
        --reference tests/data/references/cornell_spheres_full.exr --out trade/

Plots need matplotlib: ``pip install photonmap[trade]``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import time
from typing import Any

import numpy as np

#: relMSE's regulariser (tests/common/mod.rs `REL_EPS`, scripts/equal_time.py `EPS`).
EPS = 1e-2
#: Block size of the block relMSE (scripts/equal_time.py `BLOCK`).
BLOCK = 8
#: The error measures of every run, each per term: per pixel, without the worst 0.1% of
#: pixels, on 8x8 block means.
METRICS = ("relmse", "relmse_trimmed", "relmse_block")

#: Swept settings, in plot order: (name, label for the legend).
SWEEPS = (
    ("photons", "photon count (global + caustic, ×)"),
    ("gather", "gather k"),
    ("radius", "max radius (× default)"),
    ("final_gather_rays", "final-gather rays"),
    ("cache_tolerance", "irradiance-cache tolerance"),
    ("photon_power", "photon power (rgbe / f32)"),
    ("spp", "samples per pixel"),
)

#: Values of each sweep. `photons` and `radius` are factors of the base preset's value; the
#: others are the settings' own values. The base value is added when missing.
FULL = {
    "photons": [0.125, 0.25, 0.5, 1, 2, 4, 8],
    "gather": [25, 50, 100, 200, 400],
    "radius": [0.25, 0.5, 1, 2, 4],
    "final_gather_rays": [32, 64, 128, 256, 512, 1024],
    "cache_tolerance": [0.05, 0.1, 0.15, 0.3, 0.6],
    "photon_power": ["rgbe", "f32"],
    "spp": [4, 8, 16, 32, 64],
}
QUICK = {
    "photons": [0.0625, 0.25, 1, 4],
    "gather": [50, 200],
    "radius": [0.5, 2],
    "final_gather_rays": [32, 128],
    "cache_tolerance": [0.3],
    "photon_power": ["rgbe", "f32"],
    "spp": [2, 8],
}
PRESETS_FULL = ("draft", "medium", "high", "final")
PRESETS_QUICK = ("draft", "medium")


class TradeError(Exception):
    """A problem with the inputs (reference, sizes) or a missing optional dependency."""


# ------------------------------------------------------------------------------------------
# Images and error
# ------------------------------------------------------------------------------------------


def read_reference(path: str) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """The beauty (H, W, 3) of an EXR, and its per-term images where it has
    ``<term>.R/G/B`` layers (our multilayer EXR)."""
    import OpenImageIO as oiio

    from . import TERMS

    buf = oiio.ImageBuf(path)
    if buf.has_error:
        raise TradeError(f"cannot read the reference {path}: {buf.geterror()}")
    spec = buf.spec()
    px = buf.get_pixels(oiio.FLOAT)
    if px is None or px.size == 0:
        raise TradeError(f"cannot read the pixels of the reference {path}: {buf.geterror()}")
    px = np.asarray(px, dtype=np.float64).reshape(spec.height, spec.width, spec.nchannels)
    names = list(spec.channelnames)

    def rgb(prefix: str) -> np.ndarray | None:
        want = [f"{prefix}{c}" for c in "RGB"]
        if not all(n in names for n in want):
            return None
        return px[:, :, [names.index(n) for n in want]]

    beauty = rgb("")
    if beauty is None:
        raise TradeError(f"the reference {path} has no R, G, B channels (it has {names})")
    terms = {}
    for t in TERMS:
        img = rgb(f"{t}.")
        if img is not None:
            terms[t] = img
    return beauty, terms


def block_means(img: np.ndarray, b: int = BLOCK) -> np.ndarray:
    h, w, c = img.shape
    hb, wb = h - h % b, w - w % b
    if hb == 0 or wb == 0:
        return img.mean(axis=(0, 1), keepdims=True)
    return img[:hb, :wb].reshape(hb // b, b, wb // b, b, c).mean(axis=(1, 3))


def relmse(x: np.ndarray, ref: np.ndarray) -> float:
    """Mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2)."""
    x = np.asarray(x, dtype=np.float64)
    return float(np.mean((x - ref) ** 2 / (ref**2 + EPS)))


def relmse_trimmed(x: np.ndarray, ref: np.ndarray) -> float:
    """relMSE without the worst 0.1% of pixels (at least one), as scripts/equal_time.py: the
    error without the few fireflies that dominate a per-pixel relMSE."""
    x = np.asarray(x, dtype=np.float64)
    per_pixel = np.sort(((x - ref) ** 2 / (ref**2 + EPS)).mean(axis=2).ravel())[::-1]
    return float(per_pixel[max(1, per_pixel.size // 1000):].mean())


def errors(out: dict, ref: np.ndarray, ref_terms: dict[str, np.ndarray]) -> dict[str, dict]:
    """relMSE per pixel, without the worst 0.1% of pixels, and on block means, of the combined
    image and of each term that the reference holds."""
    pairs = {"combined": (out["combined"], ref)}
    pairs.update({t: (out[t], img) for t, img in ref_terms.items()})
    return {
        "relmse": {t: relmse(x, r) for t, (x, r) in pairs.items()},
        "relmse_trimmed": {t: relmse_trimmed(x, r) for t, (x, r) in pairs.items()},
        "relmse_block": {t: relmse(block_means(x), block_means(r)) for t, (x, r) in pairs.items()},
    }


# ------------------------------------------------------------------------------------------
# Runs
# ------------------------------------------------------------------------------------------


def sized_scene(path: str, width: int, height: int):
    """The scene of `path` (JSON IR or USD) with its film set to width x height."""
    import photonmap

    scene = photonmap.load_scene(path)
    ir = json.loads(scene.to_json())
    ir.setdefault("film", {})
    ir["film"]["width"], ir["film"]["height"] = int(width), int(height)
    return photonmap.Scene.from_json(json.dumps(ir))


def base_settings(preset: str, filter: str = "box") -> dict[str, Any]:
    """The render keywords of a preset (as ``photonmap.preset``), with the photon power and
    the pixel filter."""
    import photonmap

    p = photonmap.preset(preset)
    keep = ("spp", "photons", "caustic_photons", "volume_photons", "gather",
            "final_gather_rays", "irradiance_cache", "cache_tolerance")
    s = {"quality": preset, **{k: p[k] for k in keep}, "filter": filter}
    s["photon_power"] = "rgbe"
    return s


def sweep_settings(base: dict, name: str, value: Any, base_radius: float) -> dict:
    """The base settings with one setting changed."""
    s = dict(base)
    if name == "photons":
        for k in ("photons", "caustic_photons", "volume_photons"):
            s[k] = max(1, int(round(base[k] * value)))
    elif name == "radius":
        s["radius"] = base_radius * value
    else:
        s[name] = value
    return s


def is_base_value(name: str, value: Any, base: dict) -> bool:
    if name in ("photons", "radius"):
        return value == 1
    return value == base[name]


def render_once(scene, settings: dict, seed: int, threads: int) -> tuple[dict, float, float]:
    """The render's output, its wall seconds and the CPU seconds of all the process's threads
    (the renderer's workers included)."""
    import photonmap

    t0, c0 = time.perf_counter(), time.process_time()
    out = photonmap.render(scene, seed=seed, threads=threads, **settings)
    return out, time.perf_counter() - t0, time.process_time() - c0


def summarise_stats(stats: dict) -> dict:
    maps = {
        m["map"]: {k: m.get(k) for k in ("stored", "emitted", "memory_bytes", "bytes_per_photon",
                                          "max_radius", "seconds")}
        for m in stats.get("photon_maps", []) if m.get("built")
    }
    return {
        "seconds_per_pass": stats.get("seconds", {}),
        "photon_maps": maps,
        "irradiance_cache_records": stats.get("irradiance_cache_records"),
        "memory_estimate_bytes": stats.get("memory_estimate", {}).get("total_bytes"),
    }


def measure(scene, settings: dict, seeds: list[int], threads: int, ref, ref_terms) -> dict:
    """Renders once per seed; the error is the mean over seeds, the time the median."""
    secs, cpus, errs, stats = [], [], [], None
    for seed in seeds:
        out, s, c = render_once(scene, settings, seed, threads)
        errs.append(errors(out, ref, ref_terms))
        secs.append(s)
        cpus.append(c)
        stats = out["stats"]
    mean = {m: {t: float(np.mean([e[m][t] for e in errs])) for t in errs[0][m]}
            for m in METRICS}
    return {
        "seconds": float(np.median(secs)),
        "seconds_each": secs,
        "cpu_seconds": float(np.median(cpus)),
        "cpu_seconds_each": cpus,
        **mean,
        "relmse_each": [e["relmse"]["combined"] for e in errs],
        "stats": summarise_stats(stats),
    }


def log(msg: str, quiet: bool) -> None:
    if not quiet:
        print(msg, file=sys.stderr, flush=True)


def run(args: argparse.Namespace) -> dict:
    import photonmap

    ref, ref_terms = read_reference(args.reference)
    rh, rw = ref.shape[:2]
    width = args.width or rw
    height = args.height or rh
    if (width, height) != (rw, rh):
        raise TradeError(
            f"the reference {args.reference} is {rw}x{rh}, not {width}x{height}: render at the "
            f"reference's size (omit --width/--height)"
        )
    scene = sized_scene(args.scene, width, height)
    if args.base is None:
        args.base = "draft" if args.quick else "medium"
    base = base_settings(args.base, args.filter)
    values = QUICK if args.quick else FULL
    presets = PRESETS_QUICK if args.quick else PRESETS_FULL
    seeds = [args.seed + i for i in range(args.repeats)]
    runs: list[dict] = []

    log(f"trade: {args.scene} at {width}x{height}, base preset {args.base}, seeds {seeds}, "
        f"reference {args.reference} (terms: {', '.join(ref_terms) or 'beauty only'})",
        args.quiet)

    def record(sweep: str, value: Any, settings: dict, label: str) -> dict:
        r = measure(scene, settings, seeds, args.threads, ref, ref_terms)
        entry = {"sweep": sweep, "value": value, "label": label, "params": settings, **r}
        runs.append(entry)
        log(f"  {entry['sweep']:>18} {label:>14}: {r['seconds']:8.2f} s ({r['cpu_seconds']:.2f} "
            f"s CPU)  relMSE {r['relmse']['combined']:.3e}  trimmed "
            f"{r['relmse_trimmed']['combined']:.3e}  block {r['relmse_block']['combined']:.3e}",
            args.quiet)
        return entry

    # One small render first, unmeasured, so that the base does not pay for cold caches.
    warm_up = {"quality": "draft", "spp": 1, "filter": args.filter, "photons": 2000,
               "caustic_photons": 2000, "volume_photons": 2000, "final_gather_rays": 8}
    render_once(scene, warm_up, args.seed, args.threads)
    base_run = record("base", args.base, dict(base), f"{args.base} (base)")
    radii = [m["max_radius"] for m in base_run["stats"]["photon_maps"].values()
             if m.get("max_radius")]
    base_radius = float(radii[0]) if radii else 0.0
    for name, _ in SWEEPS:
        if name not in args.sweeps:
            continue
        vals = list(values[name])
        if name == "radius" and base_radius <= 0.0:
            continue  # no photon map: the radius changes nothing
        for v in vals:
            if is_base_value(name, v, base):
                continue
            settings = sweep_settings(base, name, v, base_radius)
            label = f"×{v:g}" if name in ("photons", "radius") else str(v)
            record(name, v, settings, label)
    for q in presets:
        record("preset", q, base_settings(q, args.filter), q)

    return {
        "scene": os.path.abspath(args.scene),
        "reference": os.path.abspath(args.reference),
        "width": width,
        "height": height,
        "seeds": seeds,
        "threads": args.threads,
        "base_preset": args.base,
        "base_settings": base,
        "base_radius": base_radius,
        "quick": bool(args.quick),
        "clock": args.clock,
        "filter": args.filter,
        "terms_compared": ["combined", *ref_terms.keys()],
        "metric": {
            "relmse": "mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2), "
                      "mean over seeds",
            "relmse_trimmed": "the same without the worst 0.1% of pixels (at least one)",
            "relmse_block": f"the same on {BLOCK}x{BLOCK}-pixel block means",
            "seconds": "wall time of photonmap.render (median over seeds)",
            "cpu_seconds": "CPU time of all threads during photonmap.render (median over seeds)",
        },
        "photonmap_version": photonmap.__version__,
        "machine": {
            "cpus": os.cpu_count(),
            "load_average": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
            "platform": platform.platform(),
        },
        "runs": runs,
    }


# ------------------------------------------------------------------------------------------
# Plots
# ------------------------------------------------------------------------------------------


def _pyplot():
    try:
        import matplotlib
    except ImportError:
        raise TradeError(
            "the trade plots need matplotlib: pip install 'photonmap[trade]' "
            "(or pip install matplotlib)"
        ) from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _curves(result: dict) -> list[tuple[str, str, list[dict]]]:
    """(sweep, legend label, runs in value order, base included) per swept setting."""
    runs = result["runs"]
    base = next(r for r in runs if r["sweep"] == "base")
    out = []
    for name, label in SWEEPS:
        pts = [r for r in runs if r["sweep"] == name]
        if not pts:
            continue
        base_pt = dict(base, value=1 if name in ("photons", "radius")
                       else result["base_settings"][name])
        base_pt["label"] = "×1" if name in ("photons", "radius") else str(base_pt["value"])
        pts = pts + [base_pt]
        if name == "photon_power":
            pts.sort(key=lambda r: ["rgbe", "f32"].index(r["value"]))
        else:
            pts.sort(key=lambda r: float(r["value"]))
        out.append((name, label, pts))
    return out


def _panel(ax, result: dict, metric: str, term: str, title: str, annotate: bool) -> None:
    import matplotlib.pyplot as plt

    clock = "cpu_seconds" if result.get("clock") == "cpu" else "seconds"

    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, (name, label, pts) in enumerate(_curves(result)):
        xs = [p[clock] for p in pts]
        # An exact zero (a term equal to the reference) has no place on log axes: a gap.
        ys = [p[metric][term] if p[metric][term] > 0 else math.nan for p in pts]
        c = colours[i % len(colours)]
        ax.plot(xs, ys, "-o", color=c, label=label, ms=4, lw=1.4, alpha=0.9)
        if annotate:
            for p, x, y in zip(pts, xs, ys):
                if p["sweep"] == "base":
                    continue  # the base is the square
                ax.annotate(p["label"], (x, y), xytext=(3, 3), textcoords="offset points",
                            fontsize=6.5, color=c)
    base = next(r for r in result["runs"] if r["sweep"] == "base")
    ax.plot([base[clock]], [base[metric][term]], "s", color="black", ms=7, mfc="none",
            label=f"base ({result['base_preset']})")
    presets = [r for r in result["runs"] if r["sweep"] == "preset"]
    if presets:
        ax.plot([p[clock] for p in presets], [p[metric][term] for p in presets], "*",
                color="black", ms=12, label="presets", zorder=5)
        for p in presets:
            ax.annotate(p["value"], (p[clock], p[metric][term]), xytext=(6, -10),
                        textcoords="offset points", fontsize=9, fontweight="bold")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("CPU time of the render, all threads (s)" if clock == "cpu_seconds"
                  else "wall time of the render (s)")
    ax.set_ylabel({"relmse_block": "relMSE of 8×8 block means",
                   "relmse_trimmed": "relMSE, worst 0.1% of pixels dropped"}.get(
                       metric, "relMSE (per pixel)"))
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.25)


def plot(result: dict, out_dir: str) -> list[str]:
    """Writes trade.png (combined image) and, with a per-term reference, trade_terms.png."""
    plt = _pyplot()
    scene = os.path.basename(result["scene"])
    seeds = result["seeds"]
    threads = result["threads"] or os.cpu_count()
    sub = (f"{scene}, {result['width']}×{result['height']}, base {result['base_preset']}, "
           f"{len(seeds)} seed{'s' if len(seeds) > 1 else ''}, {threads} thread"
           f"{'s' if threads != 1 else ''}")
    paths = []
    fig, axes = plt.subplots(1, 3, figsize=(21, 7), constrained_layout=True)
    _panel(axes[0], result, "relmse", "combined", "per-pixel relMSE, combined image", True)
    _panel(axes[1], result, "relmse_trimmed", "combined",
           "per-pixel relMSE without the worst 0.1% of pixels (fireflies)", True)
    _panel(axes[2], result, "relmse_block", "combined",
           "8×8 block relMSE (low-frequency error: bias, blur)", True)
    axes[0].legend(fontsize=8, loc="best")
    fig.suptitle(f"Speed and accuracy: one setting changed at a time around the base preset\n{sub}",
                 fontsize=11)
    p = os.path.join(out_dir, "trade.png")
    fig.savefig(p, dpi=110)
    plt.close(fig)
    paths.append(p)

    # Terms that no run got wrong (zero in the scene, as `volume` without media) are left out.
    terms = [t for t in result["terms_compared"] if t != "combined"
             and any(r["relmse"][t] > 0 for r in result["runs"])]
    if terms:
        n = len(terms)
        cols = min(3, n)
        rows = math.ceil(n / cols)
        fig, axes = plt.subplots(rows, cols, figsize=(5.5 * cols, 4.5 * rows),
                                 constrained_layout=True, squeeze=False)
        for ax, t in zip(axes.flat, terms):
            _panel(ax, result, "relmse", t, f"{t}: per-pixel relMSE", False)
        for ax in list(axes.flat)[n:]:
            ax.set_visible(False)
        axes.flat[0].legend(fontsize=7, loc="best")
        fig.suptitle(f"relMSE per term against seconds\n{sub}", fontsize=11)
        p = os.path.join(out_dir, "trade_terms.png")
        fig.savefig(p, dpi=100)
        plt.close(fig)
        paths.append(p)
    return paths


# ------------------------------------------------------------------------------------------
# Command line
# ------------------------------------------------------------------------------------------


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(
        prog="photonmap trade",
        description="Render a scene with one setting changed at a time around a base preset, "
        "and the presets; measure seconds and relMSE against a reference; write trade.json and "
        "log-log plots of relMSE against seconds.",
    )
    ap.add_argument("scene", nargs="?", help="scene: .json scene IR or a USD stage")
    ap.add_argument("--reference", metavar="REF.exr",
                    help="reference image: a beauty-only EXR (Mitsuba) or our multilayer EXR "
                    "(then every term is compared too); renders are made at its size")
    ap.add_argument("--out", default="trade", metavar="DIR",
                    help="output directory for trade.json and the plots (default: ./trade)")
    ap.add_argument("--quick", action="store_true",
                    help="a small sweep around draft (4 photon counts, 1-2 values of the "
                    "others, presets draft and medium), for tests")
    ap.add_argument("--base", choices=("draft", "medium", "high", "final"),
                    help="the preset swept around (default: medium; draft with --quick)")
    ap.add_argument("--width", type=int, help="image width (must match the reference)")
    ap.add_argument("--height", type=int, help="image height (must match the reference)")
    ap.add_argument("--seed", type=int, default=1, help="first seed (default 1)")
    ap.add_argument("--repeats", type=int, default=1,
                    help="seeds per setting (seed, seed+1, ...): relMSE is averaged, the time "
                    "is the median (default 1)")
    ap.add_argument("--threads", type=int, default=0, help="render threads (0 = all cores)")
    ap.add_argument("--filter", choices=("box", "tent", "gaussian"), default="box",
                    help="pixel filter of the renders (default box: the Mitsuba references of "
                    "tests/data/references use a one-pixel box; a wider filter than the "
                    "reference's blurs edges into a large per-pixel error)")
    ap.add_argument("--clock", choices=("wall", "cpu"), default="wall",
                    help="time axis of the plots: wall seconds (default) or CPU seconds of all "
                    "threads (steadier on a loaded machine); both are in trade.json")
    ap.add_argument("--sweeps", default=",".join(n for n, _ in SWEEPS), metavar="NAMES",
                    help="comma-separated settings to sweep (default: all of "
                    f"{', '.join(n for n, _ in SWEEPS)}); 'none' renders the base and the "
                    "presets only")
    ap.add_argument("--replot", metavar="trade.json",
                    help="redraw the plots of an earlier run (e.g. with another --clock) into "
                    "--out, without rendering")
    ap.add_argument("--no-plot", action="store_true", help="write trade.json only")
    ap.add_argument("--quiet", action="store_true", help="no progress on stderr")
    return ap


def main(argv: list[str] | None = None) -> int:
    ap = parser()
    args = ap.parse_args(argv)
    if args.repeats < 1:
        ap.error("--repeats must be at least 1")
    names = [n for n, _ in SWEEPS]
    args.sweeps = [] if args.sweeps == "none" else [n.strip() for n in args.sweeps.split(",")]
    unknown = [n for n in args.sweeps if n not in names]
    if unknown:
        ap.error(f"unknown sweep {', '.join(unknown)} (expected {', '.join(names)} or none)")
    if args.replot:
        try:
            with open(args.replot) as f:
                result = json.load(f)
            result["clock"] = args.clock
            os.makedirs(args.out, exist_ok=True)
            written = plot(result, args.out)
        except (OSError, ValueError, KeyError, TradeError) as e:
            print(f"photonmap trade: error: {args.replot}: {e}", file=sys.stderr)
            return 1
        log("trade: wrote " + ", ".join(written), args.quiet)
        return 0
    if not args.scene or not args.reference:
        ap.error("a SCENE and --reference REF.exr are needed (or --replot trade.json)")
    try:
        if not args.no_plot:
            _pyplot()  # fail before rendering when matplotlib is missing
        for p in (args.scene, args.reference):
            if not os.path.exists(p):
                raise TradeError(f"no such file: {p}")
        result = run(args)
        os.makedirs(args.out, exist_ok=True)
        path = os.path.join(args.out, "trade.json")
        with open(path, "w") as f:
            json.dump(result, f, indent=1)
        written = [path]
        if not args.no_plot:
            written += plot(result, args.out)
    except TradeError as e:
        print(f"photonmap trade: error: {e}", file=sys.stderr)
        return 1
    log("trade: wrote " + ", ".join(written), args.quiet)
    return 0


if __name__ == "__main__":
    sys.exit(main())
