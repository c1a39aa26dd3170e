"""Python API: numpy scenes, terms, progress, cancel, errors."""
import os
import subprocess
import sys
import threading

import numpy as np
import pytest

import photonmap

CAM = {"fov": 0.7, "transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4], [0, 0, 0, 1]]}


def numpy_scene(n=32, dtype=np.float64, idx_dtype=np.int64):
    pos = np.array([[-2, -2, 0], [2, -2, 0], [2, 2, 0], [-2, 2, 0]], dtype=dtype)
    return {
        "camera": CAM, "film": {"width": n, "height": n},
        "materials": [{"type": "diffuse", "color": [0.8, 0.8, 0.8]}],
        "meshes": [{"name": "floor", "positions": pos,
                    "indices": np.array([[0, 1, 2], [0, 2, 3]], dtype=idx_dtype),
                    "normals": np.tile(np.array([0, 0, 1], np.float32), (4, 1)),
                    "uvs": np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float16),
                    "material_indices": np.zeros(2, np.uint8)}],
        "lights": [{"type": "point", "name": "lamp", "position": [0, 0, 2], "power": np.float64(200)}],
    }


def test_terms_and_pass_names_come_from_the_core():
    assert photonmap.TERMS == ("direct", "indirect", "caustic", "specular", "volume", "emission",
                              "subsurface")
    assert photonmap.PASS_NAMES == tuple(t.capitalize() for t in photonmap.TERMS)


def floor_radiance(n=32, sub=16):
    """numpy_scene's image, exactly: each pixel's mean radiance over its footprint (a box
    filter) of the Lambertian floor (albedo 0.8) lit by the point light (200 W, 2 above the
    floor's centre): L = (0.8 / pi) (200 / (4 pi)) cos(theta) / d^2, cos(theta) = 2 / d. The
    camera 4 above the floor looks down with a field of view of 0.7 across the image; a
    ``sub`` x ``sub`` grid of points per pixel integrates it (its error is below 1e-6)."""
    half = np.tan(0.35)
    f = (np.arange(n * sub) + 0.5) / sub  # film positions, pixels
    x = 4 * half * (f / n * 2 - 1)
    y = 4 * half * (1 - f / n * 2)
    d2 = x[None, :] ** 2 + y[:, None] ** 2 + 4.0
    radiance = 0.8 / np.pi * 200 / (4 * np.pi) * 2 / d2 ** 1.5
    return radiance.reshape(n, sub, n, sub).mean(axis=(1, 3))


