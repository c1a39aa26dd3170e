"""UsdShade networks the flat IR materials cannot express, imported as shading graphs: the IR
the importer writes, and renders checked against what the network means (per pixel where the
image is noise-free, on means where it is not)."""
import math

import numpy as np
import pytest
from conftest import add_camera, add_mesh, import_stage
from pxr import Gf, Sdf, UsdGeom, UsdLux, UsdShade

import photonmap
from usd_delegate import shading_graph

T = Sdf.ValueTypeNames
W = 24  # image width and height
CAM_Z = 2.0  # the camera looks down -Z at the plane z = 0; it sees x, y in [-SPAN, SPAN]
SPAN = CAM_Z * 18.0 / 50.0


def _have(*types):
    missing = [t for t in types if t not in shading_graph.available_nodes()]
    return pytest.mark.skipif(bool(missing), reason=f"the core lacks graph nodes {missing}")


def write_texture(path, pixels):
    import OpenImageIO as oiio

    px = np.asarray(pixels, dtype=np.float32)
    h, w, c = px.shape
    spec = oiio.ImageSpec(w, h, c, oiio.FLOAT)
    out = oiio.ImageOutput.create(str(path))
    out.open(str(path), spec)
    out.write_image(px)
    out.close()
    return str(path)


def quadrants(a, b, c, d, n=32):
    """An n x n RGB texture: top-left a, top-right b, bottom-left c, bottom-right d (in the
    image, row 0 at the top; UV v = 1 at the top)."""
    px = np.zeros((n, n, 3), np.float32)
    h = n // 2
    px[:h, :h], px[:h, h:], px[h:, :h], px[h:, h:] = a, b, c, d
    return px


def plane(stage, path="/Plane", size=1.0, z=0.0, uv=True):
    s = size
    m = add_mesh(stage, path, [(-s, -s, z), (s, -s, z), (s, s, z), (-s, s, z)], [4], [0, 1, 2, 3])
    if uv:
        pv = UsdGeom.PrimvarsAPI(m).CreatePrimvar("st", T.TexCoord2fArray, UsdGeom.Tokens.vertex)
        pv.Set([(0, 0), (1, 0), (1, 1), (0, 1)])
    return m


def preview(stage, path, **inputs):
    mat = UsdShade.Material.Define(stage, path)
    sh = UsdShade.Shader.Define(stage, f"{path}/Surface")
    sh.CreateIdAttr("UsdPreviewSurface")
    types = {"diffuseColor": T.Color3f, "emissiveColor": T.Color3f, "normal": T.Normal3f}
    for k, v in inputs.items():
        sh.CreateInput(k, types.get(k, T.Float)).Set(v)
    mat.CreateSurfaceOutput().ConnectToSource(sh.ConnectableAPI(), "surface")
    return mat, sh


def uv_texture(stage, path, file, scale=None, bias=None, st=None, wrap="repeat"):
    t = UsdShade.Shader.Define(stage, path)
    t.CreateIdAttr("UsdUVTexture")
    t.CreateInput("file", T.Asset).Set(file)
    t.CreateInput("sourceColorSpace", T.Token).Set("raw")
    t.CreateInput("wrapS", T.Token).Set(wrap)
    t.CreateInput("wrapT", T.Token).Set(wrap)
    if scale is not None:
        t.CreateInput("scale", T.Float4).Set(Gf.Vec4f(*scale))
    if bias is not None:
        t.CreateInput("bias", T.Float4).Set(Gf.Vec4f(*bias))
    for o, ty in (("rgb", T.Float3), ("r", T.Float), ("g", T.Float), ("b", T.Float),
                  ("a", T.Float)):
        t.CreateOutput(o, ty)
    if st is not None:
        t.CreateInput("st", T.Float2).ConnectToSource(st.ConnectableAPI(), "result")
    return t


