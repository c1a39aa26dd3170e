"""``photonmap render ... --cluster ADDRESS|local:N``: a render command on a Dask cluster
(the optional extra ``pip install 'photonmap[distributed]'``).

The command is split into tasks that each run a piece of it through the core
(``photonmap._core.Job``), parsed from the same command line on the worker:

- **Frames** (``--frames A:B``): one task per frame. When frames reuse the first frame's
  photon maps (Jensen's mode, ``--frame-photon-maps reuse``, the default), one task builds
  them first (maps and irradiance cache for the first frame's view); they are broadcast to
  every worker (``scatter(..., broadcast=True)``), and each frame task reuses them where its
  scene matches the first frame's (the camera aside), as the command does in one process.
- **One pppm frame** (``--mode pppm``): r_1 computed once, then blocks of passes
  (``--block-passes``), whose partial sums are added pairwise on the workers (a tree) and
  the total written by the client.
- **One Jensen frame**: the photon maps and the irradiance cache built once for the frame
  and broadcast, then tiles (``--tiles CxR``); with adaptive sampling in two stages (the
  first round of every tile, then the rounds decided from the whole image).
- **One sppm frame** (its passes depend on each other), or a Jensen frame in whole passes
  (``--progressive``): one task.

Every piece is deterministic and depends only on the command line, its scene and what it is
given, so the outputs are the bits of the command run in one process, whatever the workers
and the order. A task whose worker dies is run again by Dask (``RETRIES``); frames are written
by their task, other outputs by the client, always to a temporary file renamed over the
output, so a crash never leaves a partial EXR under the final name. With workers on several
machines, the scene and the outputs must be on a file system they share.
"""

from __future__ import annotations

import json
import math
import os
import sys
import time
from typing import Any, Callable

import numpy as np

from . import _core, tile_stats

#: How the extra is installed, for the error when Dask is missing.
EXTRA = "pip install 'photonmap[distributed]'"

#: Times Dask runs a task again after it raised (a worker lost is rescheduled anyway).
RETRIES = 2


class DistributedError(RuntimeError):
    """A distributed render cannot start (Dask missing, a bad --cluster)."""


def require_dask():
    """The ``distributed`` module, or DistributedError naming the extra to install."""
    try:
        import dask  # noqa: F401
        import distributed
    except ImportError as e:
        raise DistributedError(
            f"--cluster needs Dask, which is not installed (no module {e.name!r}): {EXTRA}"
        ) from None
    return distributed


def strip_cluster(argv: list[str]) -> tuple[list[str], str | None]:
    """``argv`` without ``--cluster X`` / ``--cluster=X``, and X."""
    out, address, skip = [], None, False
    for i, a in enumerate(argv):
        if skip:
            skip = False
            continue
        if a == "--cluster":
            if i + 1 >= len(argv):
                raise DistributedError("--cluster needs a value: a scheduler address or local:N")
            address, skip = argv[i + 1], True
        elif a.startswith("--cluster="):
            address = a.split("=", 1)[1]
        else:
            out.append(a)
    return out, address


def connect(address: str):
    """A client of the cluster at ``address`` (``tcp://host:port``, or ``local:N``: a
    LocalCluster of N worker processes on 127.0.0.1); returns (client, cluster or None)."""
    distributed = require_dask()
    if address.startswith("local:"):
        try:
            n = int(address.split(":", 1)[1])
        except ValueError:
            n = 0
        if n < 1:
            raise DistributedError(f"--cluster {address}: expected local:N with N >= 1 workers")
        import logging

        cluster = distributed.LocalCluster(
            n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
            dashboard_address=":0", silence_logs=logging.ERROR,
        )
        return distributed.Client(cluster), cluster
    try:
        return distributed.Client(address, timeout="30s"), None
    except OSError as e:
        raise DistributedError(f"--cluster {address}: cannot reach the scheduler: {e}") from None


# --- Tasks: module-level functions, run on the workers. ---------------------------------

def _load(job, frame):
    from .cli import _usd_loader

    return job.scene(frame, _usd_loader([]))


def task_frame(argv, frame, maps, threads):
    """Renders and writes one frame; returns its stats."""
    job = _core.Job(argv)
    scene, imp = _load(job, frame)
    return json.loads(job.render_frame(scene, frame, imp, maps, threads))


def task_maps(argv, frame, threads):
    """The photon maps and irradiance cache of a frame's view (a photon-map file's bytes)."""
    job = _core.Job(argv)
    scene, _ = _load(job, frame)
    return job.build_maps(scene, threads)


def task_radius(argv, frame, threads):
    job = _core.Job(argv)
    scene, _ = _load(job, frame)
    return job.pppm_radius(scene, threads)


