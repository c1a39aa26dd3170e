"""Rendering on Dask (``photonmap render ... --cluster``): a local cluster of 2 worker
processes on 127.0.0.1 renders a USD camera animation, a pppm frame in blocks of passes and
a Jensen frame in tiles, each to the bits of the same command in one process; a worker
killed mid-job costs nothing; the pass-block Python API merges bit-exactly."""
import json
import os
import signal
import subprocess
import sys
import threading

import numpy as np
import pytest
from conftest import SCENES, write_scene_usda

import photonmap
from photonmap import cli

distributed = pytest.importorskip("distributed")
from photonmap import distributed as pmd  # noqa: E402

OIIO = pytest.importorskip("OpenImageIO")


def exr(path):
    """Every channel of an EXR, as float32 (H, W, C), and the channel names."""
    b = OIIO.ImageBuf(str(path))
    return b.get_pixels(OIIO.FLOAT), list(b.spec().channelnames)


def same_bits(a, b):
    (pa, ca), (pb, cb) = exr(a), exr(b)
    assert ca == cb
    return np.array_equal(pa.view(np.uint32), pb.view(np.uint32))


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       host="127.0.0.1", dashboard_address=":0")
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


@pytest.fixture(scope="module")
def animation(tmp_path_factory):
    """The caustic Cornell box (glass and mirror spheres) as USD, the camera moving."""
    desc = json.load(open(os.path.join(SCENES, "cornell_spheres.json")))
    path = str(tmp_path_factory.mktemp("anim") / "anim.usda")
    return write_scene_usda(path, desc, camera_x=(0.0, 0.04, 0.08))


SMALL = ["--width", "64", "--height", "48", "--seed", "5", "--quiet", "--photons", "20000",
         "--caustic-photons", "10000", "--final-gather-rays", "32"]


def one_process(argv):
    assert cli.main(list(argv)) == 0


def test_a_camera_animation_renders_the_same_bits(client, animation, tmp_path):
    argv = ["render", animation, "--frames", "1:3", *SMALL, "--spp", "4"]
    one_process(argv + ["-o", str(tmp_path / "one.#.exr"), "--stats", str(tmp_path / "one.#.json")])
    stats = pmd.render(argv + ["-o", str(tmp_path / "dist.#.exr")], client, threads=1)
    assert len(stats) == 3
    for f in (1, 2, 3):
        assert same_bits(tmp_path / f"one.{f:04d}.exr", tmp_path / f"dist.{f:04d}.exr"), f
        reuse = json.load(open(tmp_path / f"one.{f:04d}.json"))["photon_map_reuse"]
        # The command builds the maps once, for frame 1; frames 2 and 3 reuse them.
        assert reuse["maps"] == ("built" if f == 1 else "reused"), reuse
        assert reuse["cache"] == ("filled" if f == 1 else "extended"), reuse
    assert all(s["photon_map_reuse"]["maps"] == "reused" for s in stats)
    assert not [p for p in os.listdir(tmp_path) if ".tmp" in p]


def test_a_pppm_frame_of_8_passes_in_blocks(client, animation, tmp_path):
    argv = ["render", animation, "--frames", "2", "--mode", "pppm", *SMALL, "--spp", "8",
            "--memory-limit", "8G"]
    one_process(argv + ["-o", str(tmp_path / "one.exr"), "--stats", str(tmp_path / "one.json")])
    stats = pmd.render(argv + ["-o", str(tmp_path / "dist.exr"), "--block-passes", "3"],
                       client, threads=1)
    assert same_bits(tmp_path / "one.exr", tmp_path / "dist.exr")
    (st,) = stats
    assert st["pppm"]["passes"] == 8 and st["pppm"]["partials"] == 3
    assert st["distributed"]["blocks"] == 3 and st["distributed"]["merge_tasks"] == 2
    # The merged stats are a whole render's: its keys (the USD importer's figures aside) and
    # settings (the blocks were given r_1 and one thread each), the last pass's stored photons.
    one = json.load(open(tmp_path / "one.json"))
    assert set(st) | {"import"} == set(one) | {"distributed"}
    assert st["settings"]["initial_radius"] == st["pppm"]["initial_radius"]
    for s in (st["settings"], one["settings"]):
        s.pop("threads"), s.pop("initial_radius")
    assert st["settings"] == one["settings"]
    assert [(m["map"], m["stored"]) for m in st["photon_maps"]] == \
        [(m["map"], m["stored"]) for m in one["photon_maps"]]