def st_reader(stage, path, varname="st"):
    r = UsdShade.Shader.Define(stage, path)
    r.CreateIdAttr("UsdPrimvarReader_float2")
    r.CreateInput("varname", T.Token).Set(varname)
    r.CreateOutput("result", T.Float2)
    return r


def transform2d(stage, path, src, scale=(1, 1), rotation=0.0, translation=(0, 0)):
    t = UsdShade.Shader.Define(stage, path)
    t.CreateIdAttr("UsdTransform2d")
    t.CreateInput("in", T.Float2).ConnectToSource(src.ConnectableAPI(), "result")
    t.CreateInput("scale", T.Float2).Set(Gf.Vec2f(*scale))
    t.CreateInput("rotation", T.Float).Set(rotation)
    t.CreateInput("translation", T.Float2).Set(Gf.Vec2f(*translation))
    t.CreateOutput("result", T.Float2)
    return t


def connect(shader, name, src, output, ty=T.Color3f):
    shader.CreateInput(name, ty).ConnectToSource(src.ConnectableAPI(), output)


def bind(prim, mat):
    UsdShade.MaterialBindingAPI.Apply(prim.GetPrim()).Bind(mat)


def render(stage, path, **kw):
    r = import_stage(stage, path, width=W)
    out = photonmap.render(photonmap.Scene.from_dict(r.ir), quality="draft", seed=3, **kw)
    return r, np.asarray(out["combined"])[..., :3]


def new(stage_factory, sun=False, name="s"):
    stage, path = stage_factory(f"{name}.usda")
    add_camera(stage, z=CAM_Z)
    if sun:
        L = UsdLux.DistantLight.Define(stage, "/Sun")
        L.CreateIntensityAttr(3.0)
        L.CreateAngleAttr(0.5)
        UsdGeom.XformCommonAPI(L).SetRotate((30, 20, 0))
    return stage, path


def pixel_uv(scale=1.0):
    """The plane's UV at each pixel centre (size-1 plane: x in [-1, 1] -> u in [0, 1])."""
    c = (np.arange(W) + 0.5) / W * 2 - 1
    x = c[None, :] * SPAN
    y = -c[:, None] * SPAN
    u = (x + 1) / 2 * scale
    v = (y + 1) / 2 * scale
    return np.broadcast_to(u, (W, W)), np.broadcast_to(v, (W, W))


def lookup(tex, u, v):
    """Nearest texel of a repeating texture (row 0 at v = 1)."""
    n = tex.shape[0]
    j = np.floor(np.mod(u, 1.0) * n).astype(int) % n
    i = np.floor((1 - np.mod(v, 1.0)) * n).astype(int) % n
    return tex[i, j]


def far_from_texel_edges(u, v, n, block, scale=1.0, margin=1.5):
    """Pixels whose footprint (``margin`` pixels) stays inside one block of ``block`` texels
    (``u``, ``v`` as scaled by ``scale``)."""
    px = SPAN / W * scale * (n / block)  # a pixel's size in blocks
    fu = np.mod(u * n / block, 1.0)
    fv = np.mod(v * n / block, 1.0)
    m = margin * px
    return (fu > m) & (fu < 1 - m) & (fv > m) & (fv < 1 - m)


def nodes_of(m, kind):
    return [n for n in m["nodes"] if n["type"] == kind]


# -- UsdPreviewSurface -----------------------------------------------------------------------


def _emissive_texture_scene(stage_factory, tmp_path, tex, scale=(1, 1), bias=None,
                            tex_scale=None, varname="st"):
    stage, path = new(stage_factory)
    file = write_texture(tmp_path / "q.exr", tex)
    mat, sh = preview(stage, "/Mat/E", diffuseColor=(0, 0, 0), roughness=1.0)
    r = st_reader(stage, "/Mat/E/St", varname)
    xf = transform2d(stage, "/Mat/E/Xf", r, scale=scale)
    t = uv_texture(stage, "/Mat/E/Tex", file, scale=tex_scale, bias=bias, st=xf)
    connect(sh, "emissiveColor", t, "rgb")
    bind(plane(stage), mat)
    return stage, path


