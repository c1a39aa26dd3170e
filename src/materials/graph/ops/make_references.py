"""Reference values for the converter nodes in this directory, rendered by Cycles.

Run with the Blender-as-a-module environment:

    .venv-bpy/bin/python src/materials/graph/ops/make_references.py

Every reference is a Cycles render, so the values include whatever Cycles does
beyond the node formula (ramp and curve tables, the clamp node inserted for
Math "use_clamp" and Map Range "clamp", OpenColorIO-derived matrices).

Set-up: a grid mesh with one quad per pixel, seen by an orthographic camera
whose pixels coincide with the quads. The node inputs are face-domain
attributes (constant over each quad); each row of quads has its own material
(one node configuration), each column is one input sample. The node outputs go
to an Emission shader of strength 1 (one row per output socket), rendered with
one sample, no bounces and a 0.01 px box filter into a float32 EXR, so every
pixel of the combined pass holds the shader value at the centre of its quad
(negative and non-finite values pass unchanged). Two extra rows carry the
(column, row) of each quad and are checked, so a misplaced camera cannot go
unnoticed. (Shader AOVs would be neater, but the bpy module writes only the
combined pass.)

Colour ramps and curves also record Blender's exact evaluation (RNA
``ColorRamp.evaluate`` / ``CurveMapping.evaluate``, i.e. BKE_colorband_evaluate
and BKE_curvemap_evaluateF with clipping off) next to the Cycles render, which
looks the values up in a 257-entry table.

Inputs are chosen with at most five significant digits, so that the JSON text
(seven significant digits) parses back to exactly the float32 Blender used.
Non-finite outputs are stored as null.
"""

import json
import math
import os
import random
import sys
import tempfile

import bpy
import numpy as np
import OpenImageIO as oiio

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "testdata")
W = 48  # samples per case


def q(x, digits=5):
    """Round to `digits` significant digits (exactly representable in JSON)."""
    return float(f"{x:.{digits}g}")


def sig7(x):
    x = float(x)
    if not math.isfinite(x):
        return None
    return float(f"{x:.7g}")


def out_list(arr):
    arr = np.asarray(arr, dtype=np.float64)
    if arr.ndim == 1:
        return [sig7(v) for v in arr]
    return [[sig7(v) for v in row] for row in arr]


# ----------------------------------------------------------------------------
# Scene and render harness


def reset_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 1
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False
    scene.cycles.pixel_filter_type = "BOX"
    scene.cycles.filter_width = 0.01
    scene.cycles.max_bounces = 0
    scene.view_settings.view_transform = "Standard"
    scene.render.film_transparent = True
    scene.render.resolution_percentage = 100
    scene.render.image_settings.media_type = "MULTI_LAYER_IMAGE"
    scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    scene.render.image_settings.color_depth = "32"
    scene.render.threads_mode = "FIXED"
    scene.render.threads = 1
    return scene


def new_material(name):
    mat = bpy.data.materials.new(name)
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    return mat, nt


def emit(nt, sock, negate=False):
    """Route `sock` to an Emission shader of strength 1 (negated if asked)."""
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = 1.0
    if negate:
        neg = nt.nodes.new("ShaderNodeVectorMath")
        neg.operation = "SCALE"
        neg.inputs["Scale"].default_value = -1.0
        nt.links.new(sock, neg.inputs[0])
        sock = neg.outputs["Vector"]
    nt.links.new(sock, em.inputs["Color"])
    nt.links.new(em.outputs[0], out.inputs["Surface"])


class Inputs:
    """Lazily created Attribute nodes reading the per-face inputs."""

    def __init__(self, nt):
        self.nt = nt
        self.nodes = {}

    def __getitem__(self, name):
        if name not in self.nodes:
            n = self.nt.nodes.new("ShaderNodeAttribute")
            n.attribute_type = "GEOMETRY"
            n.attribute_name = name
            self.nodes[name] = n
        n = self.nodes[name]
        return n.outputs["Fac"] if name.startswith("f") else n.outputs["Vector"]


