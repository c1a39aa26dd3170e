"""Statistical comparison of a render with the corpus' Cycles references (numpy only).

The reference is two renders of different seeds, r1 and r2, and is used as their mean
r = (r1 + r2) / 2. Ours is one render with its ``error`` AOV (the per-pixel standard error the
core estimates), or ``MIN_SEEDS`` or more renders of different seeds (then their mean, and
their scatter as its noise: photon maps and the irradiance cache change with the seed, and
their error is shared by many pixels, so only the seeds' scatter measures it). Every
tolerance comes from these noise floors plus a stated systematic allowance; none comes from
an image mean.

**Per block** (8x8 pixels; luminance Y = 0.2126 R + 0.7152 G + 0.0722 B). For block b with
reference mean R_b and our mean O_b the deviation is d_b = (O_b - R_b) / R_b, judged where
R_b is at least ``JUDGE_FLOOR`` of the 95th percentile of the reference's block means (darker
blocks have no relative deviation worth the name). Its standard error:

    sigma_b^2 = (var(R_b) + var(O_b)) / R_b^2
    var(R_b)  = sum_p (r1_p - r2_p)^2 / 4 / n^2         (Cycles' pixels are independent)
    var(O_b)  = sum_p err_p^2 / n^2                      (one render: the error AOV, its
                                                          channels taken as correlated), or
                max(s_b^2 / m smoothed over the 3x3 neighbouring blocks,
                    s_b^2 / m,
                    sum_p s_p^2 / m / n^2)               (m seeds, s^2 their sample variance:
                                                          m - 1 degrees of freedom per block,
                                                          about 9 (m - 1) once smoothed; a
                                                          block keeps its own where it is
                                                          noisier than its neighbours)

and the block fails when |d_b| > K_BLOCK sigma_b + SYSTEMATIC. The largest |d_b| is reported
in % and in sigmas (d_b / sigma_b), with the worst blocks by |d_b| / tolerance.

**Pooled over the blocks.** A uniform error of scale (a light 2% too bright) hides below each
block's noise at any affordable sample count, but not below the noise of all blocks together:
D = sum_b w_b d_b / sum_b w_b with w_b = 1 / sigma_b^2, whose standard error is
sqrt(sum_b w_b^2 sigma_b^2) / sum_b w_b (with m seeds of ours, at least the sample variance of
the seeds' own D over m, since photon-map noise is correlated across the image). It fails when
|D| > K_POOLED sigma_D + POOLED_SYSTEMATIC. The tolerance, like the others, comes from the
noise floors and a stated allowance.

**Per pixel** (every channel). relMSE = mean (o - r)^2 / (r^2 + eps^2) with eps = ``EPS`` x the
99th percentile of the reference's luminance, against the value pure noise gives,
N = mean (var_o + var_r) / (r^2 + eps^2) (var_r = (r1 - r2)^2 / 4; var_o = err^2 or
the seeds' sample variance over m). It fails when relMSE > K_PIXEL N + SYSTEMATIC^2: more
error than the noise floors explain, beyond a uniform relative bias of SYSTEMATIC.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

LUMA = np.array([0.2126, 0.7152, 0.0722])
BLOCK = 8
#: Sigmas a block may deviate beyond the systematic allowance (about 300 blocks per image:
#: 4.5 sigma leaves a false alarm in ~1 image in 500 with exact noise estimates; the rate
#: measured with the seeds' estimates is what scripts/corpus_noise_check.py prints).
K_BLOCK = 4.5
#: Fewest renders of ours whose scatter may serve as our noise.
MIN_SEEDS = 4
#: Relative systematic allowance per block, and as a uniform bias in the per-pixel test.
SYSTEMATIC = 0.015
#: The per-pixel relMSE may exceed the noise's by this factor (the noise estimates themselves
#: are estimates: m - 1 degrees of freedom per pixel from m seeds, 3 from the error AOV).
K_PIXEL = 1.5
#: The pooled deviation (every judged block, weighted by 1 / sigma_b^2) may differ from 0 by
#: this many of its sigmas beyond POOLED_SYSTEMATIC: a uniform error of scale (a light a few
#: percent too bright) is below any single block's noise but not below the pooled noise.
K_POOLED = 4.5
POOLED_SYSTEMATIC = 0.01
#: Blocks darker than this fraction of the 95th-percentile block are not judged.
JUDGE_FLOOR = 0.02
#: relMSE's regulariser, a fraction of the reference's 99th-percentile luminance.
EPS = 0.02
#: Largest relative rounding of the stored references (make_references.py keeps 7 of the
#: half float's 10 mantissa bits): uniform, so 2^-8 / sqrt(3) rms, taken as the same for
#: every pixel of a block (an emitter seen directly is one value rounded one way).
REF_ROUNDING = 2.0 ** -8


@dataclass
class Block:
    x: int          # block column (pixels x*BLOCK .. x*BLOCK+BLOCK-1, from the left)
    y: int          # block row (from the top)
    ref: float      # reference block mean luminance
    ours: float
    dev: float      # relative deviation (ours - ref) / ref
    sigma: float    # relative standard error of the deviation
    tol: float      # relative tolerance K_BLOCK sigma + SYSTEMATIC

    @property
    def z(self) -> float:
        return self.dev / self.sigma if self.sigma > 0 else float("inf")

    def describe(self) -> str:
        return (f"block ({self.x},{self.y}) [px {self.x * BLOCK}-{self.x * BLOCK + BLOCK - 1}, "
                f"{self.y * BLOCK}-{self.y * BLOCK + BLOCK - 1}]: {100 * self.dev:+.2f}% "
                f"({self.z:+.1f} sigma; tolerance {100 * self.tol:.2f}%), ref {self.ref:.4g} "
                f"ours {self.ours:.4g}")


@dataclass
class Result:
    name: str
    passed: bool
    block_passed: bool
    pixel_passed: bool
    n_blocks: int                 # blocks judged
    n_failed: int                 # blocks beyond their tolerance
    max_dev: float                # largest |relative deviation| of a judged block (signed)
    max_dev_sigma: float          # that block's deviation in sigmas
    max_sigma: float              # largest |deviation| in sigmas of any judged block (signed)
    worst: list = field(default_factory=list)  # blocks by |dev| / tol, worst first
    all_blocks: list = field(default_factory=list, repr=False)  # every judged block
    median_sigma: float = 0.0     # median relative sigma of the judged blocks
    pooled: float = 0.0           # inverse-variance weighted mean block deviation
    pooled_sigma: float = 0.0     # its standard error
    pooled_tol: float = 0.0
    pooled_passed: bool = True
    relmse: float = 0.0
    relmse_noise: float = 0.0     # relMSE the noise floors alone give
    relmse_tol: float = 0.0
    message: str = ""

    def as_dict(self) -> dict:
        d = {k: v for k, v in self.__dict__.items() if k not in ("worst", "all_blocks")}
        d["worst"] = [b.__dict__ | {"z": b.z} for b in self.worst]
        return d

    def row(self) -> str:
        return (f"{self.name:22s} {'pass' if self.passed else 'FAIL'}  pooled {100 * self.pooled:+6.2f}% "
                f"({self.pooled / max(self.pooled_sigma, 1e-30):+5.1f} sd)  block {100 * self.max_dev:+7.2f}% "
                f"({self.max_dev_sigma:+6.1f} sd; worst {self.max_sigma:+6.1f} sd; "
                f"{self.n_failed}/{self.n_blocks} over)  pixel relMSE {self.relmse:.2e} / tol "
                f"{self.relmse_tol:.2e} (noise {self.relmse_noise:.2e})")


def _f64(a) -> np.ndarray:
    a = np.asarray(a, dtype=np.float64)
    if a.ndim != 3 or a.shape[2] < 3:
        raise ValueError(f"expected an (H, W, 3) image, got shape {a.shape}")
    return a[..., :3]


def _blocks(a: np.ndarray, n: int) -> np.ndarray:
    """Means over n x n blocks of a (H, W) array (H, W multiples of n; the rest is cut)."""
    h, w = (a.shape[0] // n) * n, (a.shape[1] // n) * n
    return a[:h, :w].reshape(h // n, n, w // n, n).mean(axis=(1, 3))


def _smooth3(a: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Mean of ``a`` over each block's 3x3 neighbourhood, counting only ``mask``ed blocks."""
    pa = np.pad(np.where(mask, a, 0.0), 1)
    pm = np.pad(mask.astype(np.float64), 1)
    s = np.zeros_like(a)
    c = np.zeros_like(a)
    for dy in range(3):
        for dx in range(3):
            s += pa[dy:dy + a.shape[0], dx:dx + a.shape[1]]
            c += pm[dy:dy + a.shape[0], dx:dx + a.shape[1]]
    return np.where(c > 0, s / np.maximum(c, 1), a)


