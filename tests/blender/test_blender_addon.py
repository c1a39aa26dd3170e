"""The PhotonMap Blender extension, headless in the `bpy` module."""

from __future__ import annotations

import json
import math

import bpy
import numpy as np
import photonmap
import pytest
import scenes
from conftest import enable, exr_parts, set_multilayer_exr
from corpus.scenes import shader_material



def test_installs_and_registers(addon):
    assert addon.__name__ == "bl_ext.user_default.photonmap"
    assert "PHOTONMAP" in {getattr(e, "bl_idname", "") for e in bpy.types.RenderEngine.__subclasses__()}
    sc = bpy.context.scene
    sc.render.engine = "PHOTONMAP"
    assert sc.photonmap.quality == "medium"
    # The add-on imports the renderer only, never the USD importer.
    import sys

    assert "usd_delegate" not in sys.modules


def test_quality_fills_the_settings_from_the_core_presets(addon):
    s = bpy.context.scene.photonmap
    for q in photonmap.QUALITIES:
        s.quality = q
        p = photonmap.preset(q)
        assert s.spp == p["spp"]
        assert s.photons == p["photons"]
        assert s.caustic_photons == p["caustic_photons"]
        assert s.final_gather_rays == p["final_gather_rays"]
        assert s.gather == p["gather"]
        assert s.irradiance_cache == p["irradiance_cache"]
        assert s.cache_tolerance == pytest.approx(p["cache_tolerance"])
        assert s.max_specular_depth == p["max_specular_depth"]


def test_settings_no_preset_fills_default_to_the_cores(addon):
    """Mode, progressive alpha and initial photons, filter, seed and threads start at the
    core's defaults (``photonmap.defaults``), not at numbers of the add-on's own."""
    s = bpy.context.scene.photonmap
    d = photonmap.defaults()
    for key in ("quality", "mode", "filter", "seed", "threads", "initial_photons"):
        assert s.bl_rna.properties[key].default == d[key], key
    assert s.bl_rna.properties["alpha"].default == pytest.approx(d["alpha"])


