"""Reference values for the procedural texture nodes, produced by Blender itself.

Run with the bpy virtual environment:

    .venv-bpy/bin/python src/materials/graph/tex/make_references.py

For every texture node and a set of parameter combinations, a Geometry Nodes
modifier evaluates the node at 64 fixed pseudo-random points of a vertex-only
mesh (Vector = point position, W = a per-point float attribute), stores each
output as a point attribute, and the evaluated mesh is read back.  Geometry
Nodes evaluates these nodes with Blender's BLI noise/texture code, which is
kept in sync with Cycles' SVM kernels.

Two nodes differ between the two evaluators: the Brick texture's mortar
smoothing (Cycles clamps its smoothstep to [0, 1], Geometry Nodes does not)
and the Magic texture for coordinates beyond 2 pi (Cycles reduces them modulo
2 pi first, Geometry Nodes does not).  For those, references are also rendered
with Cycles: a grid of quads, one per pixel, each carrying its sample point as
a constant attribute that feeds the texture's Vector input of an emission
shader, seen by an orthographic camera (1 sample, 0.01 px box filter).

Output: testdata/<texture>.json next to this script.  Floats are rounded to 7
significant digits (inputs to 9 so that they round-trip as f32).
"""

import json
import math
import os
import random
import tempfile

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "testdata")


def make_points():
    """64 points over roughly [-3, 3]^3 plus W in [-3, 3]; some sit on or
    next to integer lattice lines (also after the default scale of 5)."""
    rng = random.Random(20250101)
    pts = []
    for i in range(64):
        p = [rng.uniform(-3.0, 3.0) for _ in range(4)]
        if i % 8 == 1:
            p[0] = float(rng.randint(-3, 3))  # on a lattice plane
        if i % 8 == 3:
            p[1] = rng.randint(-3, 3) + 1e-4  # just above one
        if i % 8 == 5:
            p[2] = rng.randint(-3, 3) - 1e-4  # just below one
        if i % 8 == 7:
            p[3] = rng.randint(-15, 15) / 5.0  # integer after scale 5
        if i == 0:
            p = [0.0, 0.0, 0.0, 0.0]
        pts.append([float(np.float32(v)) for v in p])
    return pts


POINTS = make_points()


def g(v, digits=7):
    v = float(v)
    if math.isnan(v) or math.isinf(v):
        return None
    return float(f"{v:.{digits}g}")


def setup_mesh():
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    mesh = bpy.data.meshes.new("pts")
    mesh.from_pydata([p[:3] for p in POINTS], [], [])
    attr = mesh.attributes.new("w", "FLOAT", "POINT")
    attr.data.foreach_set("value", [p[3] for p in POINTS])
    ob = bpy.data.objects.new("pts", mesh)
    bpy.context.scene.collection.objects.link(ob)
    return ob


def read_positions(ob):
    deps = bpy.context.evaluated_depsgraph_get()
    me = ob.evaluated_get(deps).data
    co = np.zeros(len(me.vertices) * 3, dtype=np.float32)
    me.attributes["position"].data.foreach_get("vector", co)
    w = np.zeros(len(me.vertices), dtype=np.float32)
    me.attributes["w"].data.foreach_get("value", w)
    return co.reshape(-1, 3), w


def sock(coll, name):
    """The socket called `name`, or None (unavailable sockets may be absent)."""
    for s in coll:
        if s.identifier == name or s.name == name:
            return s
    return None