TEX = quadrants((0.9, 0.1, 0.1), (0.1, 0.8, 0.2), (0.2, 0.3, 0.9), (0.7, 0.7, 0.1))


@pytest.mark.parametrize("bias", [None, (0.25, 0.0, 0.5, 0.0)])
def test_uv_texture_reproduces_the_texture_per_pixel(stage_factory, tmp_path, bias):
    stage, path = _emissive_texture_scene(stage_factory, tmp_path, TEX,
                                          tex_scale=(0.5, 1.0, 0.5, 1.0), bias=bias)
    r, img = render(stage, path)
    m = r.ir["materials"][0]
    assert m["type"] == "graph"
    assert len(nodes_of(m, "image_texture")) == 1 and len(nodes_of(m, "principled")) == 1
    tex = r.ir["textures"][0]
    data = np.asarray(tex["data"]).reshape(tex["height"], tex["width"], tex["channels"])
    b = np.array(bias or (0, 0, 0, 0))[:3]
    assert np.allclose(data, TEX * [0.5, 1.0, 0.5] + b, atol=1e-6)  # scale and bias baked
    u, v = pixel_uv()
    expect = lookup(TEX, u, v) * [0.5, 1.0, 0.5] + b
    ok = far_from_texel_edges(u, v, 32, 16)
    assert ok.sum() > W * W / 2
    assert np.allclose(img[ok], expect[ok], atol=0.03), np.abs(img[ok] - expect[ok]).max()


def test_transform2d_scale_2_halves_the_period(stage_factory, tmp_path):
    stage, path = _emissive_texture_scene(stage_factory, tmp_path, TEX, scale=(2, 2))
    r, img = render(stage, path)
    m = r.ir["materials"][0]
    (mp,) = nodes_of(m, "mapping")
    assert mp["inputs"]["scale"] == [2.0, 2.0, 1.0]
    u, v = pixel_uv(scale=2.0)
    expect = lookup(TEX, u, v)
    ok = far_from_texel_edges(u, v, 32, 16, scale=2.0)
    assert ok.sum() > W * W / 3
    assert np.allclose(img[ok], expect[ok], atol=0.03), np.abs(img[ok] - expect[ok]).max()
    # Against the untransformed lookup the image differs.
    plain = lookup(TEX, *pixel_uv())
    assert np.abs(img[ok] - plain[ok]).max() > 0.3


def test_transform2d_rotation_and_translation_in_the_ir(stage_factory, tmp_path):
    stage, path = new(stage_factory)
    file = write_texture(tmp_path / "q.exr", TEX)
    mat, sh = preview(stage, "/Mat/E")
    xf = transform2d(stage, "/Mat/E/Xf", st_reader(stage, "/Mat/E/St", "uvset2"),
                     scale=(3, 2), rotation=90.0, translation=(0.25, 0.5))
    connect(sh, "diffuseColor", uv_texture(stage, "/Mat/E/Tex", file, st=xf), "rgb")
    bind(plane(stage), mat)
    r = import_stage(stage, path)
    m = r.ir["materials"][0]
    (mp,) = nodes_of(m, "mapping")
    assert mp["params"]["vector_type"] == "POINT"
    assert mp["inputs"]["location"] == [0.25, 0.5, 0.0]
    assert mp["inputs"]["rotation"] == pytest.approx([0, 0, math.pi / 2])
    assert mp["inputs"]["scale"] == [3.0, 2.0, 1.0]
    msgs = r.diagnostics.messages()
    assert [w for w in msgs if "/Mat/E/St" in w and "uvset2" in w], msgs


