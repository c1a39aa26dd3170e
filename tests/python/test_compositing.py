"""The compositing AOVs on the written EXR and in Python's result: Cryptomatte layers and
manifest as OpenImageIO reads them, the denoising guides, and the AOV list."""

from __future__ import annotations

import json
import math
import struct

import numpy as np
import pytest

import photonmap
from photonmap import cli

W = 32
# The card's edges, in pixels from the left and the top.
X0, X1, Y0, Y1 = 7.3, 20.6, 10.25, 25.8


def card_scene() -> dict:
    """A card parallel to the film in front of a backdrop; with the box filter a pixel's
    coverage by the card is the share of its area inside the card's edges."""
    depth = 2.0
    px = 2.0 * math.tan(0.25) * depth / W

    def at(x, y):
        return [(x - 16.0) * px, (16.0 - y) * px, -depth]

    s = 4.0
    return {
        "camera": {"fov": 0.5},
        "film": {"width": W, "height": W},
        "materials": [{"type": "diffuse", "name": "paper", "color": [0.7, 0.7, 0.7]},
                      {"type": "diffuse", "name": "felt", "color": [0.2, 0.3, 0.5]}],
        "meshes": [
            {"name": "card", "material": 0, "indices": [[0, 1, 2], [0, 2, 3]],
             "positions": [at(X0, Y1), at(X1, Y1), at(X1, Y0), at(X0, Y0)]},
            {"name": "backdrop", "material": 1, "indices": [[0, 1, 2], [0, 2, 3]],
             "positions": [[-s, -s, -4], [s, -s, -4], [s, s, -4], [-s, s, -4]]},
        ],
        "lights": [{"type": "point", "name": "bulb", "position": [0, 0, 0], "power": 50.0}],
    }


def coverage() -> np.ndarray:
    xs = np.arange(W, dtype=np.float64)
    cx = np.clip(np.minimum(xs + 1, X1) - np.maximum(xs, X0), 0, None)
    cy = np.clip(np.minimum(xs + 1, Y1) - np.maximum(xs, Y0), 0, None)
    return np.outer(cy, cx)


def read_exr(path):
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    spec = inp.spec()
    px = inp.read_image(oiio.FLOAT)
    inp.close()
    chans = {n: px[..., i] for i, n in enumerate(spec.channelnames)}
    attrs = {a.name: a.value for a in spec.extra_attribs}
    return chans, attrs


def decode_matte(chans, attrs, type_name, name) -> np.ndarray:
    """A matte as Cryptomatte decoders make it: the manifest (in the EXR metadata) gives the
    name's id; the matte is the sum of the coverages of the ranks holding it."""
    keys = [k.rsplit("/", 1)[0] for k, v in attrs.items()
            if k.startswith("cryptomatte/") and k.endswith("/name") and v == type_name]
    assert len(keys) == 1, attrs
    key = keys[0]
    assert attrs[f"{key}/hash"] == "MurmurHash3_32"
    assert attrs[f"{key}/conversion"] == "uint32_to_float32"
    manifest = json.loads(attrs[f"{key}/manifest"])
    fid = np.float32(struct.unpack(">f", bytes.fromhex(manifest[name]))[0])
    matte = np.zeros(next(iter(chans.values())).shape, np.float32)
    rank = 0
    while f"{type_name}{rank:02d}.R" in chans:
        layer = f"{type_name}{rank:02d}"
        for idc, covc in (("R", "G"), ("B", "A")):
            hit = chans[f"{layer}.{idc}"] == fid
            matte += np.where(hit, chans[f"{layer}.{covc}"], 0.0)
        rank += 1
    return matte, manifest


def test_cryptomatte_layers_and_manifest_read_by_openimageio(tmp_path):
    scene = tmp_path / "card.json"
    scene.write_text(json.dumps(card_scene()))
    exr = tmp_path / "card.exr"
    code = cli.main(["render", str(scene), "-o", str(exr), "--spp", "64", "--filter", "box",
                     "--adaptive-sampling", "off", "--cryptomatte", "both", "--quiet"])
    assert code == 0
    chans, attrs = read_exr(exr)
    for t in ("CryptoObject", "CryptoMaterial"):
        for i in range(3):
            for c in "RGBA":
                assert f"{t}{i:02d}.{c}" in chans
    card, manifest = decode_matte(chans, attrs, "CryptoObject", "card")
    assert set(manifest) == {"card", "backdrop"}
    paper, _ = decode_matte(chans, attrs, "CryptoMaterial", "paper")
    backdrop, _ = decode_matte(chans, attrs, "CryptoObject", "backdrop")
    cov = coverage()
    err = np.abs(card - cov)
    edge = (cov > 0) & (cov < 1)
    assert err.max() <= 1 / 16 + 1e-6, err.max()
    assert err[edge].mean() < 0.025 and abs((card - cov)[edge].mean()) < 0.005
    assert np.array_equal(card[~edge], cov[~edge].astype(np.float32))
    np.testing.assert_array_equal(card, paper)
    np.testing.assert_allclose(card + backdrop, 1.0, atol=1e-5)


