"""`photonmap trade`: the speed/accuracy report (trade.json and the relMSE-seconds plots)."""
import json
import math
import os
import subprocess
import sys
import time

import numpy as np
import pytest

import photonmap

from conftest import SCENES

pytest.importorskip("matplotlib")

SCENE = os.path.join(SCENES, "cornell_spheres.json")
TERMS = ("direct", "indirect", "caustic", "specular", "volume", "emission", "subsurface")


def run_cli(*args, cwd=None, timeout=300):
    env = dict(os.environ, RUST_BACKTRACE="0")
    return subprocess.run([sys.executable, "-m", "photonmap.cli", *args], capture_output=True,
                          text=True, cwd=cwd, env=env, timeout=timeout)


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    """`trade --quick` (around `draft`, seed 1) at 32x32 against a multilayer reference of our
    own: `draft` with 16x its photons, also seed 1. The camera samples (and the irradiance
    cache's records, placed by geometry) are the same in every run, so their noise cancels and
    the error left is that of the photon maps, which more photons must reduce."""
    d = tmp_path_factory.mktemp("trade")
    ref = d / "ref.exr"
    p = run_cli("render", SCENE, "-o", str(ref), "--width", "32", "--height", "32",
                "--quality", "draft", "--seed", "1", "--photons", "800000",
                "--caustic-photons", "320000", "--volume-photons", "320000", "--filter", "box",
                "--quiet")
    assert p.returncode == 0, p.stderr
    t0 = time.perf_counter()
    p = run_cli("trade", SCENE, "--reference", str(ref), "--out", str(d / "out"), "--quick",
                "--seed", "1", "--threads", "2")
    seconds = time.perf_counter() - t0
    assert p.returncode == 0, p.stderr
    with open(d / "out" / "trade.json") as f:
        result = json.load(f)
    return d / "out", result, seconds, p.stderr


def test_trade_json_structure(quick):
    out, r, seconds, _ = quick
    print(f"trade --quick: {seconds:.1f} s, {len(r['runs'])} runs")
    assert (r["width"], r["height"]) == (32, 32)
    assert r["quick"] is True and r["base_preset"] == "draft"
    # The reference is our multilayer EXR: every term is compared, and the combined image.
    assert r["terms_compared"] == ["combined", *TERMS]
    sweeps = {x["sweep"] for x in r["runs"]}
    assert sweeps == {"base", "photons", "gather", "radius", "final_gather_rays",
                      "cache_tolerance", "photon_power", "spp", "preset"}
    assert [x["value"] for x in r["runs"] if x["sweep"] == "preset"] == ["draft", "medium"]
    for x in r["runs"]:
        assert x["seconds"] > 0 and len(x["seconds_each"]) == 1
        for m in ("relmse", "relmse_trimmed", "relmse_block"):
            assert set(x[m]) == set(r["terms_compared"]), m
            for v in x[m].values():
                assert math.isfinite(v) and v >= 0
            # Dropping the worst pixels can only lower the mean.
            assert x["relmse_trimmed"]["combined"] <= x["relmse"]["combined"]
        assert x["cpu_seconds"] > 0 and x["params"]["filter"] == "box"
        assert {"spp", "photons", "gather", "final_gather_rays", "cache_tolerance",
                "photon_power"} <= set(x["params"])
    # The base is the medium preset; a sweep changes exactly the setting it names.
    base = next(x for x in r["runs"] if x["sweep"] == "base")
    draft = photonmap.preset("draft")
    for k in ("spp", "photons", "caustic_photons", "gather", "final_gather_rays"):
        assert base["params"][k] == draft[k], k
    assert base["params"]["photon_power"] == "rgbe"
    for x in r["runs"]:
        if x["sweep"] in ("base", "preset"):
            continue
        changed = {k for k in x["params"] if x["params"][k] != base["params"].get(k)}
        expect = {"photons": {"photons", "caustic_photons", "volume_photons"}}.get(
            x["sweep"], {x["sweep"]})
        assert changed == expect, (x["sweep"], changed)
    # Photons scale together; the radius sweep is around the map's default radius.
    ph = {x["value"]: x["params"] for x in r["runs"] if x["sweep"] == "photons"}
    assert ph[4]["photons"] == 4 * base["params"]["photons"]
    assert ph[4]["caustic_photons"] == 4 * base["params"]["caustic_photons"]
    rad = {x["value"]: x["params"]["radius"] for x in r["runs"] if x["sweep"] == "radius"}
    assert r["base_radius"] > 0 and rad[2] == pytest.approx(2 * r["base_radius"])
    # f32 photons are 28 bytes, RGBE ones 20.
    f32 = next(x for x in r["runs"] if x["sweep"] == "photon_power")
    assert f32["value"] == "f32"
    assert {m["bytes_per_photon"] for m in f32["stats"]["photon_maps"].values()} == {28}
    assert {m["bytes_per_photon"] for m in base["stats"]["photon_maps"].values()} == {20}