def tiny_scene():
    """A 4x4 image of one triangle under a point light."""
    return photonmap.Scene.from_dict({
        "camera": {"fov": 0.7, "transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 3], [0, 0, 0, 1]]},
        "film": {"width": 4, "height": 4},
        "materials": [{"type": "diffuse", "color": [0.5, 0.5, 0.5]}],
        "meshes": [{"positions": [[-1, -1, 0], [1, -1, 0], [1, 1, 0]], "indices": [[0, 1, 2]]}],
        "lights": [{"type": "point", "position": [0, 0, 1], "power": 10}],
    })


def test_every_schema_field_is_a_property_with_the_cores_name_and_default(addon, capfd):
    """Each setting of the core's schema is a property of ``scene.photonmap`` of the same
    name, label and default, goes into the keywords the engine renders with (an unset
    optional one as None), and is a flag of the command."""
    schema = photonmap.settings_schema()
    assert len(schema) > 20
    s = bpy.context.scene.photonmap
    s.quality = photonmap.defaults()["quality"]
    sent = addon.properties.render_settings(s)
    assert set(sent) == {f["name"] for f in schema}
    capfd.readouterr()
    assert photonmap._core.run_cli(["render", "--help"]) == 0
    helptext = capfd.readouterr().out
    for f in schema:
        k = f["name"]
        prop = s.bl_rna.properties[k]
        assert prop.name == f["label"], k
        assert prop.description == f["doc"], k
        d = f["default"]
        if f["type"] in ("int", "float"):
            assert prop.default == pytest.approx(d if d is not None else 0), k
            assert sent[k] == (pytest.approx(d) if d is not None else None), k
        elif f["type"] in ("size", "path"):
            assert prop.default == "" and sent[k] is None, k
        else:
            assert prop.default == d and sent[k] == d, k
        assert f["flag"] in helptext, f"no command-line flag for {k}"
    # What the engine sends is what the core reads: the render accepts every keyword.
    scene = tiny_scene()
    out = photonmap.render(scene, **{**sent, "spp": 1, "photons": 200, "caustic_photons": 50,
                                     "final_gather_rays": 4})
    assert out["stats"]["options"]["gather"] == sent["gather"]


def test_presets_are_what_the_core_renders_with(addon):
    scene = tiny_scene()
    out = photonmap.render(scene, quality="draft")
    p = photonmap.preset("draft")
    assert out["stats"]["spp"] == p["spp"]
    # Photons are traced in batches until the requested number is stored.
    assert p["photons"] <= out["stats"]["photons_stored"]["global"] < 1.1 * p["photons"]
    # The stats record the settings the render used.
    got = out["stats"]["settings"]
    assert got["spp"] == p["spp"]
    assert got["quality"] == "draft"
    for key in ("photons", "caustic_photons", "gather", "final_gather_rays"):
        assert got[key] == p[key], key
    assert got["cache_tolerance"] == pytest.approx(p["cache_tolerance"])


def test_passes_in_the_result_and_in_multilayer_exr(photonmap_scene, addon, tmp_path, monkeypatch):
    sc = photonmap_scene(scenes.cornell_area)
    seen = {}
    write = addon.passes.write_result

    def spy(engine, out, window, layer_name=""):
        seen["out"] = out
        write(engine, out, window, layer_name)

    monkeypatch.setattr(addon.passes, "write_result", spy)
    path = tmp_path / "passes.exr"
    set_multilayer_exr(sc, path)
    bpy.ops.render.render(write_still=True)
    assert "out" in seen, "the engine wrote no result"

    parts = exr_parts(path)
    layer = bpy.context.view_layer.name
    names = {n.split(".", 1)[1] for n in parts if n.startswith(layer + ".")}
    assert names == {"Combined", *photonmap.PASS_NAMES, photonmap.ERROR_PASS}, names
    comb = np.stack([parts[f"{layer}.Combined"][f"{layer}.Combined.{c}"] for c in "RGB"], -1)
    assert comb.mean() > 0.05
    # Blender's rows go bottom to top: the EXR (top row first) equals the core's image, and
    # each pass the core's term of its name (the sum rule itself is the core's, checked
    # against terms rendered alone in tests/render_invariants.rs).
    out = seen["out"]
    np.testing.assert_allclose(comb, out["combined"], rtol=1e-5, atol=1e-6)
    for term, name in zip(photonmap.TERMS, photonmap.PASS_NAMES):
        got = np.stack([parts[f"{layer}.{name}"][f"{layer}.{name}.{c}"] for c in "RGB"], -1)
        np.testing.assert_allclose(got, out[term], rtol=1e-5, atol=1e-6, err_msg=name)
    e = photonmap.ERROR_PASS
    got = np.stack([parts[f"{layer}.{e}"][f"{layer}.{e}.{c}"] for c in "RGB"], -1)
    np.testing.assert_allclose(got, out[photonmap.ERROR_AOV], rtol=1e-5, atol=1e-6)
    assert {t for t in photonmap.TERMS if out[t].any()} >= {"direct", "indirect"}
    # The compositor's Render Layers node offers every pass.
    tree = bpy.data.node_groups.new("Compositing", "CompositorNodeTree")
    node = tree.nodes.new("CompositorNodeRLayers")
    node.scene = sc
    sockets = {o.name for o in node.outputs if o.enabled}
    assert set(photonmap.PASS_NAMES) <= sockets, sockets


def _every_light_and_instances():
    sc = scenes.empty_scene()
    sc.unit_settings.scale_length = 0.01
    me = bpy.data.meshes.new("box")
    me.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [], [(0, 1, 2, 3)])
    glass = bpy.data.materials.new("glass")
    glass.use_nodes = True
    bsdf = glass.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Transmission Weight"].default_value = 1.0
    bsdf.inputs["IOR"].default_value = 1.45
    bsdf.inputs["Roughness"].default_value = 0.0
    bsdf.inputs["Specular IOR Level"].default_value = 0.25
    me.materials.append(glass)
    for i in range(5):
        ob = bpy.data.objects.new(f"box.{i}", me)
        ob.location = (2.0 * i, 0, 0)
        sc.collection.objects.link(ob)
    scenes.light("POINT", (0, 0, 3), energy=100.0, shadow_soft_size=0.2)
    scenes.light("SPOT", (1, 0, 3), energy=50.0, spot_size=math.radians(60), spot_blend=0.3,
                 shadow_soft_size=0.0)
    for shape in ("SQUARE", "RECTANGLE", "DISK", "ELLIPSE"):
        ob = scenes.light("AREA", (0, 2, 3), shape=shape, size=0.5, size_y=0.25, energy=10.0)
        ob.name = f"area_{shape.lower()}"
    scenes.light("SUN", (0, 0, 9), (30, 0, 0), energy=3.0, angle=math.radians(1.0))
    cam = scenes.camera((4, -8, 3), (75, 0, 0))
    cam.data.dof.use_dof = True
    cam.data.dof.aperture_fstop = 2.0
    cam.data.dof.focus_distance = 7.0
    return sc