def evaluate(ob, node_type, props, inputs, outputs):
    """Evaluate one texture node at the mesh's points.

    props: node properties; inputs: socket name -> default value;
    outputs: socket name -> 'FLOAT' | 'FLOAT_VECTOR' | 'FLOAT_COLOR'."""
    for m in list(ob.modifiers):
        ob.modifiers.remove(m)
    for ng in list(bpy.data.node_groups):
        bpy.data.node_groups.remove(ng)
    ng = bpy.data.node_groups.new("tex", "GeometryNodeTree")
    ng.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    ng.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    nodes, links = ng.nodes, ng.links
    gin = nodes.new("NodeGroupInput")
    gout = nodes.new("NodeGroupOutput")
    tex = nodes.new(node_type)
    for k, v in props.items():
        setattr(tex, k, v)
    pos = nodes.new("GeometryNodeInputPosition")
    vec = pos.outputs[0]
    inputs = dict(inputs)
    vector_scale = inputs.pop("_vector_scale", None)
    if vector_scale is not None:
        # Vector = position * _vector_scale, to reach larger coordinates.
        vm = nodes.new("ShaderNodeVectorMath")
        vm.operation = "SCALE"
        links.new(vec, vm.inputs[0])
        vm.inputs["Scale"].default_value = vector_scale
        vec = vm.outputs["Vector"]
    if sock(tex.inputs, "Vector") is not None:
        links.new(vec, sock(tex.inputs, "Vector"))
    if sock(tex.inputs, "W") is not None:
        wattr = nodes.new("GeometryNodeInputNamedAttribute")
        wattr.data_type = "FLOAT"
        wattr.inputs["Name"].default_value = "w"
        links.new(wattr.outputs["Attribute"], sock(tex.inputs, "W"))
    for k, v in inputs.items():
        sock(tex.inputs, k).default_value = v
    geo = gin.outputs[0]
    for name, dtype in outputs.items():
        st = nodes.new("GeometryNodeStoreNamedAttribute")
        st.data_type = dtype
        st.domain = "POINT"
        st.inputs["Name"].default_value = "out_" + name
        links.new(geo, st.inputs["Geometry"])
        links.new(sock(tex.outputs, name), st.inputs["Value"])
        geo = st.outputs["Geometry"]
    links.new(geo, gout.inputs[0])
    mod = ob.modifiers.new("tex", "NODES")
    mod.node_group = ng

    deps = bpy.context.evaluated_depsgraph_get()
    me = ob.evaluated_get(deps).data
    n = len(me.vertices)
    result = {}
    for name, dtype in outputs.items():
        a = me.attributes["out_" + name]
        if dtype == "FLOAT":
            buf = np.zeros(n, dtype=np.float32)
            a.data.foreach_get("value", buf)
            result[name] = [g(v) for v in buf]
        elif dtype == "FLOAT_VECTOR":
            buf = np.zeros(n * 3, dtype=np.float32)
            a.data.foreach_get("vector", buf)
            result[name] = [[g(v) for v in row] for row in buf.reshape(-1, 3)]
        else:
            buf = np.zeros(n * 4, dtype=np.float32)
            a.data.foreach_get("color", buf)
            result[name] = [[g(v) for v in row[:3]] for row in buf.reshape(-1, 4)]
    return result


def write(name, cases, points=None):
    os.makedirs(OUT, exist_ok=True)
    data = {
        "source": f"Blender {bpy.app.version_string}",
        "points": [[g(v, 9) for v in p] for p in (points or POINTS)],
        "cases": cases,
    }
    path = os.path.join(OUT, name + ".json")
    with open(path, "w") as f:
        json.dump(data, f, separators=(",", ":"))
        f.write("\n")
    print(f"{path}: {len(cases)} cases, {os.path.getsize(path)} bytes")


def case(ob, node_type, props, inputs, outputs):
    out = evaluate(ob, node_type, props, inputs, outputs)
    return {"props": props, "inputs": inputs, "outputs": out}


def noise_cases(ob):
    cases = []
    outs = {"Factor": "FLOAT", "Color": "FLOAT_COLOR"}
    base = {"Scale": 1.3, "Detail": 2.5, "Roughness": 0.6, "Lacunarity": 2.2,
            "Offset": 0.3, "Gain": 1.1, "Distortion": 0.0}
    for dim in ["1D", "2D", "3D", "4D"]:
        for nt in ["FBM", "MULTIFRACTAL", "HYBRID_MULTIFRACTAL",
                   "RIDGED_MULTIFRACTAL", "HETERO_TERRAIN"]:
            inp = dict(base)
            if nt == "RIDGED_MULTIFRACTAL":
                inp["Offset"] = 1.0
            cases.append(case(ob, "ShaderNodeTexNoise",
                              {"noise_dimensions": dim, "noise_type": nt, "normalize": True},
                              inp, outs))
        # FBM without normalisation, fractional detail.
        cases.append(case(ob, "ShaderNodeTexNoise",
                          {"noise_dimensions": dim, "noise_type": "FBM", "normalize": False},
                          dict(base), outs))
        # FBM without normalisation, with distortion, integral detail.
        inp = dict(base, Distortion=0.8, Detail=3.0, Scale=5.0)
        cases.append(case(ob, "ShaderNodeTexNoise",
                          {"noise_dimensions": dim, "noise_type": "FBM", "normalize": False},
                          inp, outs))
        inp = dict(base, Distortion=-1.5, Detail=0.0, Roughness=0.5, Lacunarity=2.0)
        cases.append(case(ob, "ShaderNodeTexNoise",
                          {"noise_dimensions": dim, "noise_type": "FBM", "normalize": True},
                          inp, outs))
    # Defaults of the node, 3D.
    cases.append(case(ob, "ShaderNodeTexNoise",
                      {"noise_dimensions": "3D", "noise_type": "FBM", "normalize": True},
                      {"Scale": 5.0, "Detail": 2.0, "Roughness": 0.5, "Lacunarity": 2.0,
                       "Offset": 0.0, "Gain": 1.0, "Distortion": 0.0}, outs))
    # Clamped detail (above 15) and negative roughness.
    cases.append(case(ob, "ShaderNodeTexNoise",
                      {"noise_dimensions": "3D", "noise_type": "MULTIFRACTAL", "normalize": False},
                      {"Scale": 0.7, "Detail": 20.0, "Roughness": -0.5, "Lacunarity": 1.7,
                       "Offset": 0.0, "Gain": 1.0, "Distortion": 0.0}, outs))
    write("noise_texture", cases)