def seeds_block_variance(seed_blocks: np.ndarray, R: np.ndarray, judged: np.ndarray,
                         var_pix: np.ndarray) -> np.ndarray:
    """Variance of the mean of m seeds' block means ``seed_blocks`` (m, H, W): each block's
    relative sample variance (m - 1 degrees of freedom) smoothed over its 3x3 judged
    neighbours (a block's noise is about its neighbours'), never below the block's own sample
    variance (a block noisier than its neighbours, such as a concave corner whose irradiance
    cache records differ by seed, keeps its own), nor below the independent-pixel value
    ``var_pix``."""
    m = len(seed_blocks)
    own = seed_blocks.var(axis=0, ddof=1) / m
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(judged, own / np.maximum(R, 1e-30) ** 2, 0.0)
    return np.maximum(np.maximum(_smooth3(rel, judged) * R ** 2, own), var_pix)


def compare(name: str, ours, ref, ours_error=None, *, k_block: float = K_BLOCK,
            systematic: float = SYSTEMATIC, k_pixel: float = K_PIXEL, block: int = BLOCK,
            ref_rounding: float = REF_ROUNDING, n_worst: int = 3) -> Result:
    """Compares ``ours`` with the reference ``ref = (r1, r2)``.

    ``ours`` is an (H, W, 3) image with ``ours_error`` its per-pixel standard error (the
    error AOV), or a sequence of at least ``MIN_SEEDS`` images of different seeds
    (``ours_error`` then unused)."""
    r1, r2 = (_f64(x) for x in ref)
    r = 0.5 * (r1 + r2)
    q2 = ref_rounding ** 2 / 3.0  # relative variance of the references' rounding
    var_r = 0.25 * (r1 - r2) ** 2 + q2 * r ** 2
    if isinstance(ours, (tuple, list)):
        seeds = np.stack([_f64(x) for x in ours])
        m = len(seeds)
        if m < MIN_SEEDS:
            raise ValueError(f"{name}: {m} renders of ours; their scatter is our noise floor, "
                             f"which needs at least {MIN_SEEDS}")
        o = seeds.mean(axis=0)
        var_o = seeds.var(axis=0, ddof=1) / m
        pair = True
    else:
        o = _f64(ours)
        if ours_error is None:
            raise ValueError("one render needs its error AOV (ours_error)")
        var_o = _f64(ours_error) ** 2
        pair = False
    if o.shape != r.shape:
        raise ValueError(f"{name}: our image is {o.shape[1]}x{o.shape[0]}, the reference "
                         f"{r.shape[1]}x{r.shape[0]}")
    n2 = float(block * block) ** 2

    # -- blocks (luminance) --
    ly = LUMA
    R = _blocks(r @ ly, block)
    O = _blocks(o @ ly, block)
    # Luminance noise from the luminance of each seed (the channels' noise is correlated).
    var_R = _blocks(0.25 * ((r1 - r2) @ ly) ** 2, block) * block * block / n2 + q2 * R ** 2
    if pair:
        seed_blocks = np.stack([_blocks(x @ ly, block) for x in seeds])
        var_O_pix = _blocks((seeds @ ly).var(axis=0, ddof=1) / m, block) * block * block / n2
    else:
        # The channels' errors taken as fully correlated: SE(Y) = sum_c l_c SE_c.
        var_O_pix = _blocks((_f64(ours_error) @ ly) ** 2, block) * block * block / n2
    floor = JUDGE_FLOOR * float(np.percentile(R, 95)) if R.size else 0.0
    judged = (R > floor) & (R > 0)
    if pair:
        var_O = seeds_block_variance(seed_blocks, R, judged, var_O_pix)
    else:
        var_O = var_O_pix
    with np.errstate(divide="ignore", invalid="ignore"):
        dev = np.where(judged, (O - R) / R, 0.0)
        sigma = np.where(judged, np.sqrt(var_R + var_O) / R, np.inf)
    tol = k_block * sigma + systematic
    over = judged & (np.abs(dev) > tol)

    # -- pooled deviation --
    w = np.where(judged, 1.0 / np.where(judged, sigma, 1.0) ** 2, 0.0)
    if w.sum() > 0:
        wn = w / w.sum()
        pooled = float((wn * dev).sum())
        # Reference noise: independent blocks. Ours: independent blocks, or, with two seeds,
        # at least the spread of the two seeds' pooled deviations (photon-map noise is
        # correlated across the whole image).
        with np.errstate(divide="ignore", invalid="ignore"):
            var_pr = float((wn ** 2 * np.where(judged, var_R / R ** 2, 0.0)).sum())
            var_po = float((wn ** 2 * np.where(judged, var_O / R ** 2, 0.0)).sum())
            if pair:
                per_seed = np.array([(wn * np.where(judged, (b - R) / R, 0.0)).sum()
                                     for b in seed_blocks])
                var_po = max(var_po, float(per_seed.var(ddof=1)) / m)
        pooled_sigma = float(np.sqrt(var_pr + var_po))
    else:
        pooled, pooled_sigma = 0.0, 0.0
    pooled_tol = K_POOLED * pooled_sigma + POOLED_SYSTEMATIC
    pooled_ok = abs(pooled) <= pooled_tol
    blocks = []
    ys, xs = np.nonzero(judged)
    for y, x in zip(ys, xs):
        blocks.append(Block(int(x), int(y), float(R[y, x]), float(O[y, x]), float(dev[y, x]),
                            float(sigma[y, x]), float(tol[y, x])))
    n_blocks = len(blocks)
    if blocks:
        by_dev = max(blocks, key=lambda b: abs(b.dev))
        by_z = max(blocks, key=lambda b: abs(b.z))
        worst = sorted(blocks, key=lambda b: -abs(b.dev) / b.tol)[:n_worst]
        med_sigma = float(np.median([b.sigma for b in blocks]))
    else:
        by_dev = by_z = None
        worst = []
        med_sigma = 0.0

    # -- pixels (every channel) --
    eps = EPS * float(np.percentile(r @ ly, 99))
    eps2 = max(eps, 1e-12) ** 2
    denom = r ** 2 + eps2
    relmse = float(np.mean((o - r) ** 2 / denom))
    noise = float(np.mean((var_o + var_r) / denom))
    relmse_tol = k_pixel * noise + systematic ** 2

    block_ok = not bool(over.any())
    pixel_ok = relmse <= relmse_tol
    res = Result(
        name=name, passed=block_ok and pooled_ok and pixel_ok, block_passed=block_ok, pixel_passed=pixel_ok,
        pooled=pooled, pooled_sigma=pooled_sigma, pooled_tol=pooled_tol, pooled_passed=pooled_ok,
        n_blocks=n_blocks, n_failed=int(over.sum()),
        max_dev=by_dev.dev if by_dev else 0.0, max_dev_sigma=by_dev.z if by_dev else 0.0,
        max_sigma=by_z.z if by_z else 0.0, worst=worst, all_blocks=blocks,
        median_sigma=med_sigma,
        relmse=relmse, relmse_noise=noise, relmse_tol=relmse_tol)
    res.message = _message(res)
    return res