def test_export_ir(photonmap_scene, addon):
    photonmap_scene(_every_light_and_instances)
    res = addon.export.export_scene(bpy.context.evaluated_depsgraph_get())
    ir = res.ir
    assert len(ir["meshes"]) == 1
    assert len(ir["instances"]) == 5 and all(i["mesh"] == 0 for i in ir["instances"])
    assert sorted(round(i["transform"][0][3], 4) for i in ir["instances"]) == [0, 2, 4, 6, 8]
    mesh = ir["meshes"][0]
    assert mesh["indices"].shape == (2, 3)
    mat = ir["materials"][mesh["material"]]
    assert mat["type"] == "principled" and mat["transmission"] == 1.0
    assert mat["ior"] == pytest.approx(1.45) and mat["specular"] == pytest.approx(0.5)
    kinds = sorted(light["type"] for light in ir["lights"])
    assert kinds == ["disk", "disk", "distant", "point", "rect", "rect", "spot"]
    by_name = {light["name"]: light for light in ir["lights"]}
    assert by_name["point"]["power"] == 100.0 and by_name["point"]["radius"] == pytest.approx(0.2)
    assert by_name["spot"]["cone_angle"] == pytest.approx(math.radians(60))
    assert by_name["spot"]["blend"] == pytest.approx(0.3)
    assert by_name["spot"]["direction"] == pytest.approx([0, 0, -1], abs=1e-6)
    assert (by_name["area_rectangle"]["width"], by_name["area_rectangle"]["height"]) == \
        pytest.approx((0.5, 0.25))
    assert by_name["area_square"]["height"] == pytest.approx(0.5)
    assert by_name["area_disk"]["radius"] == pytest.approx(0.25)
    # An ellipse keeps its two radii (size 0.5 along X, 0.25 along Y).
    assert (by_name["area_ellipse"]["radius"], by_name["area_ellipse"]["radius_y"]) == \
        pytest.approx((0.25, 0.125))
    assert by_name["point"]["soft_falloff"] is True
    assert all(light.get("spread", math.pi) == pytest.approx(math.pi)
               for light in ir["lights"] if light["type"] in ("rect", "disk"))
    sun = by_name["sun"]
    assert sun["irradiance"] == 3.0 and sun["angle"] == pytest.approx(math.radians(1.0))
    assert sun["direction"] == pytest.approx([0, math.sin(math.radians(30)),
                                              -math.cos(math.radians(30))], abs=1e-5)
    cam = ir["camera"]
    assert cam["units_per_mm"] == pytest.approx(0.1)  # 1 mm = 0.1 units of 1 cm
    assert cam["fstop"] == 2.0 and cam["focus_distance"] == pytest.approx(7.0)
    assert cam["fov"] == pytest.approx(2 * math.atan(18.0 / 35.0))  # 35 mm lens, 36 mm sensor
    assert ir["film"] == {"width": 64, "height": 64}
    assert "environment" not in ir
    # The core accepts it.
    scene = photonmap.Scene.from_dict(ir)
    assert scene.counts()["lights"] == 7