def task_passes(argv, frame, first, end, r1, threads):
    """pppm passes first..end as a partial-sum file's bytes."""
    job = _core.Job(argv)
    scene, _ = _load(job, frame)
    return job.render_passes(scene, first, end, r1, threads)


def task_tile_first(argv, frame, maps, rect, threads):
    job = _core.Job(argv)
    scene, _ = _load(job, frame)
    return job.tile_first(scene, maps, rect, threads)


def task_tile_finish(argv, frame, maps, rect, rounds, first, threads):
    """A tile's film and its stats (JSON)."""
    job = _core.Job(argv)
    scene, _ = _load(job, frame)
    state = first[2] if first is not None else None
    return job.tile_finish(scene, maps, rect, rounds, state, threads)


def task_add(a, b):
    """The sum of two partial sums (a step of the merge's tree reduction)."""
    return _core.add_partials([a, b])


def _item(t, i):
    return t[i]


# --- The client. ---------------------------------------------------------------------------

class Progress:
    """Progress of the whole job on stderr: tasks done of the tasks submitted so far."""

    def __init__(self, quiet: bool, callback: Callable[[int, int, str], Any] | None = None):
        self.quiet, self.callback = quiet, callback
        self.done = self.total = 0
        self.last = 0.0
        self.t0 = time.monotonic()

    def add(self, n: int) -> None:
        self.total += n

    def step(self, what: str) -> None:
        self.done += 1
        if self.callback is not None:
            self.callback(self.done, self.total, what)
        now = time.monotonic()
        if not self.quiet and (now - self.last > 0.5 or self.done == self.total):
            self.last = now
            line = f"{what:>9} {self.done}/{self.total} tasks, {now - self.t0:.1f} s"
            print(f"\r{line:<50}", end="", file=sys.stderr, flush=True)

    def finish(self) -> None:
        if not self.quiet and self.total:
            print(file=sys.stderr)


def _workers(client) -> int:
    return max(1, len(client.scheduler_info().get("workers", {})))


def _wait(client, futures, progress: Progress, what: str) -> list:
    """The results of ``futures`` in their order, stepping ``progress`` as each completes."""
    from distributed import as_completed

    progress.add(len(futures))
    for _ in as_completed(futures):
        progress.step(what)
    return client.gather(futures)


def render(argv: list[str], client, *, threads: int | None = None,
           on_progress: Callable[[int, int, str], Any] | None = None) -> list[dict]:
    """Renders the command ``argv`` (``render SCENE -o OUT ...``, without ``--cluster``) on
    the cluster of ``client``; returns each frame's stats. ``threads`` is each task's thread
    count (default: the command's ``--threads``); ``on_progress(done, total, what)`` is
    called as tasks complete."""
    job = _core.Job(argv)
    info = json.loads(job.info())
    if info["time_budget"]:
        raise DistributedError("--cluster cannot be combined with --time-budget: a budget "
                               "plans the render from one machine's speed")
    frames = job.frames()
    progress = Progress(info["quiet"], on_progress)
    try:
        if len(frames) > 1:
            return _frames(client, argv, job, info, frames, threads, progress)
        frame = frames[0]
        if info["mode"] == "pppm":
            return [_pppm(client, argv, job, info, frame, threads, progress)]
        if info["mode"] == "jensen" and not info["progressive"]:
            return [_tiles(client, argv, job, info, frame, threads, progress)]
        # sppm (each pass depends on the last), or Jensen's whole passes: one task.
        fut = client.submit(task_frame, argv, frame, None, threads, retries=RETRIES, pure=False)
        return _wait(client, [fut], progress, "frame")
    finally:
        progress.finish()


def _frames(client, argv, job, info, frames, threads, progress):
    maps = None
    if info["frame_maps_reused"]:
        fut = client.submit(task_maps, argv, frames[0], threads, retries=RETRIES)
        data = _wait(client, [fut], progress, "maps")[0]
        maps = client.scatter(data, broadcast=True)
    futs = [client.submit(task_frame, argv, f, maps, threads, retries=RETRIES) for f in frames]
    return _wait(client, futs, progress, "frames")


def _pppm(client, argv, job, info, frame, threads, progress):
    spp = info["spp"]
    r1 = info["initial_radius"]
    if r1 is None:
        fut = client.submit(task_radius, argv, frame, threads, retries=RETRIES)
        r1 = _wait(client, [fut], progress, "radius")[0]
    per = info["block_passes"] or max(1, math.ceil(spp / (2 * _workers(client))))
    blocks = [(a, min(a + per, spp)) for a in range(0, spp, per)]
    futs = [client.submit(task_passes, argv, frame, a, b, r1, threads, retries=RETRIES)
            for a, b in blocks]
    # A tree reduction on the workers: pairs of partial sums added where they are, so the
    # client receives one, and the adds run in parallel (integer sums: any order, same bits).
    level = futs
    merges = []
    while len(level) > 1:
        nxt = [client.submit(task_add, level[i], level[i + 1], retries=RETRIES)
               for i in range(0, len(level) - 1, 2)]
        merges += nxt
        level = nxt + level[len(level) - len(level) % 2:]
    _wait(client, futs + merges, progress, "passes")
    total = level[0].result()
    extra = {"distributed": {"workers": _workers(client), "blocks": len(blocks),
                             "passes_per_block": per, "merge_tasks": len(merges)}}
    return json.loads(job.write_merged(frame, [total], json.dumps(extra)))