def render(inputs, builders, keys=("o0",)):
    """Render the outputs of every builder over the W input samples.

    inputs: dict name -> list of W floats (names "f*") or W 3-vectors ("v*").
    builders: list of functions (node_tree, Inputs) -> dict key -> output socket.
    keys: the output keys to render (each builder must return all of them).
    Returns a list (one per builder) of dicts key -> (W, 3) array.

    Negative and non-finite emission reaches the combined pass unchanged.
    Two more rows carry the quad index, first and last, to check alignment.
    """
    scene = reset_scene()
    rows = [("index", None, False)]
    for b, build in enumerate(builders):
        for key in keys:
            rows.append((b, key, False))
    rows.append(("index", None, False))
    H = len(rows)
    scene.render.resolution_x = W
    scene.render.resolution_y = H

    verts = [(x, y, 0.0) for y in range(H + 1) for x in range(W + 1)]
    faces = []
    for r in range(H):
        y = H - 1 - r  # row 0 at the top of the image
        for c in range(W):
            v0 = y * (W + 1) + c
            faces.append((v0, v0 + 1, v0 + 1 + (W + 1), v0 + (W + 1)))
    mesh = bpy.data.meshes.new("grid")
    mesh.from_pydata(verts, [], faces)
    mesh.update()

    for name, values in inputs.items():
        assert len(values) == W, name
        if name.startswith("f"):
            a = mesh.attributes.new(name, "FLOAT", "FACE")
            a.data.foreach_set("value", [float(v) for _ in range(H) for v in values])
        else:
            a = mesh.attributes.new(name, "FLOAT_VECTOR", "FACE")
            a.data.foreach_set("vector", [float(x) for _ in range(H) for v in values for x in v])
    idx = mesh.attributes.new("vidx", "FLOAT_VECTOR", "FACE")
    idx.data.foreach_set("vector", [float(x) for r in range(H) for c in range(W) for x in (c, r, 1)])

    for r, (b, key, negate) in enumerate(rows):
        mat, nt = new_material(f"row{r}")
        inp = Inputs(nt)
        sock = inp["vidx"] if b == "index" else builders[b](nt, inp)[key]
        emit(nt, sock, negate)
        mesh.materials.append(mat)
    mesh.polygons.foreach_set("material_index", [r for r in range(H) for _ in range(W)])
    mesh.update()

    obj = bpy.data.objects.new("grid", mesh)
    scene.collection.objects.link(obj)
    cam_data = bpy.data.cameras.new("cam")
    cam_data.type = "ORTHO"
    cam_data.ortho_scale = float(max(W, H))
    cam = bpy.data.objects.new("cam", cam_data)
    cam.location = (W / 2.0, H / 2.0, 10.0)
    scene.collection.objects.link(cam)
    scene.camera = cam

    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "render.exr")
        scene.render.filepath = path
        bpy.ops.render.render(write_still=True)
        img = oiio.ImageBuf(path)
        chans = list(img.spec().channelnames)
        pixels = img.get_pixels(oiio.FLOAT)  # (H, W, C), row 0 at the top
    ids = [chans.index(f"ViewLayer.Combined.{c}") for c in "RGB"]
    rgb = pixels[:, :, ids].astype(np.float64)

    for r in (0, H - 1):
        want = np.stack([np.arange(W), np.full(W, r), np.ones(W)], axis=-1)
        assert np.array_equal(rgb[r], want), ("pixel/quad alignment is off", r, rgb[r][:4])

    results = [{} for _ in builders]
    for r, (b, key, negate) in enumerate(rows):
        if b == "index":
            continue
        results[b][key] = rgb[r]
    return results


def write(name, data):
    os.makedirs(OUT, exist_ok=True)
    path = os.path.join(OUT, f"{name}.json")
    with open(path, "w") as f:
        json.dump(data, f, separators=(",", ":"))
    print(f"wrote {path} ({os.path.getsize(path)} bytes)", file=sys.stderr)


def enum_ids(cls, prop):
    return [e.identifier for e in getattr(bpy.types, cls).bl_rna.properties[prop].enum_items]


# ----------------------------------------------------------------------------
# Inputs


def scalar_samples(rng, edge, lo, hi):
    vals = [q(v) for v in edge][:W]
    while len(vals) < W:
        vals.append(q(rng.uniform(lo, hi), 4))
    return vals


def vector_samples(rng, edge, lo, hi):
    vals = [[q(x) for x in v] for v in edge][:W]
    while len(vals) < W:
        vals.append([q(rng.uniform(lo, hi), 4) for _ in range(3)])
    return vals


# ----------------------------------------------------------------------------
# Math


def make_math():
    rng = random.Random(1)
    a_edge = [0, 1, -1, 0.5, -0.5, 2, -2, 2.5, -2.5, 3.75, -3.75, 0.25, 10, -10, 0.1, 1.5,
              0.999, -0.001, 7.3, -7.3, 8.5, 0.7, -0.7, 4, 3, 1, 0, -0.25]
    b_edge = [0, 0, 2, -2, 0.5, 0.5, 3, 1.5, -1.5, 1, 1, 0.25, 3, 3, -0.3, 1.5,
              1, 2, -2.2, 2.2, 0.5, -0.7, 0.7, 0.5, 3, 1, 1, -0.25]
    c_edge = [0, 1, 0.5, 0, 0.25, 1, -1, 0.1, 2, 0, 0.5, 0.25, 5, -5, 0.2, 0,
              0.01, 1, 0.3, 0.3, 0.2, 1, 0, 0, 2, 0.5, 0, 0]
    fa = scalar_samples(rng, a_edge, -6, 6)
    fb = scalar_samples(rng, b_edge, -4, 4)
    fc = scalar_samples(rng, c_edge, -1, 2)
    cases = [(op, False) for op in enum_ids("ShaderNodeMath", "operation")]
    cases += [(op, True) for op in ("ADD", "SUBTRACT", "MULTIPLY", "SINE", "POWER", "DEGREES")]

    def builder(op, clamp):
        def build(nt, inp):
            n = nt.nodes.new("ShaderNodeMath")
            n.operation = op
            n.use_clamp = clamp
            for i, name in enumerate(("fa", "fb", "fc")):
                nt.links.new(inp[name], n.inputs[i])
            return {"o0": n.outputs[0]}
        return build

    res = render({"fa": fa, "fb": fb, "fc": fc}, [builder(*c) for c in cases])
    write("math", {
        "inputs": {"a": fa, "b": fb, "c": fc},
        "cases": [{"op": op, "use_clamp": clamp, "value": out_list(r["o0"][:, 0])}
                  for (op, clamp), r in zip(cases, res)],
    })


# ----------------------------------------------------------------------------
# Vector Math


VALUE_OPS = {"DOT_PRODUCT", "DISTANCE", "LENGTH"}