def test_render_border_renders_only_the_border(photonmap_scene, addon, tmp_path, monkeypatch):
    sc = photonmap_scene(scenes.cornell_area)
    sc.render.use_border = True
    sc.render.use_crop_to_border = False
    sc.render.border_min_x, sc.render.border_max_x = 0.25, 0.75
    sc.render.border_min_y, sc.render.border_max_y = 0.5, 1.0
    films = []
    render = addon.engine.photonmap.render

    def spy(scene, **kw):
        films.append((scene.width, scene.height))
        return render(scene, **kw)

    monkeypatch.setattr(addon.engine.photonmap, "render", spy)
    path = tmp_path / "border.exr"
    set_multilayer_exr(sc, path)
    bpy.ops.render.render(write_still=True)
    assert films == [(32, 32)]
    parts = exr_parts(path)
    layer = bpy.context.view_layer.name
    r = parts[f"{layer}.Combined"][f"{layer}.Combined.R"]
    assert r.shape == (64, 64)
    # Border in the upper middle: rows 0..31 from the top, columns 16..47.
    assert r[:32, 16:48].mean() > 0.05
    assert np.all(r[32:, :] == 0) and np.all(r[:, :16] == 0) and np.all(r[:, 48:] == 0)
    # The border rendered alone matches the same window of the full render.
    sc.render.use_border = False
    full_path = tmp_path / "full.exr"
    set_multilayer_exr(sc, full_path)
    bpy.ops.render.render(write_still=True)
    full = exr_parts(full_path)[f"{layer}.Combined"][f"{layer}.Combined.R"]
    assert r[:32, 16:48].mean() == pytest.approx(full[:32, 16:48].mean(), rel=0.1)


def test_escape_cancels_the_render(photonmap_scene, addon, reports, monkeypatch, tmp_path):
    """Esc (``test_break`` true) as soon as the core has reported a phase: the engine sets the
    job's cancel token, the core stops with RenderCancelled in that phase (no later phase
    starts, the phase never reports itself finished), and no result is written. At the final
    preset and 256x256 an uncancelled render runs to the end and writes its result."""
    sc = photonmap_scene(scenes.cornell_area, quality="final")
    sc.render.resolution_x = sc.render.resolution_y = 256
    jobs = []

    class Job(addon.engine.RenderJob):
        def __init__(self, *a, **k):
            super().__init__(*a, **k)
            self.reports = []
            jobs.append(self)

        def _progress(self, fraction, phase):
            super()._progress(fraction, phase)
            self.reports.append((float(fraction), phase))

    state = {"polls": 0, "broke_in": None}

    def test_break(self):
        state["polls"] += 1
        job = jobs[-1] if jobs else None
        if job is not None and job.reports and state["broke_in"] is None:
            state["broke_in"] = job.reports[-1][1]
            state["reports_at_break"] = len(job.reports)
        return state["broke_in"] is not None

    monkeypatch.setattr(addon.engine, "RenderJob", Job)
    monkeypatch.setattr(addon.engine.PhotonMapRenderEngine, "_test_break", test_break)
    wrote = []
    monkeypatch.setattr(addon.passes, "write_result", lambda *a, **k: wrote.append(1))
    bpy.ops.render.render()
    assert state["polls"] > 0, "the engine never polled test_break"
    assert state["broke_in"] is not None, "the core reported no phase"
    (job,) = jobs
    print(f"\nEsc in `{state['broke_in']}` after {state['polls']} polls; the job reported "
          f"{job.reports}")
    assert job.token.cancelled, "Esc did not reach the job's cancel token"
    assert isinstance(job.error, addon.engine.photonmap.RenderCancelled), job.error
    assert job.out is None
    after = job.reports[state["reports_at_break"]:]
    assert all(p == state["broke_in"] and f < 1.0 for f, p in after), (state, after)
    assert not wrote, "a cancelled render wrote a result"
    assert not reports.of("ERROR"), reports.items


def _unsupported_material_scene():
    sc = scenes.empty_scene()
    scenes.cornell_walls()
    scenes.light("AREA", (0, 0, 1.98), size=0.5, energy=60.0)
    m = bpy.data.materials.new("toon stuff")
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    mix = nt.nodes.new("ShaderNodeMixShader")
    toon = nt.nodes.new("ShaderNodeBsdfToon")
    nt.links.new(toon.outputs[0], mix.inputs[1])
    nt.links.new(mix.outputs[0], out.inputs["Surface"])
    vol = bpy.data.materials.new("fog")
    vol.use_nodes = True
    vt = vol.node_tree
    vt.nodes.clear()
    vout = vt.nodes.new("ShaderNodeOutputMaterial")
    pv = vt.nodes.new("ShaderNodeVolumePrincipled")
    vt.links.new(pv.outputs[0], vout.inputs["Volume"])
    floor = bpy.data.objects["floor"]
    floor.data.materials[0] = m
    back = bpy.data.objects["back"]
    back.data.materials[0] = vol
    return sc