def test_error_falls_with_photon_count(quick):
    _, r, _, _ = quick
    base = next(x for x in r["runs"] if x["sweep"] == "base")
    pts = sorted([(x["value"], x) for x in r["runs"] if x["sweep"] == "photons"] + [(1, base)],
                 key=lambda p: p[0])
    factors = [f for f, _ in pts]
    assert factors == [0.0625, 0.25, 1, 4]
    for term in ("combined", "caustic", "indirect"):
        errs = [x["relmse"][term] for _, x in pts]
        print(term, ["%.3e" % e for e in errs])
        # The error falls along the sweep: on average (the slope of log error on log photons
        # is clearly negative: -0.7 measured) and 64x the photons at least halves it.
        slope = np.polyfit(np.log(factors), np.log(errs), 1)[0]
        assert slope < -0.15, (term, slope, errs)
        assert errs[-1] < 0.5 * errs[0], (term, errs)


def test_plots_are_valid_pngs(quick):
    out, _, _, _ = quick
    import matplotlib.image as mpimg

    for name in ("trade.png", "trade_terms.png"):
        p = out / name
        assert p.exists() and p.stat().st_size > 10_000, name
        with open(p, "rb") as f:
            assert f.read(8) == b"\x89PNG\r\n\x1a\n"
        img = mpimg.imread(str(p))
        assert img.ndim == 3 and img.shape[0] > 300 and img.shape[1] > 600
        # Not a blank canvas: curves and text.
        assert img[..., :3].std() > 0.05


def test_replot_with_cpu_clock(quick, tmp_path):
    """--replot redraws an earlier run's plots without rendering."""
    out, _, _, _ = quick
    t0 = time.perf_counter()
    p = run_cli("trade", "--replot", str(out / "trade.json"), "--clock", "cpu", "--out",
                str(tmp_path))
    assert p.returncode == 0, p.stderr
    with open(tmp_path / "trade.png", "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    assert not (tmp_path / "trade.json").exists()


def test_reference_size_must_match(quick, tmp_path):
    out, _, _, _ = quick
    ref = out.parent / "ref.exr"
    p = run_cli("trade", SCENE, "--reference", str(ref), "--out", str(tmp_path), "--quick",
                "--width", "64", "--height", "64")
    assert p.returncode == 1
    assert "is 32x32, not 64x64" in p.stderr
    assert not (tmp_path / "trade.json").exists()


def test_missing_matplotlib_is_a_clear_error(tmp_path):
    code = ("import sys; sys.modules['matplotlib'] = None; from photonmap.cli import main; "
            f"sys.exit(main(['trade', {SCENE!r}, '--reference', {SCENE!r}, '--out', "
            f"{str(tmp_path)!r}]))")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert p.returncode == 1
    assert "pip install 'photonmap[trade]'" in p.stderr
