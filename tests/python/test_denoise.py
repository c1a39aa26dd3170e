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


def test_denoising_lowers_the_error_and_keeps_the_caustic():
    """On the spheres' Cornell box at `draft` (128x128), against Mitsuba's reference: the
    relMSE falls, and in the caustic under the glass sphere the error of 4x4-pixel blocks
    does not rise (a denoiser that blurred the caustic's edges would raise it)."""
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
    assert be(out["combined"]) <= 1.05 * be(noisy), (be(out["combined"]), be(noisy))
    # A blur that erases the caustic's edges is caught by the same measure.
    k = 3
    pad = np.pad(out["caustic"], ((k, k), (k, k), (0, 0)), mode="edge")
    blurred = sum(pad[k + dy:k + dy + 128, k + dx:k + dx + 128]
                  for dy in range(-k, k + 1) for dx in range(-k, k + 1)) / (2 * k + 1) ** 2
    smeared = out["combined"] - out["caustic"] + blurred
    assert be(smeared) > 1.5 * be(out["combined"]), (be(smeared), be(out["combined"]))


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
