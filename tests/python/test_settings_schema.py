"""The one settings schema: the keywords of ``photonmap.render`` are the schema's fields, with
the command line's flags and defaults; unknown and bad keywords are named; the stats' options
render the same image again."""

from __future__ import annotations

import numpy as np
import photonmap
import pytest
from photonmap import _core

TINY = {
    "camera": {"fov": 0.7, "transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 3], [0, 0, 0, 1]]},
    "film": {"width": 8, "height": 6},
    "materials": [{"type": "diffuse", "color": [0.5, 0.5, 0.5]}],
    "meshes": [{"positions": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]],
                "indices": [[0, 1, 2], [0, 2, 3]]}],
    "lights": [{"type": "point", "position": [0, 0, 1], "power": 10}],
}
FAST = {"quality": "draft", "spp": 1, "photons": 500, "caustic_photons": 100,
        "volume_photons": 100, "final_gather_rays": 8}


@pytest.fixture(scope="module")
def scene():
    return photonmap.Scene.from_dict(TINY)


def test_every_field_is_a_keyword_and_a_flag(scene, capfd):
    schema = photonmap.settings_schema()
    assert len(schema) > 20
    capfd.readouterr()
    assert _core.run_cli(["render", "--help"]) == 0
    helptext = capfd.readouterr().out
    for f in schema:
        assert f["flag"] == "--" + f["name"].replace("_", "-")
        assert f["flag"] in helptext, f["name"]
        assert f["doc"] and f["label"], f["name"]
    # Every keyword is taken at its default value, and the render records it.
    given = {f["name"]: f["default"] for f in schema if f["default"] is not None}
    given.update(FAST)
    out = photonmap.render(scene, **given)
    opts = out["stats"]["options"]
    assert set(opts) == {f["name"] for f in schema}
    for k, v in given.items():
        if k != "quality":  # the recorded options spell every value out instead
            assert opts[k] == pytest.approx(v), k


def test_preset_fields_default_to_the_preset(scene):
    out = photonmap.render(scene, quality="draft", spp=1)
    p = photonmap.preset("draft")
    opts = out["stats"]["options"]
    for k, v in p.items():
        if k != "spp":
            assert opts[k] == pytest.approx(v), k
    assert {f["name"] for f in photonmap.settings_schema() if f["preset"]} == set(p)


def test_unknown_keyword_is_a_type_error_naming_it(scene):
    with pytest.raises(TypeError, match="`sampels`.*spp"):
        photonmap.render(scene, sampels=4)


@pytest.mark.parametrize("key,value,match", [
    ("spp", "many", "`spp`.*string"),
    ("spp", 0, "`spp`: must be at least 1"),
    ("alpha", 1.5, r"`alpha`: must be in \(0, 1\)"),
    ("radius", float("nan"), "`radius`"),
    ("cache_tolerance", -0.1, "`cache_tolerance`: must be a finite number > 0"),
    ("filter", "lanczos", "`filter`.*lanczos"),
    ("mode", "bdpt", "`mode`.*bdpt"),
    ("memory_limit", "8X", "`memory_limit`"),
    ("irradiance_cache", "yes", "`irradiance_cache`"),
    ("time_budget", -2.0, "`time_budget`"),
])
def test_bad_value_is_a_value_error_naming_it(scene, key, value, match):
    with pytest.raises(ValueError, match=match):
        photonmap.render(scene, **{key: value})


def test_none_is_the_default_and_numpy_scalars_are_numbers(scene):
    a = photonmap.render(scene, **FAST, seed=np.int64(2), radius=None, filter=None)
    b = photonmap.render(scene, **FAST, seed=2)
    assert np.array_equal(a["combined"], b["combined"])


def test_the_recorded_options_render_the_same_image(scene):
    first = photonmap.render(scene, quality="draft", spp=2, photons=800, gather=20,
                             radius=0.4, filter="box", photon_power="f32", seed=5,
                             mode="sppm", alpha=0.6)
    again = photonmap.render(scene, **first["stats"]["options"])
    for k in ("combined", *photonmap.TERMS):
        assert np.array_equal(first[k], again[k]), k
    # A changed option changes the image: the comparison can fail.
    other = photonmap.render(scene, **{**first["stats"]["options"], "seed": 6})
    assert not np.array_equal(first["combined"], other["combined"])