def make_vector_math():
    rng = random.Random(2)
    a_edge = [[0, 0, 0], [1, 0, 0], [1, 2, 3], [-1.5, 0.5, 2.25], [0.5, -0.5, 0],
              [3, -4, 0], [2.5, -2.5, 7.3], [0.25, 0.75, -0.125], [-2, -3, -4], [1, 1, 1],
              [0.3, -0.4, 0.5], [10, -10, 0.1]]
    b_edge = [[0, 0, 0], [0, 1, 0], [0, 0, 0], [1, 1, 0], [0.5, 0, -2],
              [0, 0, 1], [2, 0.5, -1.5], [-1, 2, 0], [3, 3, 3], [0, 0, 2],
              [1, -1, 1], [0.3, 0.3, 0]]
    c_edge = [[0, 0, 0], [1, 1, 1], [0.5, -1, 2], [0, 0, 0], [-1, 0, 1],
              [1, 0, 0], [0, 0, 0], [-1, -1, -1], [0.5, 0.5, 0.5], [0, 1, 0],
              [2, 2, 2], [-0.5, 0.5, 1]]
    s_edge = [0, 1, 1.45, 0.5, -2, 0.75, 1.5, 1, 2, 0.9, 1.33, -1]
    va = vector_samples(rng, a_edge, -4, 4)
    vb = vector_samples(rng, b_edge, -3, 3)
    vc = vector_samples(rng, c_edge, -2, 2)
    fs = scalar_samples(rng, s_edge, -2, 2)
    ops = enum_ids("ShaderNodeVectorMath", "operation")

    def builder(op):
        def build(nt, inp):
            n = nt.nodes.new("ShaderNodeVectorMath")
            n.operation = op
            nt.links.new(inp["va"], n.inputs[0])
            nt.links.new(inp["vb"], n.inputs[1])
            nt.links.new(inp["vc"], n.inputs[2])
            nt.links.new(inp["fs"], n.inputs[3])
            # Only the output the operation makes is available.
            return {"o0": n.outputs[1] if op in VALUE_OPS else n.outputs[0]}
        return build

    res = render({"va": va, "vb": vb, "vc": vc, "fs": fs}, [builder(op) for op in ops])
    cases = []
    for op, r in zip(ops, res):
        case = {"op": op}
        if op in VALUE_OPS:
            case["value"] = out_list(r["o0"][:, 0])
        else:
            case["vector"] = out_list(r["o0"])
        cases.append(case)
    write("vector_math", {"inputs": {"a": va, "b": vb, "c": vc, "scale": fs}, "cases": cases})


# ----------------------------------------------------------------------------
# Vector Rotate


def make_vector_rotate():
    rng = random.Random(9)
    v_edge = [[1, 0, 0], [0, 1, 0], [1, 2, 3], [-1.5, 0.5, 2.25], [0, 0, 0], [3, -4, 0.5]]
    c_edge = [[0, 0, 0], [0, 0, 0], [0.5, -1, 2], [1, 1, 1], [0, 0, 0], [-2, 0, 1]]
    a_edge = [[0, 0, 1], [1, 0, 0], [0, 0, 0], [1, 1, 1], [0.3, -2, 0.5], [0, 2, 0]]
    f_edge = [1.5708, 0.5, 2, -1, 3.1416, 0]
    r_edge = [[0, 0, 1.5708], [0.5, 0, 0], [0.1, 0.2, 0.3], [-1, 2, 0.5], [3.1416, 0, 0],
              [0, -0.7, 1.2]]
    vv = vector_samples(rng, v_edge, -4, 4)
    vc = vector_samples(rng, c_edge, -2, 2)
    va = vector_samples(rng, a_edge, -2, 2)
    fa = scalar_samples(rng, f_edge, -7, 7)
    vr = vector_samples(rng, r_edge, -4, 4)
    cases = [{"rotation_type": t, "invert": inv}
             for t in enum_ids("ShaderNodeVectorRotate", "rotation_type")
             for inv in (False, True)]

    def builder(case):
        def build(nt, inp):
            n = nt.nodes.new("ShaderNodeVectorRotate")
            n.rotation_type = case["rotation_type"]
            n.invert = case["invert"]
            # By index: the sockets a rotation type does not use are not found by name.
            for k, name in enumerate(("vv", "vc", "va", "fa", "vr")):
                nt.links.new(inp[name], n.inputs[k])
            return {"o0": n.outputs["Vector"]}
        return build

    res = render({"vv": vv, "vc": vc, "va": va, "fa": fa, "vr": vr},
                 [builder(c) for c in cases])
    for case, r in zip(cases, res):
        case["vector"] = out_list(r["o0"])
    write("vector_rotate", {"inputs": {"vector": vv, "center": vc, "axis": va, "angle": fa,
                                       "rotation": vr}, "cases": cases})


# ----------------------------------------------------------------------------
# Mix