def _glass_nodes_scene():
    sc = scenes.empty_scene()
    scenes.cornell_walls()
    scenes.light("AREA", (0, 0, 1.98), size=0.5, energy=60.0)
    for obj, dist in (("floor", None), ("back", "GGX")):
        m = shader_material(f"glass {dist or 'default'}", "ShaderNodeBsdfGlass", Roughness=0.3)
        if dist:
            m.node_tree.nodes["Glass BSDF"].distribution = dist
        bpy.data.objects[obj].data.materials[0] = m
    return sc


def test_glass_node_keeps_its_distribution(photonmap_scene, addon):
    """The Glass BSDF's Multiscatter GGX (Blender's default) is the core's compensated rough
    dielectric; GGX is the plain one."""
    photonmap_scene(_glass_nodes_scene)
    ir = addon.export.export_scene(bpy.context.evaluated_depsgraph_get()).ir
    glass = {m["name"]: m for m in ir["materials"] if m["type"] == "dielectric"}
    assert glass["glass default"]["multiscatter"] is True
    assert glass["glass GGX"]["multiscatter"] is False
    assert glass["glass GGX"]["roughness"] == pytest.approx(0.3)
    photonmap.Scene.from_dict(ir)


def test_unsupported_material_renders_grey_with_a_warning(photonmap_scene, reports, tmp_path):
    sc = photonmap_scene(_unsupported_material_scene)
    path = tmp_path / "unsupported.exr"
    set_multilayer_exr(sc, path)
    bpy.ops.render.render(write_still=True)
    warnings = reports.of("WARNING")
    assert any("'toon stuff'" in w and "not supported" in w for w in warnings), warnings
    # A volume on an open quad: exported as a medium, with a warning that it is not closed.
    assert any("'back'" in w and "closed" in w for w in warnings), warnings
    assert not reports.of("ERROR"), reports.items
    parts = exr_parts(path)
    layer = bpy.context.view_layer.name
    assert parts[f"{layer}.Combined"][f"{layer}.Combined.G"].mean() > 0.05


