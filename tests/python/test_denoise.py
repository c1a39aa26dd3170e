"""Denoising (``denoise=True``, ``--denoise``; the extra ``photonmap[denoise]``): each noisy
term denoised on its own with the guides, the beauty their sum, the noisy terms kept, the
filter recorded; lower error against the Mitsuba reference, caustic edges kept."""

from __future__ import annotations

import json
import os
import sys

import numpy as np
import pytest

import photonmap
from photonmap import cli

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SPHERES = os.path.join(ROOT, "tests", "data", "scenes", "cornell_spheres.json")
REFERENCE = os.path.join(ROOT, "tests", "data", "references", "cornell_spheres_full.exr")


def small_scene(size=48):
    ir = json.loads(photonmap._core.DEFAULT_SCENE_JSON)
    ir["film"] = {"width": size, "height": size}
    return json.dumps(ir)


def test_denoised_terms_sum_to_the_beauty_and_the_noisy_terms_are_kept():
    pytest.importorskip("pyoidn")
    kw = dict(quality="draft", spp=4, seed=5, adaptive_sampling=False)
    den = photonmap.render(small_scene(), denoise=True, **kw)
    raw = photonmap.render(small_scene(), **kw)
    names = [a["name"] for a in den["aovs"]]
    assert names == ["error", "albedo", "normal"] + [
        f"{t}_noisy" for t in photonmap.DENOISED_TERMS]
    for t in photonmap.DENOISED_TERMS:
        # The noisy layer is the term as rendered, bit for bit.
        assert np.array_equal(den[f"{t}_noisy"], raw[t]), t
    assert np.array_equal(den["emission"], raw["emission"])
    # Each term was denoised (the ones the scene has), each stays finite and non-negative.
    for t in ("direct", "indirect", "caustic", "specular"):
        assert not np.array_equal(den[t], raw[t]), t
        assert np.isfinite(den[t]).all() and (den[t] >= 0).all(), t
    assert not den["volume"].any()  # no media: zero, and zero it stays
    # The beauty is the sum of the terms, exactly as the core sums them.
    total = np.zeros_like(den["combined"])
    for t in photonmap.TERMS:
        total += den[t]
    assert np.array_equal(total, den["combined"])
    d = den["stats"]["denoise"]
    assert d["filter"].startswith("Open Image Denoise") and d["version"].count(".") >= 1
    assert d["terms"] == ",".join(photonmap.DENOISED_TERMS) and d["seconds"] > 0


def _reference():
    import OpenImageIO as oiio

    return oiio.ImageBuf(REFERENCE).get_pixels(oiio.FLOAT)[..., :3]


def _pixel_error(img, ref):
    return (((img - ref) ** 2) / (ref ** 2 + 1e-2)).mean(-1)


