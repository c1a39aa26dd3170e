"""The add-on's translation of Cycles node trees into shading graphs (export/node_graph.py).

Whether the graphs render as Cycles does is the corpus' question (corpus/node_scenes.py,
test_corpus.py); these tests check what the export writes."""

from __future__ import annotations

import bpy
import numpy as np
import photonmap
from corpus import node_scenes
from corpus.scenes import principled


def _export(addon):
    return addon.export.export_scene(bpy.context.evaluated_depsgraph_get())


def _graph(ex, name):
    (m,) = [m for m in ex.ir["materials"] if m["name"] == name]
    return m


def test_node_materials_become_graphs_without_warnings(addon):
    node_scenes.nodes_plastic()
    ex = _export(addon)
    g = _graph(ex, "Plastic")
    assert g["type"] == "graph"
    kinds = sorted(n["type"] for n in g["nodes"])
    assert kinds == ["diffuse", "glossy", "layer_weight", "mix_shader"]
    assert not ex.warnings, ex.warnings
    assert ex.counts["unsupported_nodes"] == 0
    # Plain materials stay plain: the room's default Principled walls.
    assert _graph(ex, "Wall")["type"] == "principled"
    photonmap.Scene.from_dict(ex.ir)


def test_groups_and_reroutes_are_flattened(addon):
    node_scenes.nodes_group()
    ex = _export(addon)
    g = _graph(ex, "Stone")
    kinds = sorted(n["type"] for n in g["nodes"])
    assert kinds == ["color_ramp", "noise_texture", "principled"] or "color_ramp" not in \
        photonmap._core.GRAPH_NODES and kinds == ["principled"], kinds
    noise = [n for n in g["nodes"] if n["type"] == "noise_texture"]
    if noise:
        # The group input's value reaches the node inside.
        assert noise[0]["inputs"]["scale"] == 6.0
    photonmap.Scene.from_dict(ex.ir)


def test_an_unsupported_node_is_warned_and_the_rest_of_the_graph_kept(addon):
    node_scenes.nodes_checker()
    m = bpy.data.materials["CheckerFloor"]
    nt = m.node_tree
    ao = nt.nodes.new("ShaderNodeAmbientOcclusion")
    ao.name = "Trick"
    nt.links.new(ao.outputs["AO"], nt.nodes["Principled BSDF"].inputs["Roughness"])
    ex = _export(addon)
    g = _graph(ex, "CheckerFloor")
    assert any("'CheckerFloor'" in w and "'Trick'" in w and "ShaderNodeAmbientOcclusion" in w
               for w in ex.warnings), ex.warnings
    assert ex.counts["unsupported_nodes"] == 1
    (p,) = [n for n in g["nodes"] if n["type"] == "principled"]
    # The checker still feeds the Base Color; Roughness falls back to the socket's value.
    assert p["inputs"]["base_color"]["node"] == [i for i, n in enumerate(g["nodes"])
                                                 if n["type"] == "checker_texture"][0]
    assert p["inputs"]["roughness"] == 0.5
    photonmap.Scene.from_dict(ex.ir)


def test_muted_nodes_pass_their_input_through(addon):
    node_scenes.nodes_checker()
    m = bpy.data.materials["CheckerFloor"]
    nt = m.node_tree
    inv = nt.nodes.new("ShaderNodeInvert")
    ck = nt.nodes["Checker Texture"]
    b = nt.nodes["Principled BSDF"]
    nt.links.new(ck.outputs["Color"], inv.inputs["Color"])
    nt.links.new(inv.outputs["Color"], b.inputs["Base Color"])
    inv.mute = True
    ex = _export(addon)
    g = _graph(ex, "CheckerFloor")
    assert "invert" not in [n["type"] for n in g["nodes"]]
    inv.mute = False
    g = _graph(_export(addon), "CheckerFloor")
    assert "invert" in [n["type"] for n in g["nodes"]]


def test_alpha_and_normal_inputs_go_through_graphs(addon):
    node_scenes.nodes_leaf_alpha()
    ex = _export(addon)
    g = _graph(ex, "Leaf")
    (p,) = [n for n in g["nodes"] if n["type"] == "principled"]
    assert p["inputs"]["alpha"]["output"] == "fac"
    # Implicit sockets are left to the core: the checker reads generated coordinates.
    (ck,) = [n for n in g["nodes"] if n["type"] == "checker_texture"]
    assert "vector" not in ck["inputs"]
    assert "normal" not in p["inputs"]
    node_scenes.nodes_tiles_normal()
    ex = _export(addon)
    g = _graph(ex, "Tiles")
    (nm,) = [n for n in g["nodes"] if n["type"] == "normal_map"]
    assert nm["params"]["space"] == "TANGENT"
    (img,) = [n for n in g["nodes"] if n["type"] == "image_texture"]
    assert ex.ir["textures"][img["params"]["texture"]]["encoding"] == "linear"  # Non-Color
    assert not ex.warnings, ex.warnings


def test_plain_principled_with_a_constant_alpha_below_one_is_a_graph(addon):
    node_scenes.nodes_checker()
    m = principled("HalfThere", Alpha=0.4)
    bpy.data.objects["Sphere"].data.materials[0] = m
    ex = _export(addon)
    g = _graph(ex, "HalfThere")
    assert g["type"] == "graph"
    (p,) = [n for n in g["nodes"] if n["type"] == "principled"]
    assert abs(p["inputs"]["alpha"] - 0.4) < 1e-6


def test_colour_attributes_reach_the_meshes_that_have_them(addon):
    node_scenes.nodes_vertex_colors()
    ex = _export(addon)
    assert not ex.warnings, ex.warnings
    g = _graph(ex, "PaintedCube")
    (a,) = [n for n in g["nodes"] if n["type"] == "attribute"]
    assert a["params"]["name"] == "Paint"
    (v,) = [n for n in _graph(ex, "Painted")["nodes"] if n["type"] == "attribute"]
    assert v["params"]["name"] == ""  # the Color Attribute node: the default colour attribute
    meshes = {m["name"].split(" ")[0]: m for m in ex.ir["meshes"]}
    # Only the meshes with a read attribute carry it; the walls carry none.
    assert set(meshes["Cube"]["attributes"]) == {"Paint"}
    assert set(meshes["Sphere"]["attributes"]) == {""}
    assert "attributes" not in meshes["Floor"]
    paint = meshes["Cube"]["attributes"]["Paint"]
    assert paint.shape == (len(meshes["Cube"]["positions"]), 4)
    # Byte colours arrive linear (stored as sRGB bytes): the face painted 0.9 reads 0.896.
    assert np.isclose(paint[:, 0].max(), 0.8963, atol=2e-3), paint[:, 0].max()
    photonmap.Scene.from_dict(ex.ir)


def test_film_transparent_is_exported_and_transparent_glass_warned(addon):
    sc = node_scenes.nodes_plastic()
    ex = _export(addon)
    assert not ex.warnings and "transparent" not in ex.ir["film"]
    sc.render.film_transparent = True
    ex = _export(addon)
    assert ex.ir["film"]["transparent"] is True and not ex.warnings, ex.warnings
    sc.cycles.film_transparent_glass = True
    ex = _export(addon)
    assert any(f"scene '{sc.name}'" in w and "Transparent Glass" in w for w in ex.warnings), \
        ex.warnings