def make_mix():
    rng = random.Random(3)
    fac_edge = [0, 1, 0.5, -0.5, 1.5, 0.25, 0.75, 2, -1, 0.1]
    a_edge = [[0, 0, 0], [1, 1, 1], [0.5, 0.5, 0.5], [0.2, 0.4, 0.8], [0.9, 0.1, 0.3],
              [1.2, -0.1, 0.5], [0.3, 0.3, 0.6], [0, 0.5, 1], [0.6, 0.2, 0.2], [0.45, 0.55, 0.65]]
    b_edge = [[1, 1, 1], [0, 0, 0], [0.5, 0.5, 0.5], [0.9, 0.1, 0.3], [0.2, 0.4, 0.8],
              [0, 0.5, 1], [1.3, 0.7, -0.2], [0.25, 0.25, 0.25], [0.1, 0.8, 0.4], [0, 0, 0.5]]
    fd = scalar_samples(rng, fac_edge, -0.3, 1.3)
    va = vector_samples(rng, a_edge, -0.2, 1.2)
    vb = vector_samples(rng, b_edge, -0.2, 1.2)
    vf = vector_samples(rng, [[0, 0.5, 1], [-0.5, 1.5, 0.25]], -0.3, 1.3)
    fa = [v[0] for v in va]
    fb = [v[1] for v in vb]
    cases = []
    for clamp in (False, True):
        cases.append({"data_type": "FLOAT", "clamp_factor": clamp})
        cases.append({"data_type": "VECTOR", "factor_mode": "UNIFORM", "clamp_factor": clamp})
        cases.append({"data_type": "VECTOR", "factor_mode": "NON_UNIFORM", "clamp_factor": clamp})
    for blend in enum_ids("ShaderNodeMix", "blend_type"):
        cases.append({"data_type": "RGBA", "blend_type": blend, "clamp_factor": False,
                      "clamp_result": False})
        cases.append({"data_type": "RGBA", "blend_type": blend, "clamp_factor": True,
                      "clamp_result": True})

    def builder(case):
        def build(nt, inp):
            n = nt.nodes.new("ShaderNodeMix")
            n.data_type = case["data_type"]
            n.clamp_factor = case["clamp_factor"]
            ins = {s.identifier: s for s in n.inputs}
            outs = {s.identifier: s for s in n.outputs}
            if case["data_type"] == "FLOAT":
                nt.links.new(inp["fd"], ins["Factor_Float"])
                nt.links.new(inp["fa"], ins["A_Float"])
                nt.links.new(inp["fb"], ins["B_Float"])
                return {"o0": outs["Result_Float"]}
            if case["data_type"] == "VECTOR":
                n.factor_mode = case["factor_mode"]
                if case["factor_mode"] == "UNIFORM":
                    nt.links.new(inp["fd"], ins["Factor_Float"])
                else:
                    nt.links.new(inp["vf"], ins["Factor_Vector"])
                nt.links.new(inp["va"], ins["A_Vector"])
                nt.links.new(inp["vb"], ins["B_Vector"])
                return {"o0": outs["Result_Vector"]}
            n.blend_type = case["blend_type"]
            n.clamp_result = case["clamp_result"]
            nt.links.new(inp["fd"], ins["Factor_Float"])
            nt.links.new(inp["va"], ins["A_Color"])
            nt.links.new(inp["vb"], ins["B_Color"])
            return {"o0": outs["Result_Color"]}
        return build

    res = render({"fd": fd, "fa": fa, "fb": fb, "va": va, "vb": vb, "vf": vf},
                 [builder(c) for c in cases])
    for case, r in zip(cases, res):
        if case["data_type"] == "FLOAT":
            case["result"] = out_list(r["o0"][:, 0])
        else:
            case["result"] = out_list(r["o0"])
    write("mix", {"inputs": {"factor": fd, "factor_vector": vf, "a_float": fa, "b_float": fb,
                             "a": va, "b": vb}, "cases": cases})


# ----------------------------------------------------------------------------
# Colour nodes


