"""Blender volumes -> the IR's homogeneous media, and renders through them."""

from __future__ import annotations

import bpy
import numpy as np
import photonmap
import pytest
import scenes
from conftest import exr_parts, set_multilayer_exr


def _export(addon):
    return addon.export.export_scene(bpy.context.evaluated_depsgraph_get())


def _principled_cube():
    sc = scenes.empty_scene()
    fog = scenes.volume_material("fog", Density=2.0, Color=(0.8, 0.6, 0.4), Anisotropy=0.3)
    scenes.cube("fog cube", (0, 0, 1), 2.0, fog)
    scenes.light("POINT", (0, 0, 5), energy=100.0)
    scenes.camera((0, -8, 1), (90, 0, 0))
    return sc


def test_principled_volume_cube_is_a_medium_in_a_null_boundary(photonmap_scene, addon):
    photonmap_scene(_principled_cube)
    res = _export(addon)
    ir = res.ir
    assert len(ir["media"]) == 1
    m = ir["media"][0]
    # Cycles (svm_node_principled_volume): sigma_s = d C, sigma_a = d max(1-C, 0)
    # max(1 - sqrt(A), 0), A = Absorption Color (black by default).
    d, c = 2.0, np.array([0.8, 0.6, 0.4])
    assert m["sigma_s"] == pytest.approx(d * c, rel=1e-6)
    assert m["sigma_a"] == pytest.approx(d * (1 - c), rel=1e-6)
    assert m["g"] == pytest.approx(0.3)
    assert m["name"] == "fog"
    (mesh,) = ir["meshes"]
    assert mesh["interior_medium"] == 0
    assert ir["materials"][mesh["material"]] == {"type": "null", "name": "fog"}
    assert "material_indices" not in mesh
    assert "world_medium" not in ir
    assert not [w for w in res.warnings if "volume" in w.lower()], res.warnings
    assert res.counts["media"] == 1
    photonmap.Scene.from_dict(ir)


def test_principled_volume_absorption_color_and_unsupported_inputs(photonmap_scene, addon):
    def build():
        sc = _principled_cube()
        fog = bpy.data.materials["fog"]
        pv = fog.node_tree.nodes["Principled Volume"]
        pv.inputs["Absorption Color"].default_value = (0.25, 0.64, 1.0, 1.0)
        pv.inputs["Emission Strength"].default_value = 1.0
        noise = fog.node_tree.nodes.new("ShaderNodeTexNoise")
        fog.node_tree.links.new(noise.outputs["Fac"], pv.inputs["Density"])
        return sc

    photonmap_scene(build)
    res = _export(addon)
    m = res.ir["media"][0]
    c, a = np.array([0.8, 0.6, 0.4]), np.array([0.25, 0.64, 1.0])
    assert m["sigma_a"] == pytest.approx(2.0 * (1 - c) * (1 - np.sqrt(a)), rel=1e-6, abs=1e-7)
    assert m["sigma_s"] == pytest.approx(2.0 * c, rel=1e-6)  # the Density socket's constant
    w = res.warnings
    assert any("'fog cube'" in x and "Density" in x and "texture" in x for x in w), w
    assert any("'fog cube'" in x and "emission" in x for x in w), w


def _glass_sphere_with_absorption():
    sc = scenes.empty_scene()
    sc.unit_settings.scale_length = 0.01  # Cycles' densities ignore the unit scale
    m = scenes.volume_material("tinted glass", "ShaderNodeVolumeAbsorption",
                               surface="ShaderNodeBsdfGlass", Density=1.5,
                               Color=(0.2, 0.5, 0.9))
    m.node_tree.nodes["Glass BSDF"].inputs["IOR"].default_value = 1.45
    bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0, location=(0, 0, 1))
    bpy.context.object.name = "sphere"
    bpy.context.object.data.materials.append(m)
    scenes.camera((0, -8, 1), (90, 0, 0))
    return sc


def test_glass_with_volume_absorption_keeps_its_surface(photonmap_scene, addon):
    photonmap_scene(_glass_sphere_with_absorption)
    res = _export(addon)
    ir = res.ir
    (mesh,) = ir["meshes"]
    mat = ir["materials"][mesh["material"]]
    assert mat["type"] == "dielectric" and mat["ior"] == pytest.approx(1.45)
    (m,) = ir["media"]
    assert mesh["interior_medium"] == 0
    # Cycles (svm_node_closure_volume): sigma_a = d (1 - C), no scattering.
    assert m["sigma_a"] == pytest.approx(1.5 * (1 - np.array([0.2, 0.5, 0.9])), rel=1e-6)
    assert m["sigma_s"] == [0.0, 0.0, 0.0]
    assert not [w for w in res.warnings if "volume" in w.lower()], res.warnings
    photonmap.Scene.from_dict(ir)


def _world_scatter():
    sc = scenes.empty_scene()
    world = bpy.data.worlds.new("hazy")
    world.use_nodes = True
    nt = world.node_tree
    out = nt.nodes["World Output"]
    vs = nt.nodes.new("ShaderNodeVolumeScatter")
    vs.inputs["Density"].default_value = 0.05
    vs.inputs["Color"].default_value = (0.9, 0.8, 0.7, 1.0)
    vs.inputs["Anisotropy"].default_value = -0.2
    nt.links.new(vs.outputs[0], out.inputs["Volume"])
    nt.nodes["Background"].inputs["Strength"].default_value = 0.0
    sc.world = world
    scenes.quad("floor", [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)],
                scenes.diffuse("white", (0.8, 0.8, 0.8)))
    scenes.light("SUN", (0, 0, 5), energy=2.0)
    scenes.camera((0, -4, 2), (60, 0, 0))
    return sc