def _layers(stage_factory, front_inputs, front_links=None, back=(0.0, 0.0, 1.0)):
    """An emissive red plane in front of an emissive blue one (no lights)."""
    stage, path = new(stage_factory)
    bmat, _ = preview(stage, "/Mat/Back", diffuseColor=(0, 0, 0), emissiveColor=back)
    bind(plane(stage, "/Back", size=3.0, z=-0.5, uv=False), bmat)
    fmat, fsh = preview(stage, "/Mat/Front", diffuseColor=(0, 0, 0), emissiveColor=(1, 0, 0),
                        **front_inputs)
    if front_links:
        front_links(stage, fsh)
    bind(plane(stage, "/Front"), fmat)
    return stage, path


def test_opacity_without_threshold_is_partial_coverage(stage_factory):
    stage, path = _layers(stage_factory, {"opacity": 0.25})
    r, img = render(stage, path, spp=64)
    m = r.ir["materials"][1]
    assert m["type"] == "graph"
    (p,) = nodes_of(m, "principled")
    assert p["inputs"]["alpha"] == 0.25 and "transmission_weight" not in p["inputs"]
    mean = img.reshape(-1, 3).mean(axis=0)
    assert mean[0] == pytest.approx(0.25, abs=0.03) and mean[2] == pytest.approx(0.75, abs=0.03)


def _threshold_scene(stage_factory, tmp_path):
    # Opacity from a texture's r: left half 0.3, right half 0.8; threshold 0.5.
    tex = quadrants((0.3,) * 3, (0.8,) * 3, (0.3,) * 3, (0.8,) * 3)
    file = write_texture(tmp_path / "op.exr", tex)

    def links(stage, sh):
        t = uv_texture(stage, "/Mat/Front/Op", file)
        connect(sh, "opacity", t, "r", T.Float)

    return _layers(stage_factory, {"opacityThreshold": 0.5}, links)


def _core_nodes(monkeypatch, add=(), remove=()):
    nodes = (set(shading_graph.available_nodes()) | set(add)) - set(remove)
    monkeypatch.setattr(shading_graph, "_AVAILABLE", frozenset(nodes))


def test_opacity_threshold_is_a_comparison_in_the_graph(stage_factory, tmp_path, monkeypatch):
    _core_nodes(monkeypatch, add=["math"])
    stage, path = _threshold_scene(stage_factory, tmp_path)
    m = import_stage(stage, path).ir["materials"][1]
    nodes = m["nodes"]
    alpha = nodes_of(m, "principled")[0]["inputs"]["alpha"]
    sub = nodes[alpha["node"]]  # 1 - (opacity < threshold)
    assert sub["type"] == "math" and sub["params"]["operation"] == "SUBTRACT"
    assert sub["inputs"]["value"] == 1.0
    lt = nodes[sub["inputs"]["value_001"]["node"]]
    assert lt["params"]["operation"] == "LESS_THAN" and lt["inputs"]["value_001"] == 0.5
    sep = nodes[lt["inputs"]["value"]["node"]]  # the texture's r
    assert sep["type"] == "separate_xyz" and lt["inputs"]["value"]["output"] == "x"
    assert nodes[sep["inputs"]["vector"]["node"]]["type"] == "image_texture"


def test_a_node_type_the_core_lacks_is_warned_and_not_emitted(stage_factory, tmp_path,
                                                              monkeypatch):
    _core_nodes(monkeypatch, remove=["math"])
    stage, path = _threshold_scene(stage_factory, tmp_path)
    r = import_stage(stage, path)
    m = r.ir["materials"][1]
    assert not nodes_of(m, "math")
    alpha = nodes_of(m, "principled")[0]["inputs"]["alpha"]
    assert m["nodes"][alpha["node"]]["type"] == "separate_xyz"  # opacity as coverage
    msgs = r.diagnostics.messages()
    assert [w for w in msgs if "/Mat/Front/Surface" in w and "`math`" in w], msgs