def block_z(image, exact, error, block=8):
    """Per block x block block: (image mean - exact mean) / the standard error of the
    image's mean (from the ``error`` AOV; a box filter keeps pixels independent), per channel.
    A floor of 1e-6 relative stands for float32 rounding where the error AOV is zero."""
    h, w = exact.shape[:2]
    shape = (h // block, block, w // block, block, -1)
    m = image.reshape(shape).mean(axis=(1, 3))
    e = exact.reshape(shape).mean(axis=(1, 3))
    se = np.sqrt((error.astype(np.float64) ** 2).reshape(shape).sum(axis=(1, 3))) / block**2
    return (m - e) / np.maximum(se, 1e-6 * np.abs(e))


@pytest.mark.parametrize("dtype,idx", [(np.float64, np.int64), (np.float32, np.uint32), (np.float16, np.int16)])
def test_numpy_scene_renders_the_lambert_floor(dtype, idx):
    """The numpy scene (any dtype) renders the closed form of its floor: the beauty, per 8x8
    block and channel, within 4.5 standard errors of the exact image (48 block channels: a
    false alarm under 10^-3); all of it is direct light, the other terms are zeros (nothing
    for the floor's light to bounce off, no light in view)."""
    out = photonmap.render(numpy_scene(dtype=dtype, idx_dtype=idx), spp=8, seed=3,
                           filter="box", adaptive_sampling=False)
    c = out["combined"]
    assert c.shape == (32, 32, 3) and c.dtype == np.float32
    for t in photonmap.TERMS:
        assert out[t].shape == c.shape and out[t].dtype == np.float32
        if t != "direct":
            assert not out[t].any(), t
    exact = np.repeat(floor_radiance()[..., None], 3, axis=2)
    z = block_z(c, exact, out["error"])
    print(f"\nfloor vs closed form: worst |z| {np.abs(z).max():.2f}, "
          f"largest relative error {np.abs(c / exact - 1).max():.2e}")
    assert np.abs(z).max() < 4.5, z
    assert out["stats"]["spp"] == 8 and out["stats"]["seed"] == 3


def test_same_seed_same_image_any_threads():
    a = photonmap.render(numpy_scene(), spp=2, seed=5, threads=1)["combined"]
    b = photonmap.render(numpy_scene(), spp=2, seed=5, threads=2)["combined"]
    assert np.array_equal(a, b)


def test_progress_callback_runs_on_calling_thread():
    calls, threads = [], set()

    def cb(f, phase):
        calls.append((f, phase))
        threads.add(threading.get_ident())

    photonmap.render(numpy_scene(64), spp=4, progress=cb)
    assert calls and calls[-1][0] == pytest.approx(1.0)
    assert threads == {threading.get_ident()}
    assert all(isinstance(p, str) for _, p in calls)


def test_cancel_token_returns_quickly():
    r = photonmap.Renderer(numpy_scene(200), spp=2048)
    threading.Timer(0.3, r.cancel).start()
    seen = []
    with pytest.raises(photonmap.RenderCancelled):
        r.render(progress=lambda f, p: seen.append((f, p)))
    # Stopped long before the end of the camera pass (2048 samples per pixel take far longer
    # than 0.3 s). Fractions are per phase: the photon pass may have reported most of itself.
    camera = [f for f, p in seen if p == "render"]
    assert max(camera, default=0.0) < 0.5, seen


def test_progress_exception_cancels_and_propagates():
    calls = []

    def cb(f, p):
        calls.append(f)
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        photonmap.render(numpy_scene(200), spp=2048, progress=cb)
    # The first report raised, and the render stopped there: the callback was not called again.
    assert len(calls) == 1


CTRL_C = r"""
import _thread, json, signal, sys, threading
import photonmap
from test_api import numpy_scene

# A process started in the background of a non-interactive shell inherits SIGINT ignored,
# and Python then installs no handler for it: Ctrl-C is Python's again here.
signal.signal(signal.SIGINT, signal.default_int_handler)

token = photonmap.CancelToken()
seen = []


def progress(fraction, phase):
    seen.append((fraction, phase))
    # Ctrl-C once the camera pass has reported itself, from another thread, as a user would.
    if phase == "render" and len([p for _, p in seen if p == "render"]) == 1:
        threading.Thread(target=_thread.interrupt_main).start()


try:
    # 10^6 samples per pixel: hours of camera pass; only a cancel ends it.
    photonmap.render(numpy_scene(64), spp=1_000_000, cancel=token, progress=progress)
except KeyboardInterrupt:
    print(json.dumps({"interrupted": True, "cancelled": token.cancelled, "seen": seen}))
    sys.exit(0)
print(json.dumps({"interrupted": False, "cancelled": token.cancelled, "seen": seen}))
sys.exit(1)
"""


def test_keyboard_interrupt_cancels():
    """Ctrl-C during a render (SIGINT raised in the main thread from another one) cancels it:
    the calling thread checks for signals every 50 ms, sets the core's cancel flag (the token
    passed in reads it) and raises KeyboardInterrupt once the render thread has stopped. The
    camera pass asked for (10^6 samples per pixel) would take hours: a Ctrl-C that did not
    stop the core would hang the test until its timeout. In a process of its own, with Python's
    SIGINT handler installed (a test run started in the background of a shell has SIGINT
    ignored, and then no interrupt reaches Python at all)."""
    import json

    r = subprocess.run([sys.executable, "-c", CTRL_C], cwd=os.path.dirname(__file__),
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    got = json.loads(r.stdout.strip().splitlines()[-1])
    assert got["interrupted"] and got["cancelled"], got
    camera = [f for f, p in got["seen"] if p == "render"]
    # Interrupted in the camera pass, which never reported itself finished.
    assert camera and max(camera) < 1.0, got["seen"]


def test_invalid_dict_is_a_scene_error_naming_the_field():
    s = numpy_scene()
    s["meshes"][0]["indices"] = np.array([[0, 1, 9]])
    with pytest.raises(photonmap.SceneError, match=r"/meshes/0/indices/0/2.*floor"):
        photonmap.Scene.from_dict(s)
    s = numpy_scene()
    s["lights"][0]["power"] = -1
    with pytest.raises(ValueError, match=r"/lights/0/power.*lamp"):
        photonmap.Scene.from_dict(s)
    s = numpy_scene()
    s["camera"] = dict(CAM, bogus=1)
    with pytest.raises(photonmap.SceneError, match=r"/camera/bogus"):
        photonmap.Scene.from_dict(s)
    s = numpy_scene()
    s["textures"] = [{"width": 1, "height": 1, "channels": 3, "data": [0.5] * 3,
                      "encoding": "gamma22"}]
    with pytest.raises(photonmap.SceneError, match=r"/textures/0/encoding.*`linear` or `srgb`"):
        photonmap.Scene.from_dict(s)
    s = numpy_scene()
    s["lights"][0]["power"] = "bright"
    with pytest.raises(photonmap.SceneError, match=r"/lights/0 .*lamp.*bright"):
        photonmap.Scene.from_dict(s)
    s = numpy_scene()
    s["meshes"][0]["positions"] = np.zeros((4, 2))
    with pytest.raises(photonmap.SceneError, match=r"/meshes/0/positions"):
        photonmap.Scene.from_dict(s)
    s = numpy_scene()
    s["meshes"][0]["positions"] = np.array([[np.nan, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    with pytest.raises(photonmap.SceneError, match=r"/meshes/0/positions/0/0"):
        photonmap.Scene.from_dict(s)
    s = numpy_scene()
    s["meshes"][0]["indices"] = np.array([[0, 1, -2]])
    with pytest.raises(photonmap.SceneError, match=r"/meshes/0/indices/0/2"):
        photonmap.Scene.from_dict(s)
    s = numpy_scene()
    s["meshes"][0]["attributes"] = {"Paint": np.ones((3, 4), np.float32)}
    with pytest.raises(photonmap.SceneError, match=r"/meshes/0/attributes/Paint.*3 entries for 4"):
        photonmap.Scene.from_dict(s)


def test_a_mesh_attribute_colours_the_floor_through_an_attribute_node():
    """Per-vertex attributes interpolate across the triangles: a floor emitting its 'Paint'
    attribute shows the blend of its corners' colours."""
    s = numpy_scene(n=16)
    s["lights"] = []
    s["meshes"][0]["attributes"] = {"Paint": np.array(
        [[1, 0, 0, 1], [1, 0, 0, 1], [0, 0, 1, 1], [0, 0, 1, 1]], np.float32)}
    s["materials"] = [{"type": "graph", "name": "painted", "nodes": [
        {"type": "attribute", "params": {"name": "Paint"}},
        {"type": "emission", "inputs": {"color": {"node": 0, "output": "color"},
                                        "strength": 1.0}}], "surface": {"node": 1}}]
    out = photonmap.render(photonmap.Scene.from_dict(s), spp=4, seed=1)
    img = out["combined"][..., :3]
    covered = img.sum(-1) > 0.5
    assert covered.mean() > 0.2
    # Red and blue always sum to one where the floor is seen; green is zero.
    rb = img[..., 0] + img[..., 2]
    assert np.allclose(rb[covered], 1.0, atol=1e-3) and np.all(img[..., 1][covered] < 1e-4)
    # Both ends of the ramp are in view.
    assert img[..., 0][covered].max() > 0.7 and img[..., 2][covered].max() > 0.7


def test_panic_becomes_an_exception():
    with pytest.raises(photonmap.PhotonmapError, match="panicked"):
        photonmap._core._panic_for_test()


def test_json_round_trip_and_bad_settings():
    s = photonmap.Scene.from_dict(numpy_scene())
    again = photonmap.Scene.from_json(s.to_json())
    assert again.to_json() == s.to_json()
    with pytest.raises(ValueError, match="quality"):
        photonmap.render(s, quality="ultra")
    with pytest.raises(ValueError, match="`spp`"):
        photonmap.render(s, spp=0)


def test_default_scene_and_settings_like_cli():
    out = photonmap.render(photonmap.default_scene(), quality="draft", spp=1, seed=0,
                           photons=1000, gather=10, radius=0.1, final_gather_rays=4,
                           irradiance_cache=False, cache_tolerance=0.3)
    assert out["combined"].shape == (512, 512, 3)


def test_keywords_arrive_in_the_recorded_settings():
    """Every keyword lands in the core's settings, as the stats record them; the defaults of
    the keywords no preset sets are the CLI's (``photonmap.defaults``)."""
    out = photonmap.render(photonmap.Scene.from_dict(numpy_scene()), quality="draft", spp=1,
                           seed=5, photons=1000, caustic_photons=500, volume_photons=300,
                           gather=10, radius=0.1, final_gather_rays=4, irradiance_cache=False,
                           cache_tolerance=0.3, max_specular_depth=3, filter="box",
                           photon_power="f32")
    s = out["stats"]["settings"]
    assert (s["spp"], s["seed"], s["max_specular_depth"], s["filter"]) == (1, 5, 3, "box")
    assert (s["photons"], s["caustic_photons"], s["volume_photons"], s["gather"]) == (
        1000, 500, 300, 10)
    assert s["radius"] == pytest.approx(0.1)
    assert (s["final_gather_rays"], s["irradiance_cache"], s["photon_power"]) == (
        4, False, "f32")
    assert s["cache_tolerance"] == pytest.approx(0.3)
    # The settings recorded are the keywords' names and values: the options render again.
    assert {k: s[k] for k in out["stats"]["options"]} == out["stats"]["options"]
    d = photonmap.defaults()
    plain = photonmap.render(photonmap.Scene.from_dict(numpy_scene()), quality="draft", spp=1)
    s = plain["stats"]["settings"]
    assert (s["seed"], s["threads"], s["filter"], s["mode"]) == (
        d["seed"], d["threads"], d["filter"], d["mode"])
    assert s["alpha"] == pytest.approx(d["alpha"])
    assert s["initial_photons"] == d["initial_photons"]
    assert s["progressive"] == d["progressive"]


def test_density_grid_from_numpy_renders_fog():
    """A heterogeneous medium from a numpy density grid (shape nz, ny, nx): a cube of fog whose
    density ramps along x scatters more light where it is denser."""
    import numpy as np
    import photonmap

    ramp = np.tile(np.linspace(0.0, 2.0, 8, dtype=np.float32), (8, 8, 1))  # (z, y, x)
    box = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                    [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=np.float32)
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 5), (0, 4, 7, 3)]
    tris = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))], dtype=np.uint32)
    ir = {
        "camera": {"fov": 0.9, "transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4], [0, 0, 0, 1]]},
        "film": {"width": 24, "height": 24},
        "materials": [{"type": "null"}],
        "meshes": [{"name": "fog", "positions": box, "indices": tris, "interior_medium": 0}],
        "media": [{"name": "ramp", "sigma_a": [0.1] * 3, "sigma_s": [0.9] * 3, "g": 0.0,
                   "density": {"data": ramp,
                               "transform": [[2, 0, 0, -1], [0, 2, 0, -1], [0, 0, 2, -1], [0, 0, 0, 1]]}}],
        "lights": [{"type": "distant", "direction": [0, -1, 0], "irradiance": 2.0}],
    }
    out = photonmap.render(photonmap.Scene.from_dict(ir), quality="draft", seed=1)
    vol = out["volume"]
    assert np.isfinite(vol).all() and vol.max() > 0
    left, right = vol[:, 6:10].mean(), vol[:, 14:18].mean()
    assert right > 1.5 * left, (left, right)
    assert out["stats"]["photon_maps"][-1]["map"] == "volume"
