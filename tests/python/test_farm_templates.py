"""The farm templates of ``farm/``: the Open Job Description templates validate (``openjd
check``) and run locally (``openjd run``) to the bits of the same render in one process; the
Flamenco job type is valid JavaScript that defines ``JOB_TYPE`` and ``compileJob``."""
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest
from conftest import ROOT, SCENES, write_scene_usda

pytest.importorskip("openjd.cli")
OIIO = pytest.importorskip("OpenImageIO")

FARM = os.path.join(ROOT, "farm")
BIN = os.path.dirname(sys.executable)
ENV = dict(os.environ, PATH=BIN + os.pathsep + os.environ.get("PATH", ""))
OPENJD = os.path.join(BIN, "openjd") if os.path.exists(os.path.join(BIN, "openjd")) else "openjd"


def pixels(path):
    b = OIIO.ImageBuf(str(path))
    return b.get_pixels(OIIO.FLOAT).view(np.uint32)


def openjd(*args):
    r = subprocess.run([OPENJD, *args], capture_output=True, text=True, env=ENV, timeout=600)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    return r.stdout


def photonmap(*args):
    r = subprocess.run([sys.executable, "-m", "photonmap.cli", *args], capture_output=True,
                       text=True, env=ENV, timeout=600)
    assert r.returncode == 0, r.stderr
    return r


@pytest.mark.parametrize("name", ["photonmap-frames.yaml", "photonmap-passes.yaml"])
def test_openjd_templates_validate(name):
    out = openjd("check", os.path.join(FARM, "openjd", name))
    assert "passes validation" in out


@pytest.fixture(scope="module")
def stage(tmp_path_factory):
    desc = json.load(open(os.path.join(SCENES, "cornell_spheres.json")))
    path = str(tmp_path_factory.mktemp("farm") / "anim.usda")
    return write_scene_usda(path, desc, camera_x=(0.0, 0.05))


def test_openjd_runs_a_2_frame_job(stage, tmp_path):
    size = "--width 48 --height 36"
    openjd("run", os.path.join(FARM, "openjd", "photonmap-frames.yaml"), "--step", "Frames",
           "--run-dependencies", "-p", f"Scene={stage}", "-p", f"OutputDir={tmp_path / 'job'}",
           "-p", "Frames=1-2", "-p", "FirstFrame=1", "-p", "Quality=draft",
           "-p", f"ExtraArgs={size}")
    photonmap("render", stage, "--frames", "1:2", "-o", str(tmp_path / "one.#.exr"),
              "--quality", "draft", *size.split(), "--quiet")
    for f in (1, 2):
        job = tmp_path / "job" / f"frame.{f:04d}.exr"
        assert np.array_equal(pixels(job), pixels(tmp_path / f"one.{f:04d}.exr")), f
        st = json.load(open(tmp_path / "job" / f"stats.{f:04d}.json"))["photon_map_reuse"]
        assert st["maps"] == "loaded", st
    assert (tmp_path / "job" / "photon_maps.pmaps").exists()


def test_openjd_runs_pass_blocks_and_their_merge(stage, tmp_path):
    openjd("run", os.path.join(FARM, "openjd", "photonmap-passes.yaml"), "--step", "Merge",
           "--run-dependencies", "-p", f"Scene={stage}", "-p", f"OutputDir={tmp_path / 'job'}",
           "-p", "Frame=2", "-p", "Blocks=2", "-p", "PassesPerBlock=2", "-p", "Photons=5000",
           "-p", "ExtraArgs=--width 48 --height 36")
    photonmap("render", stage, "--frames", "2", "--mode", "pppm", "--spp", "4", "--photons",
              "5000", "--width", "48", "--height", "36", "-o", str(tmp_path / "one.exr"),
              "--quiet")
    assert np.array_equal(pixels(tmp_path / "job" / "frame.0002.exr"),
                          pixels(tmp_path / "one.exr"))
    st = json.load(open(tmp_path / "job" / "stats.0002.json"))
    assert st["pppm"]["partials"] == 2 and st["pppm"]["passes"] == 4


@pytest.mark.skipif(shutil.which("node") is None, reason="needs node")
def test_the_flamenco_job_type_compiles_a_job():
    """Runs the job type's compileJob in node against a small stand-in of Flamenco's
    authoring API, and checks the tasks it makes: photon maps first, then frame chunks
    that load them."""
    harness = os.path.join(ROOT, "tests", "python", "flamenco_harness.js")
    r = subprocess.run(["node", harness, os.path.join(FARM, "flamenco", "photonmap.js")],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    job = json.loads(r.stdout)
    names = [t["name"] for t in job["tasks"]]
    assert names[0] == "photon-maps" and names[1:] == ["frames-2-3", "frames-4-5", "frames-6"]
    first = job["tasks"][0]["commands"][0]["parameters"]
    assert "save_photon_maps" in " ".join(first["args"])
    for t in job["tasks"][1:]:
        assert t["dependencies"] == ["photon-maps"]
        assert "load_photon_maps" in " ".join(t["commands"][0]["parameters"]["args"])
