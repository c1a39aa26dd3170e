"""The add-on's status-bar line (``blender_addon/status.py``, plain Python, loaded here without
Blender): its memory is the render's ``memory_bytes``, which already holds the photon maps'."""
import importlib.util
import json
import os

from conftest import ROOT, SCENES

import photonmap


def _status():
    path = os.path.join(ROOT, "blender_addon", "status.py")
    spec = importlib.util.spec_from_file_location("photonmap_addon_status", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_status_line_counts_the_photon_maps_once():
    stats_line = _status().stats_line
    mib = 1024 * 1024
    line = stats_line({"memory_bytes": 3 * mib, "photon_maps": [{"memory_bytes": mib}]})
    assert line.split(" | ")[-1] == "3.0 MiB", line

    desc = json.load(open(os.path.join(SCENES, "cornell_spheres.json")))
    desc["film"].update(width=32, height=24)
    st = photonmap.render(desc, spp=1, photons=20000, caustic_photons=20000, seed=2)["stats"]
    maps = sum(m["memory_bytes"] for m in st["photon_maps"])
    # The core's figure holds the maps (src/render/stats.rs); large enough here to show twice.
    assert maps > mib / 10 and st["memory_bytes"] > maps
    line = stats_line(st)
    assert f"{st['memory_bytes'] / mib:.1f} MiB" in line.split(" | "), line
    assert f"{(st['memory_bytes'] + maps) / mib:.1f} MiB" not in line, line
    assert line.startswith("photons stored: ") and "caustic" in line, line
