#!/usr/bin/env python3
"""The Cycles parity corpus (tests/blender/corpus/) through both paths, at any quality.

    .venv-test/bin/python scripts/corpus_compare.py --quality high
    .venv-test/bin/python scripts/corpus_compare.py --quality ci --paths usd --only area_back

Run it with the package's venv (photonmap, usd_delegate, OpenImageIO, matplotlib). It renders
every corpus scene

- through the Blender add-on: tests/blender/corpus/render_addon.py in the bpy venv
  (``--bpy-python``, default .venv-bpy/bin/python), with the extension zip ``--zip`` (built by
  scripts/build_blender_extension.py when not given);
- through the USD path: each committed stage (Blender's own USD export) read by
  ``usd_delegate`` and rendered by ``photonmap.render`` in this process;

with ``--seeds`` (default 1 2 3 4: their scatter is our own noise floor, photon-map noise
included, and needs at least four; one seed uses the error AOV), compares each with its two
Cycles references (tests/blender/corpus/compare.py; through USD with the references times the known factor of
Blender's exporter bugs, the 6500 K tint and the sun's S/4, where one holds:
tests/blender/corpus/usd_export.py) and prints per scene and path the largest block deviation
(% and sigmas), the number of blocks beyond tolerance, and the per-pixel relMSE against its
tolerance. Writes ``--json`` (every figure) and a contact sheet ``--sheet`` (default
docs/corpus_contact_sheet.jpg): per scene Cycles | ours through the add-on | its block
deviations | ours through USD | its block deviations, all tone-mapped with the Cycles
image's exposure (the USD render divided by the luminance of its factor); deviations in %
from blue (-10%) through white to red (+10%), blocks not judged in grey, blocks beyond
tolerance outlined in black.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "blender"))

import numpy as np  # noqa: E402

from corpus import compare, expected, refs  # noqa: E402
from corpus.settings import SETTINGS, settings  # noqa: E402

PATHS = ("addon", "usd")


def build_zip(out: Path) -> str:
    res = subprocess.run([sys.executable, str(ROOT / "scripts" / "build_blender_extension.py"),
                          "--out", str(out)], check=True, capture_output=True, text=True)
    return res.stdout.strip().splitlines()[-1]


def render_addon(a, names, work: Path) -> None:
    zip_path = a.zip or build_zip(work / "ext")
    cmd = [a.bpy_python, str(ROOT / "tests" / "blender" / "corpus" / "render_addon.py"),
           "--zip", zip_path, "--setting", a.quality, "--out", str(work / "addon"),
           "--seeds", *map(str, a.seeds), "--only", *names]
    if a.nice:
        cmd = ["nice", "-n", str(a.nice)] + cmd
    subprocess.run(cmd, check=True)


def render_usd(a, names, work: Path) -> None:
    from corpus import render_usd as ru
    from corpus.render_addon import save

    if a.nice:
        os.nice(a.nice)
    (work / "usd").mkdir(parents=True, exist_ok=True)
    for name in names:
        setting = settings(a.quality, refs.tags(name))
        for seed in a.seeds:
            out = ru.render_stage(name, setting, seed)
            save(str(work / "usd" / f"{name}_s{seed}.npz"), out)
            print(f"usd {name} seed {seed}: {out['seconds']:.1f}s", flush=True)


def load_ours(work: Path, path: str, name: str, seeds) -> dict | None:
    files = [work / path / f"{name}_s{s}.npz" for s in seeds]
    if not all(f.exists() for f in files):
        return None
    data = [np.load(f) for f in files]
    d = {"images": [x["combined"] for x in data], "error": data[0]["error"],
         "seconds": [float(x["seconds"]) for x in data],
         "warnings": json.loads(str(data[0]["warnings"]))}
    return d


def compare_one(name: str, ours: dict, ref) -> compare.Result:
    if len(ours["images"]) >= 2:
        return compare.compare(name, tuple(ours["images"]), ref)
    return compare.compare(name, ours["images"][0], ref, ours["error"])


def tone(img: np.ndarray, scale: float) -> np.ndarray:
    return np.clip(np.clip(img * scale, 0, None) ** (1 / 2.2), 0, 1)


def block_map(res: compare.Result, ours: np.ndarray, ref, shape) -> np.ndarray:
    """RGB image of the block deviations (the comparison's own figures)."""
    import matplotlib

    h, w = shape[:2]
    nb_y, nb_x = h // compare.BLOCK, w // compare.BLOCK
    dev = np.full((nb_y, nb_x), np.nan)
    over = np.zeros((nb_y, nb_x), bool)
    for b in res.all_blocks:
        dev[b.y, b.x] = b.dev
        over[b.y, b.x] = abs(b.dev) > b.tol
    cmap = matplotlib.colormaps["coolwarm"]
    rgb = cmap(np.clip(np.nan_to_num(dev) / 0.2 + 0.5, 0, 1))[..., :3]
    rgb[np.isnan(dev)] = 0.5
    img = np.repeat(np.repeat(rgb, compare.BLOCK, 0), compare.BLOCK, 1)
    for y, x in zip(*np.nonzero(over)):
        y0, x0 = y * compare.BLOCK, x * compare.BLOCK
        img[y0, x0:x0 + compare.BLOCK] = img[y0 + compare.BLOCK - 1, x0:x0 + compare.BLOCK] = 0
        img[y0:y0 + compare.BLOCK, x0] = img[y0:y0 + compare.BLOCK, x0 + compare.BLOCK - 1] = 0
    return img


def contact_sheet(rows: list, path: str, quality: str, per_row: int = 2) -> None:
    """Every scene as Cycles | ours (add-on) | blocks | ours (USD) | blocks, ``per_row``
    scenes side by side, each panel at the images' own resolution."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cols = ["Cycles", "ours: add-on", "add-on: blocks", "ours: USD", "USD: blocks"]
    h, w = rows[0]["ref"].shape[:2]
    dpi = 100
    gap, label_h, title_h = 6, 26, 30       # pixels
    ncol = per_row * len(cols)
    nrow = (len(rows) + per_row - 1) // per_row
    W = ncol * w + (per_row - 1) * gap
    H = title_h + nrow * (h + label_h)
    fig = plt.figure(figsize=(W / dpi, H / dpi), dpi=dpi)
    fig.text(0.5, 1 - 6 / H, f"Cycles parity corpus, PhotonMap at '{quality}' against Cycles "
             f"5.0 (box filter 1 px). Block deviations: blue -10% .. white .. red +10%, black "
             f"outline: beyond tolerance, grey: not judged", fontsize=7, ha="center", va="top")
    for i, row in enumerate(rows):
        r, c0 = divmod(i, per_row)
        y_top = title_h + r * (h + label_h) + label_h
        x0 = c0 * (len(cols) * w + gap)
        fig.text(x0 / W + 0.001, 1 - (y_top - label_h + 2) / H,
                 f"{row['name']}", fontsize=7, weight="bold", va="top")
        for j, col in enumerate(cols):
            ax = fig.add_axes([(x0 + j * w) / W, 1 - (y_top + h) / H, w / W, h / H])
            ax.set_xticks([])
            ax.set_yticks([])
            for sp in ax.spines.values():
                sp.set_linewidth(0.3)
            img = row["panels"].get(col)
            if img is None:
                ax.set_facecolor((0.15, 0.15, 0.15))
                ax.text(0.5, 0.5, row["missing"].get(col, "-"), color="w", ha="center",
                        va="center", fontsize=6, transform=ax.transAxes)
            else:
                ax.imshow(img, interpolation="nearest", aspect="auto")
            label = row["labels"].get(col) or col
            fig.text((x0 + j * w + w / 2) / W, 1 - (y_top - 2) / H, label, fontsize=5.2,
                     ha="center", va="bottom")
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quality", default="high", choices=sorted(SETTINGS),
                    help="corpus setting (tests/blender/corpus/settings.py)")
    ap.add_argument("--paths", nargs="+", default=list(PATHS), choices=PATHS)
    ap.add_argument("--only", nargs="*", default=None, help="scene names (default: all)")
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4])
    ap.add_argument("--zip", default=None, help="the Blender extension zip (default: build it)")
    ap.add_argument("--bpy-python", default=str(ROOT / ".venv-bpy" / "bin" / "python"))
    ap.add_argument("--work", default=None, help="folder for our renders (default: a temp dir)")
    ap.add_argument("--reuse", action="store_true", help="skip renders already in --work")
    ap.add_argument("--nice", type=int, default=10, help="niceness of the renders (0: none)")
    ap.add_argument("--json", default=None, help="write every figure here")
    ap.add_argument("--sheet", default=str(ROOT / "docs" / "corpus_contact_sheet.jpg"))
    a = ap.parse_args()
    work = Path(a.work or tempfile.mkdtemp(prefix="photonmap-corpus-"))
    work.mkdir(parents=True, exist_ok=True)
    names = a.only or refs.names()
    usd_names = [n for n in names if n in set(refs.usd_names())]

    def todo(path, group):
        if not a.reuse:
            return list(group)
        return [n for n in group if load_ours(work, path, n, a.seeds) is None]

    t0 = time.time()
    if "addon" in a.paths and todo("addon", names):
        render_addon(a, todo("addon", names), work)
    if "usd" in a.paths and todo("usd", usd_names):
        render_usd(a, todo("usd", usd_names), work)

    man = refs.manifest()["scenes"]
    results = {}
    rows = []
    print(f"\ncorpus at '{a.quality}' ({settings(a.quality)}), seeds {a.seeds}; block tolerance "
          f"{compare.K_BLOCK} sigma + {100 * compare.SYSTEMATIC:.1f}%, pixel tolerance "
          f"{compare.K_PIXEL} x noise + {compare.SYSTEMATIC}^2")
    header = (f"{'scene':22s} {'path':5s} {'result':6s} {'max block dev':>13s} {'sigma':>7s} "
              f"{'max sigma':>9s} {'over':>7s} {'relMSE':>9s} {'tolerance':>9s} {'noise':>9s} "
              f"{'secs':>6s}  expected")
    print(header)
    print("-" * len(header))
    for name in names:
        ref = refs.load(name)
        scale = 0.75 / max(float(np.percentile(0.5 * (ref[0] + ref[1]) @ compare.LUMA, 90)),
                           1e-6)
        row = {"name": name, "ref": ref[0], "panels": {"Cycles": tone(0.5 * (ref[0] + ref[1]),
                                                                    scale)},
               "labels": {}, "missing": {}}
        results[name] = {"description": man[name]["description"]}
        for path in PATHS:
            col, bcol = ("ours: add-on", "add-on: blocks") if path == "addon" else \
                ("ours: USD", "USD: blocks")
            ours = load_ours(work, path, name, a.seeds) if path in a.paths else None
            if ours is None:
                why = man[name].get("no_usd") if path == "usd" else None
                row["missing"][col] = row["missing"][bcol] = \
                    "no USD stage" if why else "not rendered"
                if why:
                    results[name][path] = {"skipped": why}
                continue
            factor, why = np.ones(3), None
            ref_p = ref
            if path == "usd":
                from corpus import usd_export

                ref_p, factor, why = usd_export.corrected(refs.usd_path(name), ref)
            res = compare_one(name, ours, ref_p)
            known = expected.reason(path, name)
            results[name][path] = dict(res.as_dict(), seconds=ours["seconds"],
                                       warnings=ours["warnings"], expected_failure=known,
                                       reference_factor=factor.tolist(), factor_reason=why)
            mean = np.mean(ours["images"], axis=0)
            row["panels"][col] = tone(mean, scale / max(float(factor @ compare.LUMA), 1e-6))
            row["panels"][bcol] = block_map(res, mean, ref_p, mean.shape)
            row["labels"][bcol] = (f"{'pass' if res.passed else 'FAIL'}: max {100 * res.max_dev:+.1f}% "
                                   f"({res.max_dev_sigma:+.1f}sd) pool {100 * res.pooled:+.1f}% "
                                   f"px {res.relmse / res.relmse_tol:.2f}xtol")
            print(f"{name:22s} {path:5s} {'pass' if res.passed else 'FAIL':6s} "
                  f"{100 * res.max_dev:+12.2f}% {res.max_dev_sigma:+7.1f} {res.max_sigma:+9.1f} "
                  f"{res.n_failed:3d}/{res.n_blocks:<3d} {res.relmse:9.2e} {res.relmse_tol:9.2e} "
                  f"{res.relmse_noise:9.2e} {sum(ours['seconds']):6.1f}  "
                  f"{'xfail: ' + known if known else ''}")
        rows.append(row)
    print(f"\n{time.time() - t0:.0f}s in all; our renders in {work}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"quality": a.quality, "settings": settings(a.quality), "seeds": a.seeds,
                       "k_block": compare.K_BLOCK, "systematic": compare.SYSTEMATIC,
                       "k_pixel": compare.K_PIXEL, "scenes": results}, f, indent=1)
        print("wrote", a.json)
    if a.sheet and rows:
        contact_sheet(rows, a.sheet, a.quality)
        print("wrote", a.sheet)


if __name__ == "__main__":
    main()