@_have("math")
def test_opacity_threshold_cuts_holes(stage_factory, tmp_path):
    stage, path = _threshold_scene(stage_factory, tmp_path)
    r, img = render(stage, path, spp=16)
    u, v = pixel_uv()
    left = far_from_texel_edges(u, v, 32, 16) & (u < 0.5)
    right = far_from_texel_edges(u, v, 32, 16) & (u > 0.5)
    assert left.sum() > 50 and right.sum() > 50
    assert np.allclose(img[left], [0, 0, 1], atol=0.02)  # holes: the back plane
    assert np.allclose(img[right], [1, 0, 0], atol=0.02)  # solid


def test_constant_opacity_threshold_is_folded(stage_factory):
    stage, path = _layers(stage_factory, {"opacity": 0.4, "opacityThreshold": 0.5})
    m = import_stage(stage, path).ir["materials"][1]
    assert nodes_of(m, "principled")[0]["inputs"]["alpha"] == 0.0
    assert not nodes_of(m, "math")


def _normal_scene(stage_factory, tmp_path, normal_texel, with_map=True, bias=(-1, -1, -1, 0),
                  name="s"):
    stage, path = new(stage_factory, sun=True, name=name)
    mat, sh = preview(stage, "/Mat/N", diffuseColor=(0.8, 0.8, 0.8), roughness=0.4)
    if with_map:
        file = write_texture(tmp_path / "n.exr", np.full((4, 4, 3), normal_texel, np.float32))
        t = uv_texture(stage, "/Mat/N/Nrm", file, scale=(2, 2, 2, 1), bias=bias)
        connect(sh, "normal", t, "rgb", T.Normal3f)
    bind(plane(stage), mat)
    return stage, path


def test_flat_normal_map_renders_as_no_normal_map(stage_factory, tmp_path):
    stage, path = _normal_scene(stage_factory, tmp_path, (0.5, 0.5, 1.0))
    r, img = render(stage, path, spp=8)
    m = r.ir["materials"][0]
    (nm,) = nodes_of(m, "normal_map")
    assert nm["params"]["space"] == "TANGENT"
    assert nodes_of(m, "principled")[0]["inputs"]["normal"] == {"node": m["nodes"].index(nm),
                                                                "output": "normal"}
    stage2, path2 = _normal_scene(stage_factory, tmp_path, None, with_map=False, name="ref")
    _, ref = render(stage2, path2, spp=8)
    assert ref.mean() > 0.05
    assert np.allclose(img, ref, atol=0.03 * ref.max()), np.abs(img - ref).max()


def test_tilted_normal_map_changes_the_shading(stage_factory, tmp_path):
    # (0.8, 0.5, 0.8) -> a normal tilted towards +u: the lit plane's brightness changes.
    stage, path = _normal_scene(stage_factory, tmp_path, (0.8, 0.5, 0.8))
    _, img = render(stage, path, spp=8)
    stage2, path2 = _normal_scene(stage_factory, tmp_path, None, with_map=False, name="ref")
    _, ref = render(stage2, path2, spp=8)
    assert np.abs(img - ref).max() > 0.1 * ref.max()


def test_display_color_reader_warns_and_uses_its_fallback(stage_factory):
    stage, path = new(stage_factory, sun=True)
    mat, sh = preview(stage, "/Mat/D", opacity=0.5)
    rd = UsdShade.Shader.Define(stage, "/Mat/D/Color")
    rd.CreateIdAttr("UsdPrimvarReader_float3")
    rd.CreateInput("varname", T.Token).Set("displayColor")
    rd.CreateInput("fallback", T.Float3).Set((0.1, 0.6, 0.3))
    rd.CreateOutput("result", T.Float3)
    connect(sh, "diffuseColor", rd, "result")
    bind(plane(stage), mat)
    r = import_stage(stage, path)
    p = nodes_of(r.ir["materials"][0], "principled")[0]
    assert p["inputs"]["base_color"] == pytest.approx([0.1, 0.6, 0.3])
    assert [w for w in r.diagnostics.messages() if "/Mat/D/Color" in w and "displayColor" in w]