def voronoi_cases(ob):
    cases = []
    base = {"Scale": 1.7, "Detail": 0.0, "Roughness": 0.5, "Lacunarity": 2.0,
            "Smoothness": 0.6, "Exponent": 1.5, "Randomness": 0.9}

    def outs_for(dim, feature):
        if feature == "DISTANCE_TO_EDGE":
            return {"Distance": "FLOAT"}
        if feature == "N_SPHERE_RADIUS":
            return {"Radius": "FLOAT"}
        o = {"Distance": "FLOAT", "Color": "FLOAT_COLOR"}
        if dim != "1D":
            o["Position"] = "FLOAT_VECTOR"
        if dim in ("1D", "4D"):
            o["W"] = "FLOAT"
        return o

    def add(dim, feature, metric, normalize, **kw):
        inp = dict(base, **kw)
        cases.append(case(ob, "ShaderNodeTexVoronoi",
                          {"voronoi_dimensions": dim, "feature": feature,
                           "distance": metric, "normalize": normalize},
                          inp, outs_for(dim, feature)))

    for dim in ["1D", "2D", "3D", "4D"]:
        for feature in ["F1", "F2", "SMOOTH_F1", "DISTANCE_TO_EDGE", "N_SPHERE_RADIUS"]:
            add(dim, feature, "EUCLIDEAN", False)
        # Fractal with a fractional detail, normalised.
        add(dim, "F1", "EUCLIDEAN", True, Detail=2.5, Roughness=0.6, Lacunarity=2.3)
        add(dim, "DISTANCE_TO_EDGE", "EUCLIDEAN", True, Detail=1.5, Lacunarity=2.1)
    for dim in ["2D", "3D"]:
        for metric in ["MANHATTAN", "CHEBYCHEV", "MINKOWSKI"]:
            add(dim, "F1", metric, False)
            add(dim, "F2", metric, True, Detail=1.5)
            add(dim, "SMOOTH_F1", metric, False, Smoothness=1.0)
        add(dim, "SMOOTH_F1", "EUCLIDEAN", True, Detail=2.5, Roughness=0.7, Smoothness=0.3)
        add(dim, "F1", "MINKOWSKI", False, Exponent=0.5, Randomness=1.0, Scale=5.0)
        add(dim, "SMOOTH_F1", "EUCLIDEAN", False, Smoothness=0.0)
    write("voronoi", cases)


def white_noise_cases(ob):
    cases = []
    for dim in ["1D", "2D", "3D", "4D"]:
        cases.append(case(ob, "ShaderNodeTexWhiteNoise", {"noise_dimensions": dim}, {},
                          {"Value": "FLOAT", "Color": "FLOAT_COLOR"}))
    write("white_noise", cases)


def checker_cases(ob):
    cases = []
    for scale in [1.0, 2.5, 5.0]:
        cases.append(case(ob, "ShaderNodeTexChecker", {},
                          {"Scale": scale, "Color1": (0.9, 0.3, 0.1, 1.0),
                           "Color2": (0.05, 0.2, 0.7, 1.0)},
                          {"Factor": "FLOAT", "Color": "FLOAT_COLOR"}))
    write("checker", cases)


def gradient_cases(ob):
    cases = []
    for gt in ["LINEAR", "QUADRATIC", "EASING", "DIAGONAL", "SPHERICAL",
               "QUADRATIC_SPHERE", "RADIAL"]:
        cases.append(case(ob, "ShaderNodeTexGradient", {"gradient_type": gt}, {},
                          {"Factor": "FLOAT", "Color": "FLOAT_COLOR"}))
    write("gradient", cases)