def _split(width, height, cols, rows):
    cols, rows = max(1, min(cols, width)), max(1, min(rows, height))
    out = []
    for r in range(rows):
        y0, y1 = r * height // rows, (r + 1) * height // rows
        for c in range(cols):
            x0, x1 = c * width // cols, (c + 1) * width // cols
            out.append((x0, y0, x1 - x0, y1 - y0))
    return out


def _tiles(client, argv, job, info, frame, threads, progress):
    scene, _ = _load(job, frame)
    width, height = scene.width, scene.height
    t0 = time.monotonic()
    fut = client.submit(task_maps, argv, frame, threads, retries=RETRIES)
    data = _wait(client, [fut], progress, "maps")[0]
    maps_seconds = time.monotonic() - t0
    maps = client.scatter(data, broadcast=True)
    cols, rows = info["tiles"] or (2 * _workers(client), 2)
    tiles = _split(width, height, cols, rows)
    firsts = [None] * len(tiles)
    rounds = [None] * len(tiles)
    frame_rounds = None
    if info["two_stage_tiles"]:
        firsts = [client.submit(task_tile_first, argv, frame, maps, t, threads, retries=RETRIES)
                  for t in tiles]
        # Only the means and errors come to the client; each tile's state stays on its worker.
        noise = [(client.submit(_item, f, 0), client.submit(_item, f, 1)) for f in firsts]
        got = _wait(client, [x for pair in noise for x in pair], progress, "tiles 1/2")
        means = np.zeros((height, width, 3), "<f4")
        errors = np.zeros((height, width, 3), "<f4")
        for i, (x, y, w, h) in enumerate(tiles):
            means[y:y + h, x:x + w] = np.frombuffer(got[2 * i], "<f4").reshape(h, w, 3)
            errors[y:y + h, x:x + w] = np.frombuffer(got[2 * i + 1], "<f4").reshape(h, w, 3)
        frame_rounds = job.adaptive_rounds(means.tobytes(), errors.tobytes(), width, height)
        if frame_rounds is not None:
            r = np.frombuffer(frame_rounds, "<u4").reshape(height, width)
            rounds = [r[y:y + h, x:x + w].tobytes() for (x, y, w, h) in tiles]
    futs = [client.submit(task_tile_finish, argv, frame, maps, t, rounds[i], firsts[i], threads,
                          retries=RETRIES)
            for i, t in enumerate(tiles)]
    done = _wait(client, futs, progress, "tiles")
    stats = tile_stats([s for _, s in done], width, height, frame_rounds)
    stats["seconds"]["photon_maps_step"] = maps_seconds
    stats["distributed"] = {"workers": _workers(client), "tiles": len(tiles),
                            "stages": 2 if info["two_stage_tiles"] else 1,
                            "photon_map_bytes": len(data)}
    job.write_tiles(frame, width, height, [(t, f) for t, (f, _) in zip(tiles, done)],
                    json.dumps(stats))
    return stats


def main(argv: list[str]) -> int:
    """The ``photonmap render ... --cluster`` command; returns the exit status."""
    try:
        rest, address = strip_cluster(argv)
        require_dask()
        _core.Job(rest)  # the command line's errors before any cluster starts
        client, cluster = connect(address)
    except DistributedError as e:
        print(f"photonmap: error: {e}", file=sys.stderr)
        return 1
    except ValueError as e:
        print(f"photonmap: error: {str(e).strip()}", file=sys.stderr)
        return 2
    try:
        threads = None
        if cluster is not None and "--threads" not in " ".join(rest):
            threads = max(1, (os.cpu_count() or 1) // max(1, len(cluster.workers)))
        t0 = time.monotonic()
        stats = render(rest, client, threads=threads)
        info = json.loads(_core.Job(rest).info())
        if not info["quiet"]:
            print(f"wrote {len(stats)} frame(s) on {_workers(client)} worker(s) in "
                  f"{time.monotonic() - t0:.2f} s", file=sys.stderr)
        return 0
    except DistributedError as e:
        print(f"photonmap: error: {e}", file=sys.stderr)
        return 1
    except (_core.PhotonmapError, ValueError) as e:
        print(f"photonmap: error: {str(e).strip().splitlines()[0]}", file=sys.stderr)
        return 1
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