def make_color():
    rng = random.Random(4)
    col_edge = [[0, 0, 0], [1, 1, 1], [0.5, 0.5, 0.5], [1, 0, 0], [0, 1, 0], [0, 0, 1],
                [1, 1, 0], [0.2, 0.4, 0.8], [0.9, 0.1, 0.3], [0.3, 0.3, 0.6], [0.6, 0.6, 0.2],
                [1.5, 0.5, 0.25], [-0.2, 0.5, 0.7], [0.8, 0.8, 0.8], [0.25, 0.75, 0.75],
                [0.999, 0.5, 0], [0.1, 0.05, 0.02], [2, 3, 1]]
    va = vector_samples(rng, col_edge, -0.1, 1.2)
    fa = scalar_samples(rng, [0.5, 0, 1, 0.25, 0.75, 0.6, 0.4], 0, 1)
    fb = scalar_samples(rng, [1, 0, 2, 0.5, 1.5, 1, 1], 0, 2)
    fc = scalar_samples(rng, [1, 1, 0.5, 2, 0, 1, 1.2], 0, 2)
    fd = scalar_samples(rng, [1, 0, 0.5, 1, 1, -0.5, 1.5], -0.2, 1.2)
    fg = scalar_samples(rng, [0, 1, 2.2, 0.45, 0.5, 3, -1], 0, 3)
    fbr = scalar_samples(rng, [0, 0.5, -0.5, 0.2, 1, -1, 0.1], -1, 1)
    fct = scalar_samples(rng, [0, 0.5, -0.5, 1, 2, -1, -0.9], -1, 2)
    # Combine Color inputs: hue-like first component inside [0, 1] mostly.
    vh = vector_samples(rng, [[0, 1, 0.5], [1, 1, 1], [0.5, 0, 0.5], [0.999, 0.5, 0.75],
                              [0.25, 0.5, 0.25], [0.75, 0.2, 0.9], [1.2, 0.5, 0.5],
                              [-0.1, 0.5, 0.5], [0.6, 1.5, 0.5], [0.3, 0.5, 1.2]], 0, 1)

    def node_case(kind, mode=None):
        def build(nt, inp):
            if kind == "HUE_SAT":
                n = nt.nodes.new("ShaderNodeHueSaturation")
                nt.links.new(inp["fa"], n.inputs["Hue"])
                nt.links.new(inp["fb"], n.inputs["Saturation"])
                nt.links.new(inp["fc"], n.inputs["Value"])
                nt.links.new(inp["fd"], n.inputs["Fac"])
                nt.links.new(inp["va"], n.inputs["Color"])
                return {"o0": n.outputs[0]}
            if kind == "BRIGHT_CONTRAST":
                n = nt.nodes.new("ShaderNodeBrightContrast")
                nt.links.new(inp["va"], n.inputs["Color"])
                nt.links.new(inp["fbr"], n.inputs["Bright"])
                nt.links.new(inp["fct"], n.inputs["Contrast"])
                return {"o0": n.outputs[0]}
            if kind == "GAMMA":
                n = nt.nodes.new("ShaderNodeGamma")
                nt.links.new(inp["va"], n.inputs["Color"])
                nt.links.new(inp["fg"], n.inputs["Gamma"])
                return {"o0": n.outputs[0]}
            if kind == "INVERT":
                n = nt.nodes.new("ShaderNodeInvert")
                nt.links.new(inp["fd"], n.inputs["Fac"])
                nt.links.new(inp["va"], n.inputs["Color"])
                return {"o0": n.outputs[0]}
            if kind == "RGB_TO_BW":
                n = nt.nodes.new("ShaderNodeRGBToBW")
                nt.links.new(inp["va"], n.inputs[0])
                return {"o0": n.outputs[0]}
            if kind == "SEPARATE":
                n = nt.nodes.new("ShaderNodeSeparateColor")
                n.mode = mode
                nt.links.new(inp["va"], n.inputs[0])
                comb = nt.nodes.new("ShaderNodeCombineXYZ")
                for i in range(3):
                    nt.links.new(n.outputs[i], comb.inputs[i])
                return {"o0": comb.outputs[0]}
            if kind == "COMBINE":
                n = nt.nodes.new("ShaderNodeCombineColor")
                n.mode = mode
                sep = nt.nodes.new("ShaderNodeSeparateXYZ")
                nt.links.new(inp["vh"], sep.inputs[0])
                for i in range(3):
                    nt.links.new(sep.outputs[i], n.inputs[i])
                return {"o0": n.outputs[0]}
            raise ValueError(kind)
        return build

    cases = [("HUE_SAT", None), ("BRIGHT_CONTRAST", None), ("GAMMA", None), ("INVERT", None),
             ("RGB_TO_BW", None)]
    cases += [("SEPARATE", m) for m in ("RGB", "HSV", "HSL")]
    cases += [("COMBINE", m) for m in ("RGB", "HSV", "HSL")]
    inputs = {"va": va, "vh": vh, "fa": fa, "fb": fb, "fc": fc, "fd": fd, "fg": fg,
              "fbr": fbr, "fct": fct}
    res = render(inputs, [node_case(*c) for c in cases])
    out = []
    for (kind, mode), r in zip(cases, res):
        case = {"node": kind}
        if mode:
            case["mode"] = mode
        if kind == "RGB_TO_BW":
            case["result"] = out_list(r["o0"][:, 0])
        else:
            case["result"] = out_list(r["o0"])
        out.append(case)
    write("color", {"inputs": {"color": va, "components": vh, "hue": fa, "saturation": fb,
                               "value": fc, "factor": fd, "gamma": fg, "bright": fbr,
                               "contrast": fct}, "cases": out})


def make_blackbody_wavelength():
    temps = [0, -100, 500, 799, 800, 900, 964.9, 965, 1000, 1166, 1167, 1300, 1448, 1449,
             1700, 1901, 1902, 2500, 3000, 3314, 3315, 4000, 5000, 5500, 6364, 6365, 6500,
             7500, 9000, 11000, 11999, 12000, 15000, 40000, 1234.5, 2345.6, 4321, 6789]
    temps = scalar_samples(random.Random(5), temps, 800, 12000)
    nms = [300, 379, 380, 381, 382.5, 385, 400, 420.3, 450, 475, 500, 525, 550, 575, 580,
           600, 625, 650, 675, 700, 725, 750, 775, 778, 779, 779.5, 779.99, 780, 781, 800,
           555.5, 612.3, 700.1]
    nms = scalar_samples(random.Random(6), nms, 380, 780)

    def bb(nt, inp):
        n = nt.nodes.new("ShaderNodeBlackbody")
        nt.links.new(inp["fa"], n.inputs[0])
        return {"o0": n.outputs[0]}

    def wl(nt, inp):
        n = nt.nodes.new("ShaderNodeWavelength")
        nt.links.new(inp["fb"], n.inputs[0])
        return {"o0": n.outputs[0]}

    res = render({"fa": temps, "fb": nms}, [bb, wl])
    write("blackbody", {"temperature": temps, "color": out_list(res[0]["o0"])})
    write("wavelength", {"wavelength": nms, "color": out_list(res[1]["o0"])})


# ----------------------------------------------------------------------------
# Map Range and Clamp


