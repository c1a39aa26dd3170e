"""`photon_power="rgbe"|"f32"`: the photon record of the maps, from Python."""
import os

import numpy as np
import pytest

import photonmap
from conftest import SCENES


def test_f32_power_photons_are_28_bytes_and_match_rgbe():
    scene = photonmap.load_scene(os.path.join(SCENES, "cornell_spheres.json"))
    kw = dict(quality="draft", spp=2, seed=4, photons=20_000, caustic_photons=10_000,
              final_gather_rays=32, filter="box")
    rgbe = photonmap.render(scene, **kw)
    f32 = photonmap.render(scene, photon_power="f32", **kw)
    for out, size in ((rgbe, 20), (f32, 28)):
        maps = [m for m in out["stats"]["photon_maps"] if m["built"]]
        assert {m["map"] for m in maps} == {"global", "caustic"}
        for m in maps:
            assert m["bytes_per_photon"] == size
            # The global map also holds its precomputed irradiance points, 20 B each.
            assert m["memory_bytes"] == size * m["stored"] + 20 * m["irradiance_points"]
        assert out["stats"]["bytes_per_photon"] == size
        assert out["stats"]["memory_estimate"]["photon_bytes"] == size * 30_000
    # The same photons, quantised or not: the images agree to well within 0.5%.
    a, b = f32["combined"].astype(np.float64), rgbe["combined"].astype(np.float64)
    diff = np.abs(a - b).sum() / np.abs(b).sum()
    assert 0 < diff < 5e-3, diff


def test_unknown_photon_power_is_a_value_error():
    with pytest.raises(ValueError, match="`photon_power`.*`half`.*`rgbe` or `f32`"):
        photonmap.render(photonmap.default_scene(), quality="draft", spp=1,
                         photon_power="half")
