"""Failures inside the core reach the Blender user as error reports, and Blender keeps
running: a panic of the renderer (the core's `PHOTONMAP_DEBUG_PANIC=render` hook), and a
render over the Memory Limit setting."""

from __future__ import annotations

from importlib import import_module

import bpy
import pytest
import scenes


@pytest.fixture
def no_write(addon, monkeypatch):
    wrote = []
    monkeypatch.setattr(addon.passes, "write_result", lambda *a, **k: wrote.append(1))
    return wrote


def test_a_panic_in_the_core_is_reported_and_blender_keeps_running(
        photonmap_scene, reports, no_write, monkeypatch):
    sc = photonmap_scene(scenes.cornell_area)
    sc.photonmap.spp = 1
    monkeypatch.setenv("PHOTONMAP_DEBUG_PANIC", "render")
    bpy.ops.render.render()
    errors = reports.of("ERROR")
    assert len(errors) == 1 and "panicked" in errors[0] and "PHOTONMAP_DEBUG_PANIC" in errors[0], \
        reports.items
    assert not no_write
    # The same session renders again once the hook is off.
    monkeypatch.delenv("PHOTONMAP_DEBUG_PANIC")
    bpy.ops.render.render()
    assert len(reports.of("ERROR")) == 1, reports.items
    assert no_write == [1]


def test_a_panic_reaches_blender_as_an_operator_error(photonmap_scene, monkeypatch):
    """Without the test's report recorder: Blender's own report system gets the error (bpy
    turns an operator's error report into RuntimeError), not a Python traceback."""
    sc = photonmap_scene(scenes.cornell_area)
    sc.photonmap.spp = 1
    monkeypatch.setenv("PHOTONMAP_DEBUG_PANIC", "render")
    try:
        bpy.ops.render.render()
    except RuntimeError as e:
        assert "PhotonMap: internal error: the renderer panicked" in str(e), e
    else:
        pytest.fail("no error report reached Blender")


def test_memory_limit_setting_stops_the_render_with_a_report(photonmap_scene, reports, no_write):
    sc = photonmap_scene(scenes.cornell_area)
    sc.photonmap.photons = 10_000_000
    sc.photonmap.memory_limit = "1M"
    bpy.ops.render.render()
    errors = reports.of("ERROR")
    assert len(errors) == 1 and "`memory_limit`" in errors[0] and "estimated" in errors[0], \
        reports.items
    assert not no_write


def test_viewport_reports_a_failed_refinement(photonmap_scene, addon, monkeypatch):
    viewport = import_module(addon.__name__ + ".viewport")
    camera_mod = import_module(addon.__name__ + ".export.camera")
    sc = photonmap_scene(scenes.cornell_area, quality="draft")

    class Engine:
        def __init__(self):
            self.reports = []

        def tag_redraw(self):
            pass

        def _report(self, kind, message):
            self.reports.append((kind, message))

    engine = Engine()
    vp = viewport.ViewportRender(engine)
    vp.update_scene(None, bpy.context.evaluated_depsgraph_get())
    win = camera_mod.Window(16, 16, 0, 0, 16, 16)
    cam = camera_mod.camera_ir(sc.camera.matrix_world, 35.0, 72.0, 72.0, "AUTO", (0, 0), 0.01,
                               100.0, win)
    monkeypatch.setenv("PHOTONMAP_DEBUG_PANIC", "render")
    vp.generation += 1
    vp._refine(vp.generation, dict(vp.ir, camera=cam), 16, 16, dict(vp.settings))
    assert vp.image is None
    vp.report_error()
    assert len(engine.reports) == 1, engine.reports
    kind, message = engine.reports[0]
    assert kind == "ERROR" and "panicked" in message
    vp.report_error()  # reported once
    assert len(engine.reports) == 1