def make_map_range():
    rng = random.Random(7)
    fa = scalar_samples(rng, [0, 1, 0.2, 0.8, 0.5, -1, 2, 0.35, 0.65, 0.2001, 0.7999, -0.5,
                              1.5, 0.4, 0.6, 0.95, 0.05, 3], -1, 2)
    va = vector_samples(rng, [[0, 0, 0], [1, 1, 1], [0.2, 0.5, 0.8], [-1, 2, 0.5],
                              [0.35, 0.65, 0.1], [1.5, -0.5, 0.3]], -1, 2)
    param_sets = [
        {"from_min": 0.2, "from_max": 0.8, "to_min": -1.0, "to_max": 2.0, "steps": 4.0},
        {"from_min": 1.0, "from_max": -1.0, "to_min": 3.0, "to_max": 0.5, "steps": 2.5},
        {"from_min": 0.5, "from_max": 0.5, "to_min": 0.25, "to_max": 1.0, "steps": 4.0},
        {"from_min": 0.0, "from_max": 1.0, "to_min": 0.0, "to_max": 1.0, "steps": 0.0},
    ]
    vparams = {"from_min": [0.2, 1.0, 0.5], "from_max": [0.8, -1.0, 0.5],
               "to_min": [-1.0, 3.0, 0.25], "to_max": [2.0, 0.5, 1.0], "steps": [4.0, 2.5, 0.0]}
    cases = []
    for interp in enum_ids("ShaderNodeMapRange", "interpolation_type"):
        for clamp in (False, True):
            for p in param_sets:
                cases.append({"data_type": "FLOAT", "interpolation": interp, "clamp": clamp, **p})
            cases.append({"data_type": "FLOAT_VECTOR", "interpolation": interp, "clamp": clamp,
                          **vparams})

    def builder(case):
        def build(nt, inp):
            n = nt.nodes.new("ShaderNodeMapRange")
            n.data_type = case["data_type"]
            n.interpolation_type = case["interpolation"]
            n.clamp = case["clamp"]
            ins = {s.identifier: s for s in n.inputs}
            if case["data_type"] == "FLOAT":
                for key, sock in (("from_min", "From Min"), ("from_max", "From Max"),
                                  ("to_min", "To Min"), ("to_max", "To Max"), ("steps", "Steps")):
                    ins[sock].default_value = case[key]
                nt.links.new(inp["fa"], ins["Value"])
                return {"o0": n.outputs["Result"]}
            for key, sock in (("from_min", "From_Min_FLOAT3"), ("from_max", "From_Max_FLOAT3"),
                              ("to_min", "To_Min_FLOAT3"), ("to_max", "To_Max_FLOAT3"),
                              ("steps", "Steps_FLOAT3")):
                ins[sock].default_value = case[key]
            nt.links.new(inp["va"], ins["Vector"])
            return {"o0": n.outputs["Vector"]}
        return build

    clamp_cases = [{"clamp_type": t, "min": lo, "max": hi}
                   for t in ("MINMAX", "RANGE") for (lo, hi) in ((0.2, 0.8), (0.8, 0.2))]

    def clamp_builder(case):
        def build(nt, inp):
            n = nt.nodes.new("ShaderNodeClamp")
            n.clamp_type = case["clamp_type"]
            n.inputs["Min"].default_value = case["min"]
            n.inputs["Max"].default_value = case["max"]
            nt.links.new(inp["fa"], n.inputs["Value"])
            return {"o0": n.outputs[0]}
        return build

    res = render({"fa": fa, "va": va},
                 [builder(c) for c in cases] + [clamp_builder(c) for c in clamp_cases])
    for case, r in zip(cases, res):
        if case["data_type"] == "FLOAT":
            case["result"] = out_list(r["o0"][:, 0])
        else:
            case["result"] = out_list(r["o0"])
    for case, r in zip(clamp_cases, res[len(cases):]):
        case["result"] = out_list(r["o0"][:, 0])
    write("map_range", {"inputs": {"value": fa, "vector": va}, "cases": cases})
    write("clamp", {"inputs": {"value": fa}, "cases": clamp_cases})


# ----------------------------------------------------------------------------
# Colour ramp


RAMP_CONFIGS = [
    {"interpolation": "LINEAR", "color_mode": "RGB", "stops": [
        (0.2, (0.9, 0.1, 0.05, 1.0)), (0.5, (0.2, 0.7, 0.3, 0.5)), (0.9, (0.1, 0.2, 1.0, 0.0))]},
    {"interpolation": "CONSTANT", "color_mode": "RGB", "stops": [
        (0.2, (0.9, 0.1, 0.05, 1.0)), (0.5, (0.2, 0.7, 0.3, 0.5)), (0.9, (0.1, 0.2, 1.0, 0.0))]},
    {"interpolation": "EASE", "color_mode": "RGB", "stops": [
        (0.0, (0.0, 0.0, 0.0, 1.0)), (0.4, (1.0, 0.5, 0.25, 1.0)), (1.0, (0.3, 0.9, 0.6, 0.2))]},
    {"interpolation": "CARDINAL", "color_mode": "RGB", "stops": [
        (0.1, (0.9, 0.1, 0.05, 1.0)), (0.3, (0.2, 0.7, 0.3, 0.5)), (0.6, (0.1, 0.2, 1.0, 0.0)),
        (0.85, (1.0, 1.0, 0.2, 0.8))]},
    {"interpolation": "B_SPLINE", "color_mode": "RGB", "stops": [
        (0.1, (0.9, 0.1, 0.05, 1.0)), (0.3, (0.2, 0.7, 0.3, 0.5)), (0.6, (0.1, 0.2, 1.0, 0.0)),
        (0.85, (1.0, 1.0, 0.2, 0.8))]},
    {"interpolation": "CARDINAL", "color_mode": "RGB", "stops": [
        (0.0, (0.0, 0.0, 0.0, 1.0)), (1.0, (1.0, 1.0, 1.0, 1.0))]},
    {"interpolation": "LINEAR", "color_mode": "RGB", "stops": [(0.4, (0.3, 0.6, 0.9, 0.7))]},
    {"interpolation": "LINEAR", "color_mode": "RGB", "stops": [
        (0.5, (1.0, 0.0, 0.0, 1.0)), (0.5, (0.0, 0.0, 1.0, 0.5))]},
]
for mode in ("HSV", "HSL"):
    for hue in ("NEAR", "FAR", "CW", "CCW"):
        RAMP_CONFIGS.append({"interpolation": "LINEAR", "color_mode": mode, "hue_interpolation": hue,
                             "stops": [(0.1, (1.0, 0.1, 0.1, 1.0)), (0.45, (0.1, 0.3, 1.0, 0.6)),
                                       (0.8, (0.9, 0.8, 0.1, 0.2)), (0.95, (0.9, 0.2, 0.6, 1.0))]})