def wave_cases(ob):
    cases = []
    base = {"Scale": 0.9, "Distortion": 0.0, "Detail": 2.0, "Detail Scale": 1.0,
            "Detail Roughness": 0.5, "Phase Offset": 0.0}
    outs = {"Factor": "FLOAT", "Color": "FLOAT_COLOR"}
    for d in ["X", "Y", "Z", "DIAGONAL"]:
        for prof in ["SIN", "SAW", "TRI"]:
            cases.append(case(ob, "ShaderNodeTexWave",
                              {"wave_type": "BANDS", "bands_direction": d, "wave_profile": prof},
                              dict(base, **{"Phase Offset": 0.7}), outs))
    for d in ["X", "Y", "Z", "SPHERICAL"]:
        cases.append(case(ob, "ShaderNodeTexWave",
                          {"wave_type": "RINGS", "rings_direction": d, "wave_profile": "SIN"},
                          base, outs))
    for prof in ["SIN", "SAW", "TRI"]:
        cases.append(case(ob, "ShaderNodeTexWave",
                          {"wave_type": "RINGS", "rings_direction": "SPHERICAL",
                           "wave_profile": prof},
                          dict(base, **{"Distortion": 3.0, "Detail": 2.5, "Detail Scale": 1.7,
                                        "Detail Roughness": 0.6, "Phase Offset": -1.2}), outs))
    cases.append(case(ob, "ShaderNodeTexWave",
                      {"wave_type": "BANDS", "bands_direction": "DIAGONAL", "wave_profile": "TRI"},
                      dict(base, **{"Distortion": -2.0, "Detail": 0.0, "Scale": 2.0}), outs))
    write("wave", cases)


def magic_cases(ob):
    cases = []
    outs = {"Factor": "FLOAT", "Color": "FLOAT_COLOR"}
    for depth in range(0, 11):
        cases.append(case(ob, "ShaderNodeTexMagic", {"turbulence_depth": depth},
                          {"Scale": 1.3, "Distortion": 1.4}, outs))
    cases.append(case(ob, "ShaderNodeTexMagic", {"turbulence_depth": 3},
                      {"Scale": 5.0, "Distortion": 0.0}, outs))

    write("magic", cases)


BRICK_CASES = [
    ({"offset": 0.5, "offset_frequency": 2, "squash": 1.0, "squash_frequency": 2},
     {"Scale": 1.0, "Mortar Size": 0.02, "Mortar Smooth": 1.0, "Bias": 0.0,
      "Brick Width": 0.5, "Row Height": 0.25}),
    ({"offset": 0.3, "offset_frequency": 3, "squash": 0.6, "squash_frequency": 2},
     {"Scale": 1.5, "Mortar Size": 0.1, "Mortar Smooth": 0.0, "Bias": 0.2,
      "Brick Width": 0.7, "Row Height": 0.3}),
    ({"offset": 0.5, "offset_frequency": 2, "squash": 1.0, "squash_frequency": 2},
     {"Scale": 1.0, "Mortar Size": 0.15, "Mortar Smooth": 1.0, "Bias": -0.3,
      "Brick Width": 0.45, "Row Height": 0.35}),
    ({"offset": 0.5, "offset_frequency": 2, "squash": 1.0, "squash_frequency": 2},
     {"Scale": 1.0, "Mortar Size": 0.15, "Mortar Smooth": 0.4, "Bias": 0.1,
      "Brick Width": 0.45, "Row Height": 0.35}),
]
BRICK_COLORS = {"Color1": (0.8, 0.5, 0.3, 1.0), "Color2": (0.1, 0.3, 0.6, 1.0),
                "Mortar": (0.05, 0.9, 0.2, 1.0)}


def brick_cases(ob):
    """Geometry Nodes references, restricted to mortar smoothing where the
    clamped and unclamped smoothstep agree (Mortar Smooth 0 or 1)."""
    cases = []
    outs = {"Factor": "FLOAT", "Color": "FLOAT_COLOR"}
    for props, inp in BRICK_CASES:
        if inp["Mortar Smooth"] not in (0.0, 1.0):
            continue
        cases.append(case(ob, "ShaderNodeTexBrick", props, dict(inp, **BRICK_COLORS), outs))
    write("brick", cases)