def _message(res: Result) -> str:
    lines = [f"{res.name}: {'pass' if res.passed else 'FAIL'}"]
    lines.append(
        f"  blocks: {res.n_failed} of {res.n_blocks} judged 8x8 blocks beyond tolerance "
        f"(K={K_BLOCK} sigma + {100 * SYSTEMATIC:.1f}%); largest deviation "
        f"{100 * res.max_dev:+.2f}% ({res.max_dev_sigma:+.1f} sigma), largest in sigmas "
        f"{res.max_sigma:+.1f}; median block sigma {100 * res.median_sigma:.2f}%")
    for b in res.worst:
        lines.append("    " + b.describe())
    lines.append(
        f"  pooled over the blocks: {100 * res.pooled:+.2f}% "
        f"({res.pooled / max(res.pooled_sigma, 1e-30):+.1f} sigma of {100 * res.pooled_sigma:.2f}%; "
        f"tolerance {100 * res.pooled_tol:.2f}% = {K_POOLED} sigma + {100 * POOLED_SYSTEMATIC:.1f}%)"
        f"{'' if res.pooled_passed else ': FAIL'}")
    lines.append(
        f"  pixels: relMSE {res.relmse:.3e} against tolerance {res.relmse_tol:.3e} "
        f"(noise floors alone {res.relmse_noise:.3e}; ratio {res.relmse / max(res.relmse_noise, 1e-30):.2f})")
    return "\n".join(lines)
