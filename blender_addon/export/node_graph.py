"""Cycles node trees -> IR shading graphs.

Walks a material's node tree from the Material Output's Surface socket and writes every node
it reaches as an IR node (``materials::graph`` in the core), with the sockets the core
lists in ``photonmap._core.GRAPH_NODES``: a socket's IR name is its Blender identifier in
snake case ("Base Color" -> ``base_color``, "Value_001" -> ``value_001``). Node groups and
reroutes are flattened, muted nodes pass their first matching input through, and nodes nothing
reads are never written.

A node the core does not have is replaced by the value of the socket it feeds (a shader by
nothing), with a warning naming the material, the node and its type; the rest of the graph
stays. Unsupported nodes are counted in ``stats["unsupported"]``.
"""

from __future__ import annotations

import json
import re

import photonmap

SPECS = json.loads(photonmap._core.GRAPH_NODES)

# Blender node types -> IR node types.
TYPES = {
    "ShaderNodeBsdfPrincipled": "principled",
    "ShaderNodeBsdfDiffuse": "diffuse",
    "ShaderNodeBsdfGlossy": "glossy",
    "ShaderNodeBsdfAnisotropic": "glossy",
    "ShaderNodeBsdfGlass": "glass",
    "ShaderNodeBsdfRefraction": "refraction",
    "ShaderNodeBsdfTransparent": "transparent",
    "ShaderNodeBsdfTranslucent": "translucent",
    "ShaderNodeEmission": "emission",
    "ShaderNodeHoldout": "holdout",
    "ShaderNodeBsdfSheen": "sheen",
    "ShaderNodeMixShader": "mix_shader",
    "ShaderNodeAddShader": "add_shader",
    "ShaderNodeTexCoord": "tex_coord",
    "ShaderNodeNewGeometry": "geometry",
    "ShaderNodeUVMap": "uv_map",
    "ShaderNodeObjectInfo": "object_info",
    "ShaderNodeLightPath": "light_path",
    "ShaderNodeAttribute": "attribute",
    "ShaderNodeVertexColor": "attribute",
    "ShaderNodeLayerWeight": "layer_weight",
    "ShaderNodeFresnel": "fresnel",
    "ShaderNodeMapping": "mapping",
    "ShaderNodeSeparateXYZ": "separate_xyz",
    "ShaderNodeCombineXYZ": "combine_xyz",
    "ShaderNodeNormalMap": "normal_map",
    "ShaderNodeBump": "bump",
    "ShaderNodeDisplacement": "displacement",
    "ShaderNodeTexImage": "image_texture",
    "ShaderNodeValue": "value",
    "ShaderNodeRGB": "rgb",
    "ShaderNodeInvert": "invert",
    "ShaderNodeMath": "math",
    "ShaderNodeVectorMath": "vector_math",
    "ShaderNodeVectorRotate": "vector_rotate",
    "ShaderNodeMix": "mix",
    "ShaderNodeMapRange": "map_range",
    "ShaderNodeClamp": "clamp",
    "ShaderNodeValToRGB": "color_ramp",
    "ShaderNodeRGBCurve": "rgb_curves",
    "ShaderNodeFloatCurve": "float_curve",
    "ShaderNodeHueSaturation": "hue_saturation",
    "ShaderNodeBrightContrast": "bright_contrast",
    "ShaderNodeGamma": "gamma",
    "ShaderNodeRGBToBW": "rgb_to_bw",
    "ShaderNodeSeparateColor": "separate_color",
    "ShaderNodeCombineColor": "combine_color",
    "ShaderNodeBlackbody": "blackbody",
    "ShaderNodeWavelength": "wavelength",
    "ShaderNodeTexNoise": "noise_texture",
    "ShaderNodeTexVoronoi": "voronoi_texture",
    "ShaderNodeTexWhiteNoise": "white_noise_texture",
    "ShaderNodeTexChecker": "checker_texture",
    "ShaderNodeTexBrick": "brick_texture",
    "ShaderNodeTexGradient": "gradient_texture",
    "ShaderNodeTexWave": "wave_texture",
    "ShaderNodeTexMagic": "magic_texture",
}

# Enum properties written as params (the core reads Blender's identifiers).
ENUMS = ("operation", "blend_type", "data_type", "interpolation_type", "distribution",
         "noise_type", "noise_dimensions", "voronoi_dimensions", "feature", "distance",
         "gradient_type", "wave_type", "bands_direction", "rings_direction", "wave_profile",
         "vector_type", "space", "mode", "clamp_type", "factor_mode", "rotation_type")
BOOLS = ("use_clamp", "clamp_factor", "clamp_result", "normalize", "invert", "clamp")


def snake(s: str) -> str:
    return re.sub(r"[^0-9a-z]+", "_", s.lower()).strip("_")