# -- MaterialX ---------------------------------------------------------------------------------


def _mtlx_node(stage, path, node_id, inputs=None, out_type=T.Token):
    n = UsdShade.Shader.Define(stage, path)
    n.CreateIdAttr(node_id)
    for k, v in (inputs or {}).items():
        if isinstance(v, tuple) and len(v) == 2 and isinstance(v[0], UsdShade.Shader):
            n.CreateInput(k, out_type).ConnectToSource(v[0].ConnectableAPI(), v[1])
        else:
            ty, val = v
            n.CreateInput(k, ty).Set(val)
    n.CreateOutput("out", out_type)
    return n


def _mtlx_material(stage, path, shader):
    mat = UsdShade.Material.Define(stage, path)
    g = UsdShade.NodeGraph.Define(stage, f"{path}/NodeGraphs")
    g.CreateOutput("surface_out", T.Token).ConnectToSource(shader.ConnectableAPI(), "out")
    surf = UsdShade.Shader.Define(stage, f"{path}/Surface")
    surf.CreateIdAttr("ND_surface")
    surf.CreateInput("bsdf", T.Token).ConnectToSource(g.ConnectableAPI(), "surface_out")
    surf.CreateOutput("surface", T.Token)
    mat.CreateSurfaceOutput("mtlx").ConnectToSource(surf.ConnectableAPI(), "surface")
    return mat


def _diffuse(stage, path, color):
    return _mtlx_node(stage, path, "ND_oren_nayar_diffuse_bsdf",
                      {"color": (T.Color3f, color), "roughness": (T.Float, 0.0)})


def _mix_render(stage_factory, which, mix=0.3):
    stage, path = new(stage_factory, sun=True, name=which)
    ng = "/Mat/M/NodeGraphs"
    red = _diffuse(stage, f"{ng}/Red", (0.9, 0.2, 0.1))
    blue = _diffuse(stage, f"{ng}/Blue", (0.1, 0.3, 0.8))
    if which == "mix":
        node = _mtlx_node(stage, f"{ng}/Mix", "ND_mix_bsdf",
                          {"fg": (red, "out"), "bg": (blue, "out"), "mix": (T.Float, mix)})
    else:
        node = red if which == "red" else blue
    bind(plane(stage), _mtlx_material(stage, "/Mat/M", node))
    return render(stage, path, spp=8)


def test_mix_bsdf_is_the_weighted_mean_of_its_two_bsdfs(stage_factory):
    r, mixed = _mix_render(stage_factory, "mix", 0.3)
    m = r.ir["materials"][0]
    (mx,) = nodes_of(m, "mix_shader")
    assert mx["inputs"]["fac"] == pytest.approx(0.3)
    s1 = m["nodes"][mx["inputs"]["shader1"]["node"]]
    assert s1["type"] == "diffuse" and s1["inputs"]["color"] == pytest.approx([0.1, 0.3, 0.8])
    _, red = _mix_render(stage_factory, "red")
    _, blue = _mix_render(stage_factory, "blue")
    expect = 0.3 * red + 0.7 * blue
    assert expect.mean() > 0.05
    assert np.allclose(mixed, expect, atol=0.03 * expect.max()), np.abs(mixed - expect).max()


