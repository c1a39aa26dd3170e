"""Checks the corpus comparison's noise model against seed-to-seed scatter (USD path).

Each scene is rendered with 2 x MIN_SEEDS seeds at a corpus setting. The seeds are split into
two halves, and the halves are compared with each other the way `corpus/compare.py` compares
ours with Cycles: per 8x8 block, each half's mean with the variance its own seeds give
(`compare.seeds_block_variance`). Both halves render the same scene, so every deviation is
noise: the fraction of blocks beyond K_BLOCK sigma is the block test's false-alarm rate, and
the mean of z^2 tells whether the variance estimate is right (1) or understated (> 1).

    .venv-test/bin/python scripts/corpus_noise_check.py [--setting ci] [--scenes a b ...]
        [--save DIR]
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests",
                                "blender"))
from corpus import compare, refs, render_usd  # noqa: E402
from corpus.settings import settings  # noqa: E402


def half_blocks(images: np.ndarray, R: np.ndarray, judged: np.ndarray):
    """(block means, variance of those means) of one half's seed renders (m, H, W, 3)."""
    b, n = compare.BLOCK, compare.BLOCK * compare.BLOCK
    m = len(images)
    lum = images @ compare.LUMA
    seed_blocks = np.stack([compare._blocks(x, b) for x in lum])
    var_pix = compare._blocks(lum.var(axis=0, ddof=1) / m, b) / n
    return seed_blocks.mean(0), compare.seeds_block_variance(seed_blocks, R, judged, var_pix)


def check(name: str, setting_name: str, seeds: int, save: str | None) -> dict:
    t = time.time()
    path = os.path.join(save, f"{name}_{setting_name}_{seeds}.npy") if save else None
    if path and os.path.exists(path):
        imgs = np.load(path)
    else:
        ir, _ = render_usd.load_ir(name)
        setting = settings(setting_name, refs.tags(name))
        imgs = np.array([render_usd.render_ir(ir, setting, seed=100 + k)["combined"][..., :3]
                         for k in range(seeds)], dtype=np.float64)
        if path:
            np.save(path, imgs)
    r1, r2 = (np.asarray(x, np.float64)[..., :3] for x in refs.load(name))
    R = compare._blocks(0.5 * (r1 + r2) @ compare.LUMA, compare.BLOCK)
    judged = (R > compare.JUDGE_FLOOR * np.percentile(R, 95)) & (R > 0)
    (a, va), (b, vb) = (half_blocks(h, R, judged) for h in (imgs[: seeds // 2],
                                                             imgs[seeds // 2:]))
    diff, var = (a - b)[judged], (va + vb)[judged]
    # A block both halves render identically (an emitter seen directly, no noise) is a z of 0.
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(var > 0, diff / np.sqrt(var), np.where(diff == 0, 0.0, np.inf))
    return {"name": name, "blocks": int(judged.sum()), "z2": float(np.mean(z ** 2)),
            "over": int((np.abs(z) > compare.K_BLOCK).sum()), "max": float(np.abs(z).max()),
            "seconds": time.time() - t}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--setting", default="ci")
    ap.add_argument("--scenes", nargs="*", default=None, help="default: every stage")
    ap.add_argument("--seeds", type=int, default=2 * compare.MIN_SEEDS)
    ap.add_argument("--save", help="keep the renders in this folder and reuse them")
    a = ap.parse_args()
    if a.save:
        os.makedirs(a.save, exist_ok=True)
    names = a.scenes or refs.usd_names()
    rows = []
    for name in names:
        r = check(name, a.setting, a.seeds, a.save)
        rows.append(r)
        print(f"{name:22s} {r['blocks']:4d} blocks  mean z^2 {r['z2']:5.2f}  max |z| "
              f"{r['max']:4.1f}  beyond {compare.K_BLOCK}: {r['over']}  ({r['seconds']:.0f} s)",
              flush=True)
    blocks = sum(r["blocks"] for r in rows)
    over = sum(r["over"] for r in rows)
    images = sum(r["over"] > 0 for r in rows)
    z2 = sum(r["z2"] * r["blocks"] for r in rows) / max(blocks, 1)
    print(f"\n{len(rows)} scenes, {blocks} blocks, {a.seeds // 2} seeds a side: mean z^2 "
          f"{z2:.2f}; blocks beyond {compare.K_BLOCK} sigma: {over} ({over / max(blocks, 1):.2e} "
          f"per block); images with one: {images} of {len(rows)}")


if __name__ == "__main__":
    main()