def test_python_result_lists_its_aovs_and_the_manifests():
    out = photonmap.render(card_scene(), spp=4, cryptomatte="object", cryptomatte_levels=2,
                           denoising_data=True)
    names = [a["name"] for a in out["aovs"]]
    assert names == ["error", "albedo", "normal", "CryptoObject00"]
    assert names == [a["name"] for a in photonmap.aov_specs(
        cryptomatte="object", cryptomatte_levels=2, denoising_data=True)]
    assert out["CryptoObject00"].shape == (W, W, 4) and out["normal"].shape == (W, W, 3)
    assert out["cryptomatte"] == {"CryptoObject": ["backdrop", "card"]}
    header = photonmap.cryptomatte_header(out["cryptomatte"], "ViewLayer.")
    assert sorted(v for k, v in header.items() if k.endswith("/name")) == [
        "ViewLayer.CryptoObject"]
    # Asked for nothing, a render has the error AOV only.
    plain = photonmap.render(card_scene(), spp=1)
    assert [a["name"] for a in plain["aovs"]] == ["error"] and "albedo" not in plain


def test_bad_cryptomatte_settings_are_named():
    with pytest.raises(ValueError, match="cryptomatte"):
        photonmap.render(card_scene(), spp=1, cryptomatte="objects")
    with pytest.raises(ValueError, match="cryptomatte_levels"):
        photonmap.render(card_scene(), spp=1, cryptomatte="object", cryptomatte_levels=0)


@pytest.mark.parametrize("transparent", [False, True])
def test_holdout_card_makes_alpha_one_minus_its_coverage(tmp_path, transparent):
    """The card held out (the IR's ``holdout``, Blender's Object > Visibility > Holdout): the
    EXR's ``A`` is 1 - the card's coverage of each pixel, and the card's pixels are black.
    With ``film.transparent`` (the backdrop filling the frame) nothing changes. The PNG
    preview carries the alpha."""
    import OpenImageIO as oiio

    scene = card_scene()
    scene["meshes"][0]["holdout"] = True
    scene["film"]["transparent"] = transparent
    path = tmp_path / "card.json"
    path.write_text(json.dumps(scene))
    exr, png = tmp_path / "card.exr", tmp_path / "card.png"
    code = cli.main(["render", str(path), "-o", str(exr), "--png", str(png), "--spp", "64",
                     "--filter", "box", "--adaptive-sampling", "off", "--quiet"])
    assert code == 0
    chans, _ = read_exr(exr)
    cov = coverage()
    alpha = chans["A"]
    edge = (cov > 0) & (cov < 1)
    err = np.abs(alpha - (1 - cov))
    # 64 stratified samples per pixel: the coverage of an edge pixel to 1/16 at worst.
    assert err.max() <= 1 / 16 + 1e-6, err.max()
    assert np.array_equal(alpha[~edge], (1 - cov[~edge]).astype(np.float32))
    inside = cov == 1
    assert (chans["R"][inside] == 0).all() and (chans["R"][cov == 0] > 0).all()
    preview = oiio.ImageBuf(str(png))
    assert preview.spec().nchannels == 4
    a8 = preview.get_pixels(oiio.FLOAT)[..., 3]
    assert np.abs(a8 - alpha).max() <= 0.5 / 255 + 1e-6


def test_python_result_has_the_alpha():
    scene = card_scene()
    scene["meshes"][0]["holdout"] = True
    out = photonmap.render(scene, spp=16, filter="box", adaptive_sampling=False)
    cov = coverage()
    assert out["alpha"].shape == (W, W) and out["alpha"].dtype == np.float32
    assert np.array_equal(out["alpha"][cov == 1], np.zeros((cov == 1).sum(), np.float32))
    assert (out["alpha"][cov == 0] == 1).all()
    opaque = photonmap.render(card_scene(), spp=1)
    assert (opaque["alpha"] == 1).all()