def test_blender_style_network_ifequal_multiply_image(stage_factory, tmp_path, monkeypatch):
    """An image multiplied by a constant and chosen by ND_ifequal, into OpenPBR's base_color,
    as Blender's exporter writes Mix and Math nodes."""
    have = {"mix", "math", "vector_math"} <= shading_graph.available_nodes()
    _core_nodes(monkeypatch, add=["mix", "math", "vector_math"])
    stage, path = new(stage_factory)
    file = write_texture(tmp_path / "q.exr", TEX)
    ng = "/Mat/B/NodeGraphs"
    tc = _mtlx_node(stage, f"{ng}/uv", "ND_texcoord_vector2", {"index": (T.Int, 0)})
    img = _mtlx_node(stage, f"{ng}/img", "ND_image_color4", {"texcoord": (tc, "out")})
    img.GetInput("file").Set(file) if img.GetInput("file") else img.CreateInput("file", T.Asset).Set(file)
    conv = _mtlx_node(stage, f"{ng}/conv", "ND_convert_color4_color3", {"in": (img, "out")})
    mul = _mtlx_node(stage, f"{ng}/mul", "ND_multiply_color3FA",
                     {"in1": (conv, "out"), "in2": (T.Float, 2.0)})
    red = _mtlx_node(stage, f"{ng}/red", "ND_separate3_color3", {"in": (conv, "out")})
    red.CreateOutput("outr", T.Float)
    sel = _mtlx_node(stage, f"{ng}/sel", "ND_ifequal_color3",
                     {"value1": (red, "outr"), "value2": (T.Float, 0.9), "in1": (mul, "out"),
                      "in2": (T.Color3f, (0, 0, 0))})
    noise = _mtlx_node(stage, f"{ng}/noise", "ND_noise3d_float", {"amplitude": (T.Float, 1.0)})
    mat = UsdShade.Material.Define(stage, "/Mat/B")
    g = UsdShade.NodeGraph(stage.GetPrimAtPath(ng))
    g.CreateOutput("base_out", T.Color3f).ConnectToSource(sel.ConnectableAPI(), "out")
    g.CreateOutput("rough_out", T.Float).ConnectToSource(noise.ConnectableAPI(), "out")
    pbr = UsdShade.Shader.Define(stage, "/Mat/B/PBR")
    pbr.CreateIdAttr("ND_open_pbr_surface_surfaceshader")
    pbr.CreateInput("base_color", T.Color3f).Set((0.3, 0.3, 0.3))
    pbr.CreateInput("base_color", T.Color3f).ConnectToSource(g.ConnectableAPI(), "base_out")
    pbr.CreateInput("specular_roughness", T.Float).Set(0.7)
    pbr.CreateInput("specular_roughness", T.Float).ConnectToSource(g.ConnectableAPI(), "rough_out")
    pbr.CreateOutput("surface", T.Token)
    mat.CreateSurfaceOutput("mtlx").ConnectToSource(pbr.ConnectableAPI(), "surface")
    bind(plane(stage), mat)
    r = import_stage(stage, path)
    m = r.ir["materials"][0]
    assert m["type"] == "graph"
    nodes = m["nodes"]
    p = nodes_of(m, "principled")[0]
    assert p["inputs"]["roughness"] == pytest.approx(0.7)  # the noise is warned, the input's value kept
    assert [w for w in r.diagnostics.messages() if f"{ng}/noise" in w and "ND_noise3d_float" in w]
    # base_color = mix(factor = (red == 0.9), a = black, b = image x 2)
    mix = nodes[p["inputs"]["base_color"]["node"]]
    assert mix["type"] == "mix" and mix["params"]["data_type"] == "RGBA"
    cmp = nodes[mix["inputs"]["factor"]["node"]]  # red == 0.9
    assert cmp["type"] == "math" and cmp["params"]["operation"] == "COMPARE"
    assert cmp["inputs"]["value_001"] == pytest.approx(0.9)
    assert nodes[cmp["inputs"]["value"]["node"]]["type"] == "separate_xyz"
    assert mix["inputs"]["a"] == [0.0, 0.0, 0.0]
    mul = nodes[mix["inputs"]["b"]["node"]]
    assert mul["type"] == "vector_math" and mul["params"]["operation"] == "MULTIPLY"
    assert mul["inputs"]["vector_001"] == 2.0
    img = nodes[mul["inputs"]["vector"]["node"]]
    assert img["type"] == "image_texture" and nodes[img["inputs"]["vector"]["node"]]["type"] == "tex_coord"
    if have:
        photonmap.Scene.from_dict(r.ir)  # the core compiles it