def test_world_volume_scatter_is_the_world_medium(photonmap_scene, addon):
    photonmap_scene(_world_scatter)
    res = _export(addon)
    ir = res.ir
    (m,) = ir["media"]
    assert ir["world_medium"] == 0
    assert m["sigma_s"] == pytest.approx(0.05 * np.array([0.9, 0.8, 0.7]), rel=1e-6)
    assert m["sigma_a"] == [0.0, 0.0, 0.0]
    assert m["g"] == pytest.approx(-0.2)
    assert "environment" not in ir
    assert all("interior_medium" not in mesh for mesh in ir["meshes"])
    assert not [w for w in res.warnings if "volume" in w.lower()], res.warnings
    photonmap.Scene.from_dict(ir)


def test_added_volume_shaders_sum_and_volume_objects_warn(photonmap_scene, addon):
    def build():
        sc = scenes.empty_scene()
        m = bpy.data.materials.new("smoke")
        m.use_nodes = True
        nt = m.node_tree
        nt.nodes.clear()
        out = nt.nodes.new("ShaderNodeOutputMaterial")
        scatter = nt.nodes.new("ShaderNodeVolumeScatter")
        scatter.inputs["Density"].default_value = 0.5
        scatter.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        scatter.inputs["Anisotropy"].default_value = 0.4
        absorb = nt.nodes.new("ShaderNodeVolumeAbsorption")
        absorb.inputs["Density"].default_value = 0.2
        absorb.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1.0)
        add = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(scatter.outputs[0], add.inputs[0])
        nt.links.new(absorb.outputs[0], add.inputs[1])
        nt.links.new(add.outputs[0], out.inputs["Volume"])
        scenes.cube("box", (0, 0, 0), 1.0, m)
        vol = bpy.data.volumes.new("vdb")
        ob = bpy.data.objects.new("vdb smoke", vol)
        sc.collection.objects.link(ob)
        scenes.camera((0, -5, 0), (90, 0, 0))
        return sc

    photonmap_scene(build)
    res = _export(addon)
    (m,) = res.ir["media"]
    assert m["sigma_s"] == pytest.approx([0.5] * 3)
    assert m["sigma_a"] == pytest.approx([0.1] * 3)
    assert m["g"] == pytest.approx(0.4)
    assert any("'vdb smoke'" in w and "Volume objects" in w for w in res.warnings), res.warnings


def _pass(parts, layer, name):
    return np.stack([parts[f"{layer}.{name}"][f"{layer}.{name}.{c}"] for c in "RGB"], -1)


def test_fog_scene_renders_a_volume_pass(photonmap_scene, addon, reports, tmp_path, monkeypatch):
    sc = photonmap_scene(scenes.fog_spot)
    sc.render.resolution_x = sc.render.resolution_y = 48
    path = tmp_path / "fog.exr"
    set_multilayer_exr(sc, path)
    seen = {}
    write = addon.passes.write_result

    def spy(engine, out, window, layer_name=""):
        seen["out"] = out
        write(engine, out, window, layer_name)

    monkeypatch.setattr(addon.passes, "write_result", spy)
    bpy.ops.render.render(write_still=True)
    assert not reports.of("ERROR"), reports.items
    assert not [w for w in reports.of("WARNING") if "volume" in w.lower()], reports.items
    parts = exr_parts(path)
    layer = bpy.context.view_layer.name
    comb = _pass(parts, layer, "Combined")
    vol = _pass(parts, layer, "Volume")
    assert np.all(np.isfinite(comb)) and np.all(np.isfinite(vol))
    assert vol.mean() > 1e-3, vol.mean()
    # Each pass in the file is the core's term of its name (the sum rule is the core's,
    # checked against terms rendered alone in tests/render_invariants.rs).
    out = seen["out"]
    np.testing.assert_allclose(comb, out["combined"], rtol=1e-5, atol=1e-6)
    for term, name in zip(photonmap.TERMS, photonmap.PASS_NAMES):
        np.testing.assert_allclose(_pass(parts, layer, name), out[term], rtol=1e-5, atol=1e-6,
                                   err_msg=name)



def test_mixed_volume_shaders_blend_and_inside_out_boundaries_warn(photonmap_scene, addon):
    def build():
        sc = scenes.empty_scene()
        m = bpy.data.materials.new("mixed")
        m.use_nodes = True
        nt = m.node_tree
        nt.nodes.clear()
        out = nt.nodes.new("ShaderNodeOutputMaterial")
        scatter = nt.nodes.new("ShaderNodeVolumeScatter")
        scatter.inputs["Density"].default_value = 2.0
        scatter.inputs["Color"].default_value = (1.0, 0.5, 0.25, 1.0)
        absorb = nt.nodes.new("ShaderNodeVolumeAbsorption")
        absorb.inputs["Density"].default_value = 4.0
        absorb.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
        mix = nt.nodes.new("ShaderNodeMixShader")
        mix.inputs[0].default_value = 0.25
        nt.links.new(scatter.outputs[0], mix.inputs[1])
        nt.links.new(absorb.outputs[0], mix.inputs[2])
        nt.links.new(mix.outputs[0], out.inputs["Volume"])
        ob = scenes.cube("inside out", (0, 0, 0), 1.0, m)
        for p in ob.data.polygons:
            p.flip()
        scenes.camera((0, -5, 0), (90, 0, 0))
        return sc

    photonmap_scene(build)
    res = _export(addon)
    (m,) = res.ir["media"]
    assert m["sigma_s"] == pytest.approx([0.75 * 2.0, 0.75 * 1.0, 0.75 * 0.5])
    assert m["sigma_a"] == pytest.approx([0.25 * 4.0] * 3)
    assert any("'inside out'" in w and "inwards" in w for w in res.warnings), res.warnings
