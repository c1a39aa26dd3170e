"""Progressive photon mapping, previews and the error AOV through the Python API."""

import json
import os

import numpy as np
import pytest

import photonmap


ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def spheres(size=32):
    """The caustic test scene (glass and mirror spheres in a Cornell box), small."""
    with open(os.path.join(ROOT, "tests", "data", "scenes", "cornell_spheres.json")) as f:
        ir = json.load(f)
    ir["film"] = dict(ir.get("film", {}), width=size, height=size)
    return ir


def block_z(a, b, err_a, err_b, block=8):
    """Per block x block block and channel: (mean of a - mean of b) over the standard error
    of that difference, from the two renders' ``error`` AOVs (pixels taken as independent)."""
    h, w = a.shape[:2]
    shape = (h // block, block, w // block, block, -1)
    d = a.reshape(shape).mean(axis=(1, 3)) - b.reshape(shape).mean(axis=(1, 3))
    v = sum((e.astype(np.float64) ** 2).reshape(shape).sum(axis=(1, 3)) for e in (err_a, err_b))
    return d / np.maximum(np.sqrt(v) / block**2, 1e-9)


def test_sppm_renders_converging_passes_with_previews_and_an_error_aov():
    s = spheres()
    seen = []
    out = photonmap.render(s, mode="sppm", spp=8, photons=5000, seed=2,
                           preview=lambda img, passes: seen.append((img.shape, passes, img.mean())))
    st = out["stats"]
    assert st["mode"] == "sppm" and st["sppm"]["passes"] == 8
    assert st["sppm"]["mean_final_radius"] < st["sppm"]["mean_initial_radius"]
    # No caustic map in progressive mode, and the stats say why.
    caustic = [m for m in st["photon_maps"] if m["map"] == "caustic"][0]
    assert not caustic["built"] and "progressive" in caustic["skipped_because"]
    # Previews (the calling thread gets the latest every 50 ms), each the beauty so far.
    passes = [p for _, p, _ in seen]
    assert passes and passes == sorted(passes) and passes[-1] <= 8
    assert all(shape == out["combined"].shape for shape, _, _ in seen)
    # The error AOV: finite, non-negative, and it measures the beauty's noise: against a render
    # of another seed, every 8x8 block's difference is within 4.5 of the two renders'
    # standard errors combined (48 block channels: a false alarm under 10^-3). Each pass has
    # its own photon map, so the photon noise is in it too, and the progressive bias estimate.
    err = out[photonmap.ERROR_AOV]
    assert err.shape == out["combined"].shape and np.isfinite(err).all() and (err >= 0).all()
    assert err.mean() > 0
    other = photonmap.render(s, mode="sppm", spp=8, photons=5000, seed=3)
    z = block_z(out["combined"], other["combined"], err, other[photonmap.ERROR_AOV])
    print(f"\nseed 2 vs seed 3: worst |z| {np.abs(z).max():.2f}, rms z {np.sqrt((z**2).mean()):.2f}")
    assert np.abs(z).max() < 4.5, z
    # Nor grossly overstated: the spread of z (0.91 measured) would be under 0.3 with the
    # error AOV three times too large.
    assert np.sqrt((z**2).mean()) > 0.3, z


def test_error_aov_shrinks_with_samples_in_jensen_mode():
    s = spheres()
    # Without adaptive sampling, which would add samples where the error is largest.
    a = photonmap.render(s, quality="draft", spp=8, seed=1, adaptive_sampling=False)
    b = photonmap.render(s, quality="draft", spp=128, seed=1, adaptive_sampling=False)
    # Standard error ~ 1/sqrt(spp): 16x the samples, about a quarter of the error.
    ratio = b["error"].mean() / a["error"].mean()
    assert 0.15 < ratio < 0.4, ratio


def test_bad_mode_and_alpha_name_the_setting():
    s = spheres()
    with pytest.raises(ValueError, match="mode"):
        photonmap.render(s, mode="progressive")
    with pytest.raises(ValueError, match="alpha"):
        photonmap.render(s, mode="sppm", alpha=1.5)


def test_cli_writes_the_error_layer(tmp_path):
    oiio = pytest.importorskip("OpenImageIO")
    path = tmp_path / "s.json"
    path.write_text(json.dumps(spheres(24)))
    exr = tmp_path / "out.exr"
    from photonmap.cli import main

    assert main(["render", str(path), "-o", str(exr), "--mode", "sppm", "--spp", "4",
                 "--photons", "2000", "--quiet"]) == 0
    spec = oiio.ImageInput.open(str(exr)).spec()
    names = list(spec.channelnames)
    assert {"error.R", "error.G", "error.B", "caustic.R"} <= set(names), names
