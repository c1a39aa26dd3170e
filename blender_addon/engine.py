"""The PhotonMap render engine: final renders, material previews and the viewport."""

from __future__ import annotations

import threading
import time

import bpy
import photonmap

from . import passes
from .export import export_scene
from .properties import SCHEMA, render_settings
from .status import stats_line


def _result_seconds(pixels: int) -> float:
    """Seconds that handing a result of ``pixels`` pixels to Blender takes (every pass copied
    into the render result): about 40 ns per pixel and pass, measured with bpy 5.0.1."""
    return 40e-9 * pixels * (len(photonmap.PASS_NAMES) + 2)


class RenderJob:
    """One ``photonmap.render`` on a Python thread (the core releases the GIL), so that the
    engine's thread stays free to poll Blender (``test_break``) and to report progress."""

    def __init__(self, ir: dict, settings: dict, preview=None):
        self.scene = photonmap.Scene.from_dict(ir)
        self.settings = settings
        self.preview = preview
        self.token = photonmap.CancelToken()
        self.fraction = 0.0
        self.phase = "starting"
        self.out = None
        self.error = None
        self.thread = threading.Thread(target=self._run, daemon=True)

    def _progress(self, fraction: float, phase: str) -> None:
        self.fraction, self.phase = float(fraction), phase

    def _run(self) -> None:
        try:
            self.out = photonmap.render(self.scene, progress=self._progress, cancel=self.token,
                                        preview=self.preview, **self.settings)
        except BaseException as e:  # handed to the engine's thread
            self.error = e

    def start(self) -> "RenderJob":
        self.thread.start()
        return self

    def cancel(self) -> None:
        self.token.cancel()

    def wait(self, poll, interval: float = 0.05) -> None:
        """Waits for the end, calling ``poll(self)`` every ``interval`` seconds."""
        while self.thread.is_alive():
            self.thread.join(interval)
            poll(self)


class PhotonMapRenderEngine(bpy.types.RenderEngine):
    bl_idname = "PHOTONMAP"
    bl_label = "PhotonMap"
    bl_use_preview = True
    bl_use_shading_nodes_custom = False
    bl_use_eevee_viewport = False

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.viewport = None

    def __del__(self):
        try:
            vp = self.viewport
        except (AttributeError, ReferenceError):  # freed by Blender already
            return
        if vp is not None:
            vp.stop()

    def _report(self, kind: str, message: str) -> None:
        """Every message goes through here (one place to log or to test)."""
        self.report({kind}, f"PhotonMap: {message}")

    def _test_break(self) -> bool:
        """Esc pressed (or the render otherwise stopped)."""
        return self.test_break()

    # Passes -----------------------------------------------------------------------------
    def update_render_passes(self, scene=None, renderlayer=None):
        passes.register_passes(self, scene, renderlayer)

    # Final render and material preview ---------------------------------------------------
    def render(self, depsgraph):
        # A Time Budget is the wall clock of the whole render: the export and the writing of
        # the result into Blender count as well as the core's render.
        started = time.monotonic()
        scene = depsgraph.scene
        self.update_stats("", "PhotonMap | exporting")
        try:
            exported = export_scene(depsgraph)
        except Exception as e:
            self._report("ERROR", f"export failed: {e}")
            return
        for w in exported.warnings:
            self._report("WARNING", w)
        settings = render_settings(scene.photonmap)
        if self.is_preview:
            # Material previews: the beauty alone, at draft settings.
            settings.update({f["name"]: f["default"] for f in SCHEMA if f["group"] == "passes"})
            draft = photonmap.preset("draft")
            settings.update(quality="draft", **{
                k: min(settings[k], draft[k])
                for k in ("spp", "photons", "caustic_photons", "final_gather_rays")})
        budget = settings.get("time_budget")
        if budget:
            win = exported.window
            settings["time_budget"] = max(budget - (time.monotonic() - started)
                                          - _result_seconds(win.w * win.h), 1e-3)
        try:
            job = RenderJob(exported.ir, settings)
        except Exception as e:  # SceneError (a ValueError), PhotonmapError
            self._report("ERROR", str(e))
            return

        def poll(j: RenderJob) -> None:
            if self._test_break():
                j.cancel()
            self.update_progress(min(max(j.fraction, 0.0), 1.0))
            self.update_stats("", f"PhotonMap | {j.phase} {100 * j.fraction:.0f}% | "
                                  f"{time.monotonic() - started:.1f}s")

        job.start().wait(poll)
        if isinstance(job.error, photonmap.RenderCancelled) or (
                job.error is not None and job.token.cancelled):
            return
        if job.error is not None:
            # Bad settings (ValueError naming the keyword), a failure or a panic of the core
            # (PhotonmapError: "internal error: the renderer panicked: ..."): reported, never
            # raised into Blender.
            self._report("ERROR", str(job.error) or type(job.error).__name__)
            return
        passes.write_result(self, job.out, exported.window, depsgraph.view_layer.name)
        self.update_progress(1.0)
        job.out["stats"]["unsupported_nodes"] = exported.counts.get("unsupported_nodes", 0)
        self.update_stats("", f"PhotonMap | {stats_line(job.out['stats'])}")

    # Viewport -------------------------------------------------------------------------------
    def view_update(self, context, depsgraph):
        from .viewport import ViewportRender

        if self.viewport is None:
            self.viewport = ViewportRender(self)
        self.viewport.update_scene(context, depsgraph)

    def view_draw(self, context, depsgraph):
        if self.viewport is None:
            self.view_update(context, depsgraph)
        self.viewport.draw(context, depsgraph)