def test_a_jensen_frame_in_4_tiles(client, animation, tmp_path):
    argv = ["render", animation, "--frames", "3", *SMALL, "--spp", "4", "--max-spp", "32",
            "--noise-threshold", "0.05"]
    one_process(argv + ["-o", str(tmp_path / "one.exr"), "--stats", str(tmp_path / "one.json")])
    stats = pmd.render(argv + ["-o", str(tmp_path / "dist.exr"), "--tiles", "2x2",
                               "--stats", str(tmp_path / "dist.json")], client, threads=1)
    assert same_bits(tmp_path / "one.exr", tmp_path / "dist.exr")
    one, dist = json.load(open(tmp_path / "one.json")), json.load(open(tmp_path / "dist.json"))
    assert dist["distributed"]["tiles"] == 4 and dist["distributed"]["stages"] == 2
    # Adaptive sampling decided over the whole frame: the same samples as in one process.
    assert dist["adaptive"]["pixels_refined"] == one["adaptive"]["pixels_refined"] > 0
    assert dist["camera_rays"] == one["camera_rays"]
    # Adaptive sampling's figures and the memory over the frame, as the core computes them.
    assert dist["adaptive"] == one["adaptive"]
    assert dist["memory_bytes"] == one["memory_bytes"]
    assert stats[0]["width"] == 64


def test_a_worker_killed_mid_job_changes_nothing(animation, tmp_path):
    argv = ["render", animation, "--frames", "1", "--mode", "pppm", *SMALL, "--spp", "12"]
    one_process(argv + ["-o", str(tmp_path / "one.exr")])
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       host="127.0.0.1", dashboard_address=":0")
    client = distributed.Client(cluster)
    try:
        pids = client.run(os.getpid)
        victim = sorted(pids.values())[0]
        killed = threading.Event()

        def kill_once(done, total, what):
            # After the first block is in, kill a worker while the others run.
            if what == "passes" and done >= 2 and not killed.is_set():
                killed.set()
                os.kill(victim, signal.SIGKILL)

        pmd.render(argv + ["-o", str(tmp_path / "dist.exr"), "--block-passes", "1"], client,
                   threads=1, on_progress=kill_once)
        assert killed.is_set()
        assert victim not in client.run(os.getpid).values()
        assert same_bits(tmp_path / "one.exr", tmp_path / "dist.exr")
    finally:
        client.close()
        cluster.close()


def test_the_command_line_starts_a_local_cluster(tmp_path):
    scene = os.path.join(SCENES, "cornell_diffuse.json")
    base = [sys.executable, "-m", "photonmap.cli", "render", scene, "--width", "40",
            "--height", "30", "--quality", "draft", "--seed", "2", "--quiet"]
    r = subprocess.run(base + ["-o", str(tmp_path / "a.exr")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    r = subprocess.run(base + ["-o", str(tmp_path / "b.exr"), "--cluster", "local:2"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert same_bits(tmp_path / "a.exr", tmp_path / "b.exr")


def test_without_dask_the_error_names_the_extra(tmp_path):
    code = ("import sys; sys.modules['distributed'] = None; from photonmap.cli import main; "
            f"sys.exit(main(['render', '-o', {str(tmp_path / 'x.exr')!r}, '--cluster', 'local:2']))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 1
    assert "pip install 'photonmap[distributed]'" in r.stderr, r.stderr


def test_bad_cluster_arguments_are_clear_errors(tmp_path):
    out = ["-o", str(tmp_path / "x.exr")]
    assert pmd.main(["render", *out, "--cluster", "local:0"]) == 1
    assert pmd.main(["render", *out, "--cluster", "local:2", "--spp", "0"]) == 2
    with pytest.raises(pmd.DistributedError, match="time-budget"):
        pmd.render(["render", *out, "--time-budget", "5"], None)


def test_pass_blocks_merge_through_the_python_api():
    scene = photonmap.Scene.from_file(os.path.join(SCENES, "cornell_spheres.json"))
    kw = dict(mode="pppm", spp=6, photons=5000, seed=4)
    whole = photonmap.render(scene, **kw)
    parts = [photonmap.render(scene, pass_range=r, threads=t, **kw)["partial"]
             for r, t in (((3, 6), 1), ((0, 2), 2), ((2, 3), 1))]
    merged = photonmap.merge_partials(parts)
    for k in ("combined", "error") + photonmap.TERMS:
        assert np.array_equal(merged[k].view(np.uint32), whole[k].view(np.uint32)), k
    assert merged["stats"]["pppm"]["passes"] == 6
    with pytest.raises(ValueError, match="passes 2..3 of the render's 6 are missing"):
        photonmap.merge_partials(parts[:2])
    with pytest.raises(ValueError, match="passes 3..6 of the render's 6 are missing"):
        photonmap.merge_partials(parts[1:])
    with pytest.raises(ValueError, match="counted twice"):
        photonmap.merge_partials([parts[0], parts[0]])
    with pytest.raises(ValueError, match="pass_range"):
        photonmap.render(scene, pass_range=(0, 2), spp=4)