def cycles_render(name, node_type, case_list, pts):
    """Cycles renders of a texture node: one pixel per sample point.

    case_list: (props, inputs) pairs; every output in ("Factor", "Color")."""
    res = int(round(math.sqrt(len(pts))))
    assert res * res == len(pts)
    scene = bpy.context.scene
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    verts, faces = [], []
    for j in range(res):
        for i in range(res):
            k = len(verts)
            # Quad covering pixel (i, j) in a [0, res] x [0, res] plane.
            verts += [(i, j, 0), (i + 1, j, 0), (i + 1, j + 1, 0), (i, j + 1, 0)]
            faces.append((k, k + 1, k + 2, k + 3))
    mesh = bpy.data.meshes.new("grid")
    mesh.from_pydata(verts, [], faces)
    attr = mesh.attributes.new("pt", "FLOAT_VECTOR", "POINT")
    flat = []
    for p in pts:
        flat += p[:3] * 4
    attr.data.foreach_set("vector", flat)
    ob = bpy.data.objects.new("grid", mesh)
    scene.collection.objects.link(ob)
    cam_data = bpy.data.cameras.new("cam")
    cam_data.type = "ORTHO"
    cam_data.ortho_scale = res
    cam = bpy.data.objects.new("cam", cam_data)
    cam.location = (res / 2, res / 2, 10.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 1
    scene.cycles.use_denoising = False
    scene.cycles.pixel_filter_type = "BOX"
    scene.cycles.filter_width = 0.01
    scene.render.resolution_x = res
    scene.render.resolution_y = res
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    if scene.world is None:
        scene.world = bpy.data.worlds.new("w")
    scene.world.use_nodes = True
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0

    mat = bpy.data.materials.new("m")
    mat.use_nodes = True
    ob.data.materials.append(mat)
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = 1.0
    attr_node = nt.nodes.new("ShaderNodeAttribute")
    attr_node.attribute_name = "pt"
    tex = nt.nodes.new(node_type)
    nt.links.new(attr_node.outputs["Vector"], tex.inputs["Vector"])
    nt.links.new(em.outputs[0], out.inputs["Surface"])

    tmp = tempfile.mkdtemp()
    cases = []
    for props, inp in case_list:
        for k, v in props.items():
            setattr(tex, k, v)
        for k, v in inp.items():
            sock(tex.inputs, k).default_value = v
        result = {}
        for out_name in ("Factor", "Color"):
            nt.links.new(sock(tex.outputs, out_name), em.inputs["Color"])
            path = os.path.join(tmp, f"{name}_{out_name}.exr")
            scene.render.filepath = path
            bpy.ops.render.render(write_still=True)
            img = bpy.data.images.load(path)
            px = np.array(img.pixels[:], dtype=np.float32).reshape(res, res, 4)
            bpy.data.images.remove(img)
            # Image rows run bottom to top, like the quads' j.
            vals = [px[j, i, :3] for j in range(res) for i in range(res)]
            if out_name == "Factor":
                result[out_name] = [g(v[0]) for v in vals]
            else:
                result[out_name] = [[g(c) for c in v] for v in vals]
        cases.append({"props": props, "inputs": inp, "outputs": result})
    write(name + "_cycles", cases, points=pts)


def random_points(n, seed, lo, hi, z_lo, z_hi):
    rng = random.Random(seed)
    return [[float(np.float32(rng.uniform(lo, hi))), float(np.float32(rng.uniform(lo, hi))),
             float(np.float32(rng.uniform(z_lo, z_hi))), 0.0] for _ in range(n)]


def brick_cycles_cases():
    cycles_render("brick", "ShaderNodeTexBrick",
                  [(props, dict(inp, **BRICK_COLORS)) for props, inp in BRICK_CASES],
                  random_points(256, 7, -3.0, 3.0, -1.0, 1.0))


def magic_cycles_cases():
    """Cycles reduces Magic's coordinates modulo 2 pi, Geometry Nodes does
    not: check coordinates beyond 2 pi against Cycles."""
    cycles_render("magic", "ShaderNodeTexMagic",
                  [({"turbulence_depth": 2}, {"Scale": 0.3, "Distortion": 1.0}),
                   ({"turbulence_depth": 5}, {"Scale": 1.1, "Distortion": 2.0})],
                  random_points(256, 11, -12.0, 12.0, -12.0, 12.0))


def main():
    ob = setup_mesh()
    co, w = read_positions(ob)
    assert np.allclose(co, np.array(POINTS, dtype=np.float32)[:, :3])
    assert np.allclose(w, np.array(POINTS, dtype=np.float32)[:, 3])
    noise_cases(ob)
    voronoi_cases(ob)
    white_noise_cases(ob)
    checker_cases(ob)
    gradient_cases(ob)
    wave_cases(ob)
    magic_cases(ob)
    brick_cases(ob)
    brick_cycles_cases()
    magic_cycles_cases()


if __name__ == "__main__":
    main()