def _blocks(img, k):
    h, w = img.shape[:2]
    return img.reshape(h // k, k, w // k, k, -1).mean((1, 3))


def _edge_strength(img, region):
    """Mean gradient magnitude (|dx| + |dy| of the channel mean) over the 8x8 blocks of
    ``region``: what a blur of the caustic's edges lowers."""
    c = img.mean(-1)
    gx = np.abs(np.diff(c, axis=1))[:-1, :]
    gy = np.abs(np.diff(c, axis=0))[:, :-1]
    m = np.repeat(np.repeat(region, 8, 0), 8, 1)[:-1, :-1]
    return float((gx + gy)[m].mean())


def test_denoising_lowers_the_error_and_keeps_the_caustic():
    """On the spheres' Cornell box at `draft` (128x128), against Mitsuba's reference: the
    relMSE falls, the caustic under the glass sphere keeps the strength of its edges, and the
    error of 4x4-pixel blocks in the caustic's region stays within what its photon noise
    spreads (BENCHMARKS.md: over seeds, 0.82-1.06 of the raw render's at `draft`)."""
    pytest.importorskip("pyoidn")
    ref = _reference()
    out = photonmap.render(SPHERES, quality="draft", seed=1, threads=2, denoise=True)
    noisy = out["emission"] + sum(out[f"{t}_noisy"] for t in photonmap.DENOISED_TERMS)
    e_raw = _pixel_error(noisy, ref)
    e_den = _pixel_error(out["combined"], ref)
    # Pixels where the renderers disagree by construction (the light's edges and its image
    # in the mirror sphere: a few pixels of aliasing) would swamp both: the raw render's
    # worst 1% are left out of both measures, which can only favour the raw one.
    keep = e_raw <= np.quantile(e_raw, 0.99)
    raw, den = e_raw[keep].mean(), e_den[keep].mean()
    assert den < 0.8 * raw, (den, raw)
    # The caustic region: 8x8 blocks where the noisy caustic term is bright.
    caus = _blocks(out["caustic_noisy"], 8).mean(-1)
    region = caus > 0.25 * caus.max()
    assert 2 <= region.sum() <= 40, region.sum()
    mask = np.repeat(np.repeat(region, 2, 0), 2, 1)  # as 4x4 blocks
    be = lambda img: _pixel_error(_blocks(img, 4), _blocks(ref, 4))[mask].mean()  # noqa: E731
    assert be(out["combined"]) <= 1.25 * be(noisy), (be(out["combined"]), be(noisy))
    # The edges keep their strength (seeds 1-5: 0.94-1.01 of the noisy caustic's; the
    # denoiser takes the noise's share of the gradients away)...
    before = _edge_strength(out["caustic_noisy"], region)
    after = _edge_strength(out["caustic"], region)
    assert after >= 0.9 * before, (after, before)
    # ... where a blur of the caustic (a 5x5 box) loses a good part of it (seeds 1-5:
    # 0.43-0.48 of it): the measure tells a smeared caustic apart.
    k = 2
    pad = np.pad(out["caustic"], ((k, k), (k, k), (0, 0)), mode="edge")
    blurred = sum(pad[k + dy:k + dy + 128, k + dx:k + dx + 128]
                  for dy in range(-k, k + 1) for dx in range(-k, k + 1)) / (2 * k + 1) ** 2
    assert _edge_strength(blurred, region) < 0.8 * before, (_edge_strength(blurred, region),
                                                           before)


def test_missing_pyoidn_is_named(monkeypatch, tmp_path, capfd):
    monkeypatch.setitem(sys.modules, "pyoidn", None)  # import pyoidn -> ImportError
    with pytest.raises(photonmap.PhotonmapError, match=r"pyoidn.*photonmap\[denoise\]"):
        photonmap.render(small_scene(8), quality="draft", spp=1, denoise=True)
    code = cli.main(["render", "-o", str(tmp_path / "x.exr"), "--quality", "draft",
                     "--spp", "1", "--width", "8", "--denoise", "--quiet"])
    err = capfd.readouterr().err
    assert code == 2, err
    assert "--denoise" in err and "pyoidn" in err and "photonmap[denoise]" in err, err
    assert not (tmp_path / "x.exr").exists()


def test_command_line_denoise_writes_noisy_layers_and_the_filter(tmp_path):
    pytest.importorskip("pyoidn")
    import OpenImageIO as oiio

    exr = tmp_path / "d.exr"
    code = cli.main(["render", "-o", str(exr), "--quality", "draft", "--spp", "4",
                     "--width", "48", "--denoise", "--quiet", "--stats", str(tmp_path / "s.json")])
    assert code == 0
    inp = oiio.ImageInput.open(str(exr))
    spec = inp.spec()
    px = inp.read_image(oiio.FLOAT)
    inp.close()
    ch = {n: i for i, n in enumerate(spec.channelnames)}
    for name in ["albedo.R", "normal.Z"] + [f"{t}_noisy.R" for t in photonmap.DENOISED_TERMS]:
        assert name in ch, name
    assert spec.getattribute("photonmap/denoise/filter").startswith("Open Image Denoise")
    assert spec.getattribute("photonmap/denoise/version")
    assert spec.getattribute("photonmap/denoise/binding").startswith("pyoidn")
    # The beauty is the sum of the (denoised) term layers; the noisy ones differ from them.
    for c in "RGB":
        total = np.zeros(px.shape[:2], np.float32)
        for t in photonmap.TERMS:
            total += px[..., ch[f"{t}.{c}"]]
        assert np.array_equal(total, px[..., ch[c]])
    assert not np.array_equal(px[..., ch["direct.R"]], px[..., ch["direct_noisy.R"]])
    stats = json.loads((tmp_path / "s.json").read_text())
    assert stats["denoise"]["terms"] == ",".join(photonmap.DENOISED_TERMS)


def test_keeping_local_means():
    """A denoised image whose local means drifted (here: 20% dark, and flat where the noisy
    image has a slow gradient) gets them back; one with the noisy image's local means is
    left as it is."""
    from photonmap.denoise import box_mean, keep_local_means

    rng = np.random.default_rng(3)
    y, x = np.mgrid[0:24, 0:32].astype(np.float32)
    smooth = (1.0 + 0.5 * np.sin(x / 9.0) * np.cos(y / 7.0))[..., None] * np.ones(3, np.float32)
    noisy = smooth * (1.0 + 0.1 * rng.standard_normal((24, 32, 3)).astype(np.float32))
    drifted = 0.8 * box_mean(noisy, 6)
    kept = keep_local_means(drifted, noisy, 2)
    inner = (slice(4, -4), slice(4, -4))
    before = np.abs(box_mean(drifted, 2) / box_mean(noisy, 2) - 1)[inner].mean()
    after = np.abs(box_mean(kept, 2) / box_mean(noisy, 2) - 1)[inner].mean()
    assert before > 0.15 and after < 0.02, (before, after)
    np.testing.assert_allclose(keep_local_means(noisy, noisy, 2), noisy, rtol=1e-5)
    # box_mean against a direct sum.
    b = box_mean(noisy, 1)
    assert np.isclose(b[5, 7, 1], noisy[4:7, 6:9, 1].mean(), rtol=1e-5)