RAMP_CONFIGS.append({"interpolation": "EASE", "color_mode": "HSV", "hue_interpolation": "FAR",
                     "stops": [(0.0, (0.2, 0.9, 0.3, 1.0)), (1.0, (0.2, 0.9, 0.3, 1.0))]})


def setup_ramp(ramp, cfg):
    ramp.interpolation = cfg["interpolation"]
    ramp.color_mode = cfg["color_mode"]
    ramp.hue_interpolation = cfg.get("hue_interpolation", "NEAR")
    stops = cfg["stops"]
    els = ramp.elements
    while len(els) > 1:
        els.remove(els[len(els) - 1])
    els[0].position = stops[0][0]
    els[0].color = stops[0][1]
    for pos, col in stops[1:]:
        e = els.new(pos)
        e.color = col


def make_ramp():
    rng = random.Random(8)
    edge = [-0.3, 0, 0.1, 0.2, 0.3, 0.4, 0.45, 0.5, 0.6, 0.8, 0.85, 0.9, 0.95, 1, 1.3,
            0.25, 0.7, 0.001, 0.999, 0.50001, 0.49999, 0.123, 0.777]
    fa = scalar_samples(rng, edge, 0, 1)

    def builder(cfg):
        def build(nt, inp):
            n = nt.nodes.new("ShaderNodeValToRGB")
            setup_ramp(n.color_ramp, cfg)
            nt.links.new(inp["fa"], n.inputs[0])
            return {"o0": n.outputs["Color"], "o1": n.outputs["Alpha"]}
        return build

    res = render({"fa": fa}, [builder(c) for c in RAMP_CONFIGS], keys=("o0", "o1"))
    # Exact colour-band evaluation through RNA.
    mat, nt = new_material("exact")
    cases = []
    for cfg, r in zip(RAMP_CONFIGS, res):
        n = nt.nodes.new("ShaderNodeValToRGB")
        setup_ramp(n.color_ramp, cfg)
        exact = [list(n.color_ramp.evaluate(x)) for x in fa]
        stops = [{"position": e.position, "color": [sig7(c) for c in e.color]}
                 for e in n.color_ramp.elements]
        cases.append({
            "interpolation": cfg["interpolation"], "color_mode": cfg["color_mode"],
            "hue_interpolation": cfg.get("hue_interpolation", "NEAR"), "stops": stops,
            "cycles_color": out_list(r["o0"]), "cycles_alpha": out_list(r["o1"][:, 0]),
            "exact": out_list(exact),
        })
    write("ramp", {"inputs": {"factor": fa}, "cases": cases})


# ----------------------------------------------------------------------------
# Curves

FLOAT_CURVES = [
    {"extend": "HORIZONTAL", "points": [(0, 0, "AUTO"), (0.3, 0.7, "AUTO"), (1, 1, "AUTO")]},
    {"extend": "EXTRAPOLATED", "points": [(0, 0, "AUTO"), (0.3, 0.7, "AUTO"), (1, 1, "AUTO")]},
    {"extend": "EXTRAPOLATED", "points": [(0, 0.1, "AUTO_CLAMPED"), (0.25, 0.9, "AUTO_CLAMPED"),
                                          (0.6, 0.2, "AUTO_CLAMPED"), (1, 0.8, "AUTO_CLAMPED")]},
    {"extend": "EXTRAPOLATED", "points": [(0, 1, "VECTOR"), (0.5, 0.2, "VECTOR"), (1, 0.6, "VECTOR")]},
    {"extend": "EXTRAPOLATED", "points": [(0.1, 0.2, "VECTOR"), (0.4, 0.9, "AUTO"),
                                          (0.7, 0.3, "AUTO_CLAMPED"), (0.9, 0.5, "AUTO")]},
    {"extend": "EXTRAPOLATED", "points": [(-0.5, 0.2, "AUTO"), (0.4, 0.9, "AUTO"), (1.5, 0.1, "AUTO")]},
    {"extend": "EXTRAPOLATED", "points": [(0.2, 0.1, "AUTO"), (0.7, 0.9, "AUTO")]},
    {"extend": "HORIZONTAL", "points": [(0.2, 0.1, "VECTOR"), (0.7, 0.9, "VECTOR")]},
]

