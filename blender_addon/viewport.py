"""Progressive viewport rendering, on a background thread: a coarse draft at a quarter of the
resolution first, then one progressive render at full resolution with the scene's settings
(the core's progressive passes, as a time budget or the progressive mode use them), whose
previews after passes 1, 2, 4, ... replace the image as it refines. ``draw`` shows the latest
image. ``gpu`` is imported only when drawing (it does not exist in background mode)."""

from __future__ import annotations

import threading

import numpy as np
import photonmap

from .engine import RenderJob
from .export import export_scene
from .export.camera import Window, camera_ir, export_camera
from .properties import SCHEMA, render_settings

# (resolution divisor, settings over the scene's) of each stage; the last is progressive.
STAGES = (
    (4, {"quality": "draft", "spp": 1, "photons": 20_000, "caustic_photons": 10_000,
         "final_gather_rays": 16, "mode": "jensen"}),
    (1, {"progressive": True}),
)
VIEWPORT_SENSOR = 72.0  # Blender's viewport: 36 mm sensor at zoom 2


class ViewportRender:
    def __init__(self, engine):
        self.engine = engine
        self.ir = None
        self.settings = None
        self.view_key = None
        self.image = None
        self.image_id = 0
        self.drawn_id = -1
        self.texture = None
        self.job = None
        self.lock = threading.Lock()
        self.generation = 0
        #: The last refinement's failure, reported (once) by the next ``draw``: Blender's
        #: reports are written from its own thread, not from the refinement thread.
        self.error = None

    # Scene and view -------------------------------------------------------------------------
    def _camera(self, context, depsgraph):
        region, rv3d, space = context.region, context.region_data, context.space_data
        scene = depsgraph.scene
        win = Window(region.width, region.height, 0, 0, region.width, region.height)
        if rv3d.view_perspective == "CAMERA" and scene.camera is not None:
            cam = export_camera(scene, scene.camera.evaluated_get(depsgraph), win, lambda m: None)
        else:
            cam = camera_ir(rv3d.view_matrix.inverted(), space.lens, VIEWPORT_SENSOR,
                            VIEWPORT_SENSOR, "AUTO", (0.0, 0.0), space.clip_start,
                            space.clip_end, win)
        key = (region.width, region.height, tuple(tuple(r) for r in cam["transform"]),
               cam["fov"], tuple(cam["shift"]))
        return cam, key

    def update_scene(self, context, depsgraph):
        exported = export_scene(depsgraph, camera={}, window=Window(1, 1, 0, 0, 1, 1))
        self.ir = exported.ir
        self.settings = render_settings(depsgraph.scene.photonmap)
        # The viewport shows the beauty alone: no compositing passes, no denoising.
        self.settings.update({f["name"]: f["default"] for f in SCHEMA if f["group"] == "passes"})
        self.view_key = None  # restart on the next draw

    def _restart(self, camera):
        self.stop()
        self.generation += 1
        gen = self.generation
        ir = dict(self.ir, camera=camera)
        w, h = self._size
        t = threading.Thread(target=self._refine, args=(gen, ir, w, h, dict(self.settings)),
                             daemon=True)
        t.start()

    def _refine(self, gen, ir, w, h, settings):
        for div, over in STAGES:
            if gen != self.generation:
                return
            stage = dict(settings, **over)
            if stage.get("time_budget"):  # the viewport refines until done or moved
                stage["time_budget"] = None
            film = {"width": max(1, w // div), "height": max(1, h // div)}
            try:
                job = RenderJob(dict(ir, film=film), stage,
                                preview=lambda img, _passes: self._show(gen, img))
            except Exception as e:  # SceneError (a ValueError), PhotonmapError
                self._failed(gen, e)
                return
            self.job = job
            job._run()
            if gen != self.generation:
                return
            if job.error is not None:
                if not (isinstance(job.error, photonmap.RenderCancelled) or job.token.cancelled):
                    self._failed(gen, job.error)
                return
            if not self._show(gen, job.out["combined"]):
                return

    def _show(self, gen, image) -> bool:
        """Shows ``image`` if it belongs to the current view; False once it no longer does."""
        if gen != self.generation:
            return False
        with self.lock:
            self.image = image
            self.image_id += 1
        try:
            self.engine.tag_redraw()
        except ReferenceError:  # the engine was freed
            return False
        return True

    def _failed(self, gen, error):
        if gen == self.generation:
            self.error = str(error) or type(error).__name__
            try:
                self.engine.tag_redraw()
            except ReferenceError:
                pass

    def report_error(self):
        """Reports the last refinement's failure through the engine (from Blender's thread)."""
        error, self.error = self.error, None
        if error is not None:
            self.engine._report("ERROR", error)

    def stop(self):
        self.generation += 1
        if self.job is not None:
            self.job.cancel()

    # Drawing --------------------------------------------------------------------------------
    def draw(self, context, depsgraph):
        import gpu
        from gpu_extras.presets import draw_texture_2d

        self.report_error()
        if self.ir is None:
            return
        cam, key = self._camera(context, depsgraph)
        if key != self.view_key:
            self.view_key = key
            self._size = (context.region.width, context.region.height)
            self._restart(cam)
        with self.lock:
            img, img_id = self.image, self.image_id
        if img is None:
            return
        if img_id != self.drawn_id or self.texture is None:
            h, w = img.shape[:2]
            rgba = np.ones((h, w, 4), dtype=np.float32)
            rgba[..., :3] = img[::-1]
            buf = gpu.types.Buffer("FLOAT", w * h * 4, rgba.ravel())
            self.texture = gpu.types.GPUTexture((w, h), format="RGBA16F", data=buf)
            self.drawn_id = img_id
        gpu.state.blend_set("ALPHA_PREMULT")
        self.engine.bind_display_space_shader(depsgraph.scene)
        draw_texture_2d(self.texture, (0, 0), context.region.width, context.region.height)
        self.engine.unbind_display_space_shader()
        gpu.state.blend_set("NONE")
