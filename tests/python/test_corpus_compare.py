"""The corpus comparison (tests/blender/corpus/compare.py) on synthetic images of known noise:
it passes images that differ by noise only, and fails a small uniform bias (pooled over the
blocks), a local defect (per block) and a colour shift (per pixel) once the noise is low
enough to see them."""

import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blender"))
from corpus import compare  # noqa: E402

H, W = 120, 160


def truth():
    y, x = np.mgrid[0:H, 0:W] / np.array([H, W])[:, None, None]
    base = 0.2 + 0.8 * np.exp(-((x - 0.4) ** 2 + (y - 0.3) ** 2) / 0.1)
    img = np.stack([base, 0.8 * base, 0.6 * base + 0.05], -1)
    img[60:100, 20:60] *= 0.3  # a shadow
    return img


def noisy(rng, t, rel):
    return t * (1 + rel * rng.standard_normal(t.shape))


def test_noise_alone_passes():
    rng = np.random.default_rng(1)
    t = truth()
    for _ in range(20):
        ref = (noisy(rng, t, 0.05), noisy(rng, t, 0.05))
        ours = noisy(rng, t, 0.2)
        r = compare.compare("noise", ours, ref, ours_error=0.2 * t)
        assert r.passed, r.message
        assert abs(r.max_sigma) < compare.K_BLOCK
        seeds = [noisy(rng, t, 0.2) for _ in range(compare.MIN_SEEDS)]
        r2 = compare.compare("noise seeds", seeds, ref)
        assert r2.passed, r2.message


@pytest.mark.parametrize("pair", [False, True])
def test_a_two_percent_bias_fails_by_the_pooled_deviation(pair):
    rng = np.random.default_rng(2)
    t = truth()
    ref = (noisy(rng, t, 0.01), noisy(rng, t, 0.01))
    for bias, should_pass in ((0.0, True), (0.02, False)):
        if pair:
            ours = [noisy(rng, t, 0.02) * (1 + bias) for _ in range(compare.MIN_SEEDS)]
            r = compare.compare("bias", ours, ref)
        else:
            r = compare.compare("bias", noisy(rng, t, 0.02) * (1 + bias), ref, 0.02 * t)
        assert r.passed == should_pass, r.message
    # Below every block's tolerance, but not below the pooled noise of all blocks.
    assert r.block_passed and not r.pooled_passed
    assert 0.015 < r.pooled < 0.025, r.message


def test_a_local_defect_is_named():
    rng = np.random.default_rng(3)
    t = truth()
    ref = (noisy(rng, t, 0.03), noisy(rng, t, 0.03))
    ours = noisy(rng, t, 0.05)
    ours[16:32, 96:112] *= 0.85
    r = compare.compare("defect", ours, ref, 0.05 * t)
    assert not r.block_passed
    assert r.n_failed >= 3
    worst = r.worst[0]
    assert 12 <= worst.x <= 13 and 2 <= worst.y <= 3, r.message
    assert "block (1" in r.message and "-15.0" in r.message or worst.dev < -0.1


def test_a_colour_shift_fails_per_pixel():
    rng = np.random.default_rng(4)
    t = truth()
    ref = (noisy(rng, t, 0.01), noisy(rng, t, 0.01))
    tint = np.array([1.05, 0.985, 1.04])  # luminance almost unchanged
    r = compare.compare("tint", noisy(rng, t, 0.01) * tint, ref, 0.01 * t)
    assert abs(r.max_dev) < 0.02
    assert not r.pixel_passed, r.message


def test_dark_blocks_are_not_judged():
    rng = np.random.default_rng(5)
    t = truth()
    t[:40] = 1e-5
    ref = (noisy(rng, t, 0.01), noisy(rng, t, 0.01))
    ours = noisy(rng, t, 0.01)
    ours[:40] *= 3
    r = compare.compare("dark", ours, ref, 0.01 * t)
    assert r.block_passed and r.n_blocks == (H - 40) // 8 * (W // 8)


def test_fewer_seeds_than_the_noise_model_needs_are_refused():
    rng = np.random.default_rng(5)
    t = truth()
    ref = (noisy(rng, t, 0.01), noisy(rng, t, 0.01))
    with pytest.raises(ValueError, match="at least"):
        compare.compare("two", [noisy(rng, t, 0.02) for _ in range(2)], ref)


def test_a_block_noisier_than_its_neighbours_keeps_its_own_noise():
    """Noise shared by a block's pixels (an irradiance cache record differs by seed) in one
    block only: with the neighbours' noise alone the block would fail on noise; its own
    scatter over the seeds keeps it within tolerance, and its sigma is its own."""
    rng = np.random.default_rng(6)
    t = truth()
    ref = (noisy(rng, t, 0.005), noisy(rng, t, 0.005))
    seeds = []
    for f in (1.25, 1.25, 1.25, 0.95):  # block (10,5) over four seeds: +17.5%, 2.3 of its SE
        img = noisy(rng, t, 0.01)
        img[40:48, 80:88] *= f
        seeds.append(img)
    r = compare.compare("noisy block", seeds, ref)
    b = [x for x in r.all_blocks if (x.x, x.y) == (10, 5)][0]
    # Its own scatter: a standard error of 7.5% (its neighbours' smoothed in, 2.5%, would
    # put the tolerance at 12.8% and fail it).
    assert 0.06 < b.sigma < 0.09, r.message
    assert r.block_passed, r.message
    neighbour = [x for x in r.all_blocks if (x.x, x.y) == (12, 5)][0]
    assert neighbour.sigma < 0.01, r.message