RGB_CURVES = [
    {"extend": "HORIZONTAL", "curves": {
        "C": [(0, 0, "AUTO"), (0.4, 0.6, "AUTO"), (1, 1, "AUTO")]}},
    {"extend": "EXTRAPOLATED", "curves": {
        "R": [(0, 0.1, "AUTO"), (0.5, 0.3, "AUTO"), (1, 0.9, "AUTO")],
        "G": [(0, 0, "VECTOR"), (0.6, 0.8, "VECTOR"), (1, 1, "VECTOR")],
        "B": [(0, 0.5, "AUTO_CLAMPED"), (0.3, 0.1, "AUTO_CLAMPED"), (1, 0.7, "AUTO_CLAMPED")]}},
    {"extend": "EXTRAPOLATED", "curves": {
        "C": [(-0.25, 0, "AUTO"), (0.5, 0.7, "AUTO"), (1.25, 1.1, "AUTO")],
        "R": [(0, 0, "AUTO"), (0.5, 0.4, "AUTO"), (1, 1, "AUTO")]}},
]
CURVE_INDEX = {"R": 0, "G": 1, "B": 2, "C": 3}


def setup_curve(cmap, points):
    pts = cmap.points
    while len(pts) > 2:
        pts.remove(pts[len(pts) - 1])
    # Place the first two, then add the rest.
    pts[0].location = points[0][:2]
    pts[0].handle_type = points[0][2]
    pts[1].location = points[1][:2]
    pts[1].handle_type = points[1][2]
    for x, y, h in points[2:]:
        p = pts.new(x, y)
        p.handle_type = h


def setup_mapping(mapping, extend, curves):
    mapping.use_clip = False
    mapping.extend = extend
    for key, points in curves.items():
        setup_curve(mapping.curves[CURVE_INDEX.get(key, 0)], points)
    mapping.update()


def make_curves():
    rng = random.Random(9)
    fa = scalar_samples(rng, [-1, -0.5, 0, 0.1, 0.2, 0.25, 0.3, 0.4, 0.5, 0.6, 0.7, 0.9, 1, 1.25,
                              1.5, 2, 0.001, 0.999, 0.123, 0.8765], -0.6, 1.6)
    fd = scalar_samples(rng, [1] * 30 + [0, 0.5, -0.5, 1.5], 0, 1)
    va = vector_samples(rng, [[0, 0, 0], [1, 1, 1], [0.5, 0.25, 0.75], [-0.5, 1.5, 0.3],
                              [0.1, 0.9, 0.6], [1.2, -0.2, 0.45]], -0.6, 1.6)
    fd = [1.0 if i < 30 else v for i, v in enumerate(fd)]

    def fbuild(cfg):
        def build(nt, inp):
            n = nt.nodes.new("ShaderNodeFloatCurve")
            setup_mapping(n.mapping, cfg["extend"], {"X": cfg["points"]})
            nt.links.new(inp["fd"], n.inputs["Factor"])
            nt.links.new(inp["fa"], n.inputs["Value"])
            return {"o0": n.outputs[0]}
        return build

    def cbuild(cfg):
        def build(nt, inp):
            n = nt.nodes.new("ShaderNodeRGBCurve")
            setup_mapping(n.mapping, cfg["extend"], cfg["curves"])
            nt.links.new(inp["fd"], n.inputs["Fac"])
            nt.links.new(inp["va"], n.inputs["Color"])
            return {"o0": n.outputs[0]}
        return build

    res = render({"fa": fa, "fd": fd, "va": va},
                 [fbuild(c) for c in FLOAT_CURVES] + [cbuild(c) for c in RGB_CURVES])
    mat, nt = new_material("exact")

    def dump_points(cmap):
        return [{"x": sig7(p.location[0]), "y": sig7(p.location[1]), "handle": p.handle_type}
                for p in cmap.points]

    fcases = []
    for cfg, r in zip(FLOAT_CURVES, res):
        n = nt.nodes.new("ShaderNodeFloatCurve")
        setup_mapping(n.mapping, cfg["extend"], {"X": cfg["points"]})
        m = n.mapping
        m.initialize()
        exact = [m.evaluate(m.curves[0], x) for x in fa]
        fcases.append({"extend": cfg["extend"], "points": dump_points(m.curves[0]),
                       "cycles": out_list(r["o0"][:, 0]), "exact": out_list(exact)})
    ccases = []
    for cfg, r in zip(RGB_CURVES, res[len(FLOAT_CURVES):]):
        n = nt.nodes.new("ShaderNodeRGBCurve")
        setup_mapping(n.mapping, cfg["extend"], cfg["curves"])
        m = n.mapping
        m.initialize()
        curves = {}
        for key, i in CURVE_INDEX.items():
            curves[key] = {"points": dump_points(m.curves[i]),
                           "exact": out_list([m.evaluate(m.curves[i], x) for x in fa])}
        ccases.append({"extend": cfg["extend"], "curves": curves, "cycles": out_list(r["o0"])})
    write("curves", {"inputs": {"value": fa, "factor": fd, "color": va},
                     "float_curves": fcases, "rgb_curves": ccases})


if __name__ == "__main__":
    which = sys.argv[1:] or ["math", "vector_math", "vector_rotate", "mix", "color",
                             "blackbody", "map_range", "ramp", "curves"]
    for name in which:
        {"math": make_math, "vector_math": make_vector_math, "vector_rotate": make_vector_rotate,
         "mix": make_mix, "color": make_color,
         "blackbody": make_blackbody_wavelength, "map_range": make_map_range, "ramp": make_ramp,
         "curves": make_curves}[name]()