def _value(socket):
    v = getattr(socket, "default_value", None)
    if v is None:
        return None
    try:
        return [float(x) for x in v][:3]
    except TypeError:
        return float(v)


class GraphBuilder:
    """One IR graph for one Blender material."""

    def __init__(self, mat_name, images, warn, stats):
        self.mat = mat_name
        self.images = images
        self.warn = warn
        self.stats = stats
        self.nodes: list[dict] = []
        self.index: dict[tuple, int] = {}

    # --- sockets -------------------------------------------------------------------------

    def _source(self, socket, path):
        """(node, output socket, group path) feeding ``socket``, through reroutes, groups and
        muted nodes; (None, None, path) when unlinked."""
        while socket.is_linked:
            link = socket.links[0]
            if not link.is_valid or link.is_muted:
                return None, None, path
            node, out = link.from_node, link.from_socket
            if node.bl_idname == "NodeReroute":
                socket = node.inputs[0]
                continue
            if node.mute:
                inner = next((l.from_socket for l in node.internal_links if l.to_socket == out),
                             None)
                if inner is None:
                    return None, None, path
                socket = inner
                continue
            if node.bl_idname == "ShaderNodeGroup" and node.node_tree is not None:
                gout = next((n for n in node.node_tree.nodes
                             if n.bl_idname == "NodeGroupOutput" and n.is_active_output), None)
                if gout is None:
                    return None, None, path
                inner = next((s for s in gout.inputs if s.identifier == out.identifier), None)
                if inner is None:
                    return None, None, path
                path = path + (node,)
                socket = inner
                continue
            if node.bl_idname == "NodeGroupInput":
                if not path:
                    return None, None, path
                group = path[-1]
                outer = next((s for s in group.inputs if s.identifier == out.identifier), None)
                if outer is None:
                    return None, None, path
                path = path[:-1]
                if not outer.is_linked:
                    return ("const", outer), None, path
                socket = outer
                continue
            return node, out, path
        return None, None, path

    def input_value(self, socket, path):
        """The IR value of a Blender input socket: a constant or a link."""
        node, out, p = self._source(socket, path)
        if isinstance(node, tuple):  # an unlinked group input: the group node's value
            return _value(node[1])
        if node is None:
            return _value(socket)
        i = self.node(node, p)
        if i is None:
            return _value(socket)
        return {"node": i, "output": self.output_name(node, out)}

    def output_name(self, node, out):
        if node.bl_idname == "ShaderNodeMix":
            return "result"
        if node.bl_idname in ("ShaderNodeMixShader", "ShaderNodeAddShader"):
            return "shader"
        return snake(out.identifier)

    # --- nodes ---------------------------------------------------------------------------

    def unsupported(self, node, why="is not supported"):
        self.stats["unsupported"] = self.stats.get("unsupported", 0) + 1
        self.warn(f"material '{self.mat}': node '{node.name}' ({node.bl_idname}) {why}; "
                  f"uses the value of the socket it feeds")

    def node(self, node, path):
        key = (tuple(n.name for n in path), node.name, id(node.id_data))
        if key in self.index:
            return self.index[key]
        kind = TYPES.get(node.bl_idname)
        if kind is None or kind not in SPECS:
            self.index[key] = None
            self.unsupported(node)
            return None
        ir = {"type": kind, "name": node.name}
        self.index[key] = len(self.nodes)
        self.nodes.append(ir)
        params = self.params(node, kind)
        if params is None:  # e.g. an image without pixels
            self.nodes[self.index[key]] = {"type": "value", "name": node.name,
                                           "params": {"value": 0.0}}
            return self.index[key]
        if params:
            ir["params"] = params
        ir["inputs"] = self.inputs(node, kind, path)
        return self.index[key]

    def inputs(self, node, kind, path):
        accepted = {n for n, _ in SPECS[kind]["inputs"]}
        out = {}
        if kind == "mix":
            dt = node.data_type
            suffix = {"FLOAT": "Float", "VECTOR": "Vector", "RGBA": "Color", "ROTATION": "Rotation"}[dt]
            fac = "Factor_Vector" if dt == "VECTOR" and node.factor_mode == "NON_UNIFORM" else "Factor_Float"
            names = {fac: "factor", f"A_{suffix}": "a", f"B_{suffix}": "b"}
        elif kind == "mix_shader":
            names = {"Fac": "fac", "Shader": "shader1", "Shader_001": "shader2"}
        elif kind == "add_shader":
            names = {"Shader": "shader1", "Shader_001": "shader2"}
        else:
            names = None
        for s in node.inputs:
            if not s.enabled and names is None:
                continue
            name = names.get(s.identifier) if names is not None else snake(s.identifier)
            if name is None:
                continue
            if name not in accepted:
                if s.is_linked:
                    self.warn(f"material '{self.mat}': node '{node.name}' ({node.bl_idname}): "
                              f"input '{s.name}' is not supported; ignored")
                continue
            if not s.is_linked and getattr(s, "hide_value", False):
                continue  # an implicit input (texture coordinates, the normal): the core's
            v = self.input_value(s, path)
            if v is not None:
                out[name] = v
        return out

    def params(self, node, kind):
        p = {}
        for e in ENUMS:
            if hasattr(node, e):
                p[e] = getattr(node, e)
        for b in BOOLS:
            if hasattr(node, b) and isinstance(getattr(node, b), bool):
                p[b] = bool(getattr(node, b))
        if kind in ("principled", "glossy", "glass"):
            p["multiscatter"] = getattr(node, "distribution", "MULTI_GGX") == "MULTI_GGX"
            p.pop("distribution", None)
        if kind == "value":
            p["value"] = float(node.outputs[0].default_value)
        elif kind == "rgb":
            p["color"] = [float(c) for c in node.outputs[0].default_value[:3]]
        elif kind == "image_texture":
            linked_alpha = node.outputs["Alpha"].is_linked
            t = self.images.texture(node.image, node.extension, f" (material '{self.mat}')",
                                    alpha=linked_alpha)
            if t is None:
                return None
            p = {"texture": t, "interpolation": node.interpolation,
                 "projection": node.projection}
            if node.projection == "BOX":
                p["projection_blend"] = float(node.projection_blend)
        elif kind == "color_ramp":
            r = node.color_ramp
            p = {"interpolation": r.interpolation, "color_mode": r.color_mode,
                 "hue_interpolation": r.hue_interpolation,
                 "stops": [[float(e.position)] + [float(c) for c in e.color] for e in r.elements]}
        elif kind in ("rgb_curves", "float_curve"):
            m = node.mapping
            m.update()
            handle = {"AUTO": 0.0, "AUTO_CLAMPED": 1.0, "VECTOR": 2.0}
            p = {"curves": [[[float(pt.location[0]), float(pt.location[1]),
                              handle.get(pt.handle_type, 0.0)]
                             for pt in c.points] for c in m.curves],
                 "clip": [float(m.clip_min_x), float(m.clip_max_x)],
                 "extend": m.extend}
        elif kind == "brick_texture":
            p.update(offset=float(node.offset), offset_frequency=int(node.offset_frequency),
                     squash=float(node.squash), squash_frequency=int(node.squash_frequency))
        elif kind == "magic_texture":
            p["turbulence_depth"] = int(node.turbulence_depth)
        elif kind == "tex_coord" and node.object is not None:
            self.warn(f"material '{self.mat}': node '{node.name}': coordinates of another "
                      f"object ('{node.object.name}') render as this object's own")
        elif kind == "uv_map" and node.uv_map:
            # A named UV map is the mesh's corner attribute of that name.
            p["uv_map"] = node.uv_map
            self.stats.setdefault("attributes", set()).add(node.uv_map)
        elif kind == "attribute":
            if node.bl_idname == "ShaderNodeVertexColor":
                name = node.layer_name  # empty: the mesh's default colour attribute
            else:
                name = node.attribute_name
                if node.attribute_type != "GEOMETRY":
                    self.warn(f"material '{self.mat}': node '{node.name}': "
                              f"{node.attribute_type.lower()} attributes are not supported; "
                              f"reads zero")
                    name = "\0unsupported"
            p = {"name": name}
            self.stats.setdefault("attributes", set()).add(name)
        return p

    def displacement(self, mat, out_node):
        """The Material Output's Displacement as a link, applied as a bump (Cycles' Bump Only);
        None when unlinked or constant."""
        socket = out_node.inputs.get("Displacement")
        if socket is None or not socket.is_linked:
            return None
        method = getattr(mat, "displacement_method", "BUMP")
        if method != "BUMP":
            self.warn(f"material '{self.mat}': displacement method {method}: the surface is "
                      f"not moved; the displacement renders as a bump (Bump Only)")
        v = self.input_value(socket, ())
        return {"node": v["node"], "output": v["output"]} if isinstance(v, dict) else None

    def surface(self, socket):
        v = self.input_value(socket, ())
        if not isinstance(v, dict):
            return None
        return {"node": v["node"]}


def translate(mat, out_node, images, warn, stats) -> dict | None:
    """The IR ``graph`` material for ``mat`` (its Material Output ``out_node``), or None when
    the Surface socket reaches no shader the core knows."""
    b = GraphBuilder(mat.name, images, warn, stats)
    surf = b.surface(out_node.inputs["Surface"])
    if surf is None:
        return None
    g = {"type": "graph", "name": mat.name, "nodes": b.nodes, "surface": surf}
    disp = b.displacement(mat, out_node)
    if disp is not None:
        g["displacement"] = disp
    return g