def test_world_and_textures_export(photonmap_scene, addon):
    def build():
        sc = scenes.empty_scene()
        world = bpy.data.worlds.new("sky")
        world.use_nodes = True
        bg = world.node_tree.nodes["Background"]
        img = bpy.data.images.new("env", 8, 4, float_buffer=True)
        img.pixels.foreach_set(np.full(8 * 4 * 4, 0.5, dtype=np.float32))
        env = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
        env.image = img
        world.node_tree.links.new(env.outputs["Color"], bg.inputs["Color"])
        bg.inputs["Strength"].default_value = 2.0
        sc.world = world
        tex = bpy.data.images.new("albedo", 2, 2)  # byte image, sRGB
        tex.pixels.foreach_set(np.array([1, 0, 0, 1] * 2 + [0.5, 0.5, 0.5, 1] * 2, np.float32))
        m = bpy.data.materials.new("textured")
        m.use_nodes = True
        t = m.node_tree.nodes.new("ShaderNodeTexImage")
        t.image = tex
        m.node_tree.links.new(t.outputs["Color"],
                              m.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
        bpy.ops.mesh.primitive_plane_add()
        bpy.context.object.data.materials.append(m)
        scenes.camera((0, -4, 2), (60, 0, 0))
        return sc

    photonmap_scene(build)
    ir = addon.export.export_scene(bpy.context.evaluated_depsgraph_get()).ir
    env = ir["environment"]
    assert env["strength"] == 2.0 and ir["textures"][env["texture"]]["width"] == 8
    mat = next(m for m in ir["materials"] if m["name"] == "textured")
    tex = ir["textures"][mat["base_color"]["texture"]]
    data = np.asarray(tex["data"]).reshape(tex["height"], tex["width"], tex["channels"])
    # A byte sRGB image is passed encoded (the core decodes after interpolating, as Cycles
    # does): the top row (Blender's last) is the grey byte 128, the bottom row red.
    assert tex["encoding"] == "srgb"
    assert data[0, 0] == pytest.approx([128 / 255] * 3, abs=1e-6)
    assert data[1, 0] == pytest.approx([1, 0, 0], abs=1e-6)
    assert ir["textures"][env["texture"]]["encoding"] == "linear"  # a float image
    assert ir["meshes"][0]["uvs"].shape == (4, 2)
    photonmap.Scene.from_dict(ir)


def test_viewport_refines_progressively(photonmap_scene, addon):
    """The viewport's refinement loop (drawing needs `gpu`, absent headless)."""
    from importlib import import_module

    viewport = import_module(addon.__name__ + ".viewport")
    camera_mod = import_module(addon.__name__ + ".export.camera")
    sc = photonmap_scene(scenes.cornell_area)
    sc.photonmap.quality = "draft"

    class Engine:
        redraws = 0

        def tag_redraw(self):
            Engine.redraws += 1

    vp = viewport.ViewportRender(Engine())
    depsgraph = bpy.context.evaluated_depsgraph_get()
    vp.update_scene(None, depsgraph)
    win = camera_mod.Window(48, 32, 0, 0, 48, 32)
    cam = camera_mod.camera_ir(sc.camera.matrix_world, 35.0, 72.0, 72.0, "AUTO", (0, 0), 0.01,
                               100.0, win)
    vp._size = (48, 32)
    sizes = []
    vp.generation += 1
    gen = vp.generation
    orig = viewport.RenderJob

    previews = []

    class Spy(orig):
        def __init__(self, ir, settings, preview=None):
            def spy(img, passes):
                previews.append((img.shape[:2], passes))
                preview(img, passes)
            super().__init__(ir, settings, preview=spy)

        def _run(self):
            super()._run()
            sizes.append(self.out["combined"].shape[:2])

    viewport.RenderJob = Spy
    try:
        vp._refine(gen, dict(vp.ir, camera=cam), 48, 32, dict(vp.settings))
    finally:
        viewport.RenderJob = orig
    # A quarter-resolution draft, then one progressive render whose passes refine the image.
    assert sizes == [(8, 12), (32, 48)]
    # The calling thread hands on the latest preview every 50 ms, and the last at the end.
    passes = [p for _, p in previews]
    assert passes and passes == sorted(passes) and passes[-1] <= sc.photonmap.spp, previews
    assert all(s == (32, 48) for s, _ in previews), previews
    assert Engine.redraws == 1 + len(previews) + 1  # the draft, each preview, the end
    assert vp.image.shape == (32, 48, 3) and vp.image.mean() > 0.01


def test_photon_maps_saved_and_loaded_by_the_addon(photonmap_scene, addon, tmp_path, monkeypatch):
    """The first frame saves the photon maps (Save Photon Maps), a later frame with the camera
    moved loads them (Load Photon Maps, On Mismatch: rebuild) and says so; a scene changed
    beyond its camera rebuilds them: what the Flamenco job type sets on every worker."""
    sc = photonmap_scene(scenes.cornell_area)
    seen = []
    write = addon.passes.write_result

    def spy(engine, out, window, layer_name=""):
        seen.append(out["stats"])
        write(engine, out, window, layer_name)

    monkeypatch.setattr(addon.passes, "write_result", spy)
    sc.render.resolution_x, sc.render.resolution_y = 32, 24
    sc.photonmap.spp = 2
    maps = tmp_path / "maps.pmaps"
    # Blender's "//" paths are relative to the .blend file; an absolute one is kept.
    sc.photonmap.save_photon_maps = str(maps)
    bpy.ops.render.render()
    assert maps.exists() and seen[-1]["photon_map_reuse"]["saved_to"] == str(maps)
    sc.photonmap.save_photon_maps = ""
    sc.photonmap.load_photon_maps = str(maps)
    sc.photonmap.photon_maps_mismatch = "rebuild"
    sc.camera.location.x += 0.05
    bpy.ops.render.render()
    assert seen[-1]["photon_map_reuse"]["maps"] == "loaded", seen[-1]["photon_map_reuse"]
    assert seen[-1]["photon_map_reuse"]["cache"] == "extended"
    light = next(o for o in sc.objects if o.type == "LIGHT")
    light.data.energy *= 1.5
    bpy.ops.render.render()
    st = seen[-1]["photon_map_reuse"]
    assert st["maps"] == "built" and "lights differ" in st["rebuilt_because"], st
