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
    # A reader of another UV set than st reads that primvar per vertex (an Attribute node).
    (at,) = nodes_of(m, "attribute")
    assert at["params"]["name"] == "uvset2"
    assert mp["inputs"]["vector"] == {"node": m["nodes"].index(at), "output": "vector"}
    msgs = r.diagnostics.messages()
    assert not [w for w in msgs if "uvset2" in w], msgs


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


def test_displacement_bumps_the_normal_as_the_equal_normal_map(stage_factory, tmp_path):
    # A displacement ramp h = 0.8 u over the plane (u spans x in [-1, 1]) tilts the normal to
    # (-0.4, 0, 1) normalised: the render equals that of a constant normal map of this tilt,
    # and differs from the flat plane.
    stage, path = new(stage_factory, sun=True, name="disp")
    mat, sh = preview(stage, "/Mat/D", diffuseColor=(0.8, 0.8, 0.8), roughness=0.4)
    ramp = np.repeat(np.linspace(0.0, 0.8, 65, dtype=np.float32)[None, :, None], 4, axis=0)
    file = write_texture(tmp_path / "ramp.exr", np.repeat(ramp, 3, axis=2))
    t = uv_texture(stage, "/Mat/D/Height", file, wrap="clamp")
    connect(sh, "displacement", t, "r", T.Float)
    bind(plane(stage), mat)
    r, img = render(stage, path, spp=8)
    m = r.ir["materials"][0]
    (d,) = nodes_of(m, "displacement")
    assert m["displacement"] == {"node": m["nodes"].index(d), "output": "displacement"}
    n = np.array([-0.4, 0.0, 1.0]) / np.hypot(0.4, 1.0)
    stage2, path2 = _normal_scene(stage_factory, tmp_path, tuple((n + 1) / 2), name="tilt")
    _, ref = render(stage2, path2, spp=8)
    stage3, path3 = _normal_scene(stage_factory, tmp_path, None, with_map=False, name="flat")
    _, flat = render(stage3, path3, spp=8)
    inner = (slice(W // 8, -W // 8), slice(W // 8, -W // 8))
    assert np.abs(ref - flat)[inner].max() > 0.1 * ref.max()
    assert np.allclose(img[inner], ref[inner], atol=0.03 * ref.max()), \
        np.abs(img - ref)[inner].max() / ref.max()


def test_display_color_reader_reads_the_primvar_with_its_fallback(stage_factory):
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
    g = r.ir["materials"][0]
    p = nodes_of(g, "principled")[0]
    a = g["nodes"][p["inputs"]["base_color"]["node"]]
    # The plane has no displayColor: the reader's fallback, as USD defines it.
    assert a["type"] == "attribute" and a["params"] == {"name": "displayColor",
                                                        "fallback": pytest.approx([0.1, 0.6, 0.3, 1])}
    assert "attributes" not in r.ir["meshes"][0]


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


# -- MaterialX math as Blender's exporter writes it ------------------------------------------


def _emissive_mtlx(stage, path, color_node, output="out"):
    """A material whose surface is an ND_uniform_edf of ``color_node``'s ``output``."""
    mat = UsdShade.Material.Define(stage, path)
    edf = _mtlx_node(stage, f"{path}/NodeGraphs/Edf", "ND_uniform_edf")
    edf.CreateInput("color", T.Color3f).ConnectToSource(color_node.ConnectableAPI(), output)
    surf = UsdShade.Shader.Define(stage, f"{path}/Surface")
    surf.CreateIdAttr("ND_surface")
    surf.CreateInput("edf", T.Token).ConnectToSource(edf.ConnectableAPI(), "out")
    surf.CreateOutput("surface", T.Token)
    mat.CreateSurfaceOutput("mtlx").ConnectToSource(surf.ConnectableAPI(), "surface")
    return mat


def _fnode(stage, path, node_id, out_type=T.Float, **inputs):
    """A MaterialX node: inputs are (shader, output) links or (type, value) constants."""
    return _mtlx_node(stage, path, node_id, inputs, out_type=out_type)


def _in(node, src, ty=T.Float):
    """Connects ``node``'s ``in`` to ``src``'s ``out``."""
    node.CreateInput("in", ty).ConnectToSource(src.ConnectableAPI(), "out")
    return node


def _uv_parts(stage, ng, scale):
    """Blender's checker front end: texcoord x scale, modulo 2, each component floored."""
    tc = _fnode(stage, f"{ng}/uv", "ND_texcoord_vector2", T.Float2)
    mul = _fnode(stage, f"{ng}/mul", "ND_multiply_vector2", T.Float2, in1=(tc, "out"),
                 in2=(T.Float2, Gf.Vec2f(*scale)))
    mod = _fnode(stage, f"{ng}/mod", "ND_modulo_vector2", T.Float2, in1=(mul, "out"),
                 in2=(T.Float2, Gf.Vec2f(2, 2)))
    floors = []
    for i in (0, 1):
        ex = _in(_fnode(stage, f"{ng}/ex{i}", "ND_extract_vector2"), mod, T.Float2)
        ex.CreateInput("index", T.Int).Set(i)
        floors.append(_in(_fnode(stage, f"{ng}/floor{i}", "ND_floor_float"), ex))
    return _fnode(stage, f"{ng}/sum", "ND_add_float", in1=(floors[0], "out"),
                  in2=(floors[1], "out"))


CELL_A, CELL_B = (0.9, 0.6, 0.1), (0.1, 0.2, 0.7)


@_have("math", "vector_math", "separate_xyz", "mix")
def test_blender_checker_floors_a_floored_modulo(stage_factory):
    """Blender's Checker as its exporter writes it (ND_modulo_vector2, ND_extract_vector2,
    ND_floor_float, ND_add_float, ND_ifequal_color3), at a negative scale along u, where a
    truncated modulo would give no cell of colour A at all."""
    stage, path = new(stage_factory, name="checker")
    ng = "/Mat/C/NodeGraphs"
    total = _uv_parts(stage, ng, (-4, 4))
    sel = _fnode(stage, f"{ng}/sel", "ND_ifequal_color3", T.Color3f,
                 value1=(total, "out"), value2=(T.Float, 1.0), in1=(T.Color3f, CELL_A),
                 in2=(T.Color3f, CELL_B))
    bind(plane(stage), _emissive_mtlx(stage, "/Mat/C", sel))
    r, img = render(stage, path)
    m = r.ir["materials"][0]
    ops = sorted(n["params"]["operation"] for n in m["nodes"]
                 if n["type"] in ("math", "vector_math"))
    assert ops.count("FLOOR") == 2 and "WRAP" in ops and "MODULO" not in ops, ops
    assert not [w for w in r.diagnostics.messages() if "/Mat/" in w]
    u, v = pixel_uv()
    a, b = -4 * u, 4 * v
    cell = np.floor(np.mod(a, 2)) + np.floor(np.mod(b, 2))
    expect = np.where((cell == 1)[..., None], CELL_A, CELL_B)
    margin = 1.5 * SPAN / W * 4
    ok = ((np.mod(a, 1) > margin) & (np.mod(a, 1) < 1 - margin)
          & (np.mod(b, 1) > margin) & (np.mod(b, 1) < 1 - margin))
    assert ok.sum() > W * W / 4 and (cell[ok] == 1).any() and (cell[ok] != 1).any()
    assert np.allclose(img[ok], expect[ok], atol=0.03), np.abs(img[ok] - expect[ok]).max()


@_have("math", "clamp", "map_range", "separate_xyz", "combine_xyz")
def test_clamp_remap_absval_power_max_per_pixel(stage_factory):
    """r = clamp(u, 0.3, 0.6); g = remap(v, 0.2..0.4 -> 0.1..0.2), unclamped as MaterialX's
    remap; b = max(|u - 0.5|^2, 0.05): rendered as an emission and compared per pixel."""
    stage, path = new(stage_factory, name="ops")
    ng = "/Mat/O/NodeGraphs"
    tc = _fnode(stage, f"{ng}/uv", "ND_texcoord_vector2", T.Float2)
    comps = []
    for i in (0, 1):
        ex = _in(_fnode(stage, f"{ng}/ex{i}", "ND_extract_vector2"), tc, T.Float2)
        ex.CreateInput("index", T.Int).Set(i)
        comps.append(ex)
    u_, v_ = comps

    def unary(name, node_id, src, **consts):
        n = _in(_fnode(stage, f"{ng}/{name}", node_id), src)
        for k, val in consts.items():
            n.CreateInput(k, T.Float).Set(val)
        return n

    r_ = unary("clamp", "ND_clamp_float", u_, low=0.3, high=0.6)
    g_ = unary("remap", "ND_remap_float", v_, inlow=0.2, inhigh=0.4, outlow=0.1, outhigh=0.2)
    d = _fnode(stage, f"{ng}/d", "ND_subtract_float", in1=(u_, "out"), in2=(T.Float, 0.5))
    ab = unary("abs", "ND_absval_float", d)
    pw = _fnode(stage, f"{ng}/pow", "ND_power_float", in1=(ab, "out"), in2=(T.Float, 2.0))
    b_ = _fnode(stage, f"{ng}/max", "ND_max_float", in1=(pw, "out"), in2=(T.Float, 0.05))
    rgb = _fnode(stage, f"{ng}/rgb", "ND_combine3_color3", T.Color3f, in1=(r_, "out"),
                 in2=(g_, "out"), in3=(b_, "out"))
    bind(plane(stage), _emissive_mtlx(stage, "/Mat/O", rgb))
    r, img = render(stage, path)
    m = r.ir["materials"][0]
    (cl,) = nodes_of(m, "clamp")
    assert cl["params"]["clamp_type"] == "MINMAX"
    (mr,) = nodes_of(m, "map_range")
    assert mr["params"]["clamp"] is False and mr["params"]["interpolation_type"] == "LINEAR"
    assert not [w for w in r.diagnostics.messages() if "/Mat/" in w]
    u, v = pixel_uv()
    expect = np.stack([np.clip(u, 0.3, 0.6), 0.1 + (v - 0.2) * 0.5,
                       np.maximum(np.abs(u - 0.5) ** 2, 0.05)], -1)
    assert expect[..., 1].max() > 0.35 and expect[..., 1].min() < 0.1  # beyond the out range
    assert np.allclose(img, expect, atol=0.02), np.abs(img - expect).max()


@pytest.mark.parametrize("node_id, inputs, expect", [
    ("ND_modulo_float", {"in1": -1.0, "in2": 3.0}, 2.0),  # floored, not C's fmod (-1)
    ("ND_floor_float", {"in": -1.5}, -2.0),
    ("ND_ceil_float", {"in": -1.5}, -1.0),
    ("ND_clamp_float", {"in": 1.7, "low": 0.2, "high": 0.9}, 0.9),
    ("ND_remap_float", {"in": 0.5, "inlow": 0.0, "inhigh": 0.25, "outlow": 0.0,
                        "outhigh": 1.0}, 2.0),
    ("ND_power_float", {"in1": 2.0, "in2": 3.0}, 8.0),
    ("ND_min_float", {"in1": 0.4, "in2": 0.3}, 0.3),
    ("ND_sign_float", {"in": -3.0}, -1.0),
    ("ND_absval_float", {"in": -0.25}, 0.25),
    ("ND_invert_float", {"in": 0.25}, 0.75),
    ("ND_sqrt_float", {"in": 0.09}, 0.3),
    ("ND_sin_float", {"in": math.pi / 6}, 0.5),
    ("ND_atan2_float", {"iny": 1.0, "inx": -1.0}, 0.75 * math.pi),
])
def test_constant_math_is_folded(stage_factory, node_id, inputs, expect):
    """Constant operands are folded into the consumer's input, with MaterialX's meaning."""
    stage, path = new(stage_factory, name="fold")
    n = _fnode(stage, "/Mat/F/NodeGraphs/op", node_id,
               **{k: (T.Float, v) for k, v in inputs.items()})
    mat = UsdShade.Material.Define(stage, "/Mat/F")
    g = UsdShade.NodeGraph(stage.GetPrimAtPath("/Mat/F/NodeGraphs"))
    g.CreateOutput("m_out", T.Float).ConnectToSource(n.ConnectableAPI(), "out")
    pbr = UsdShade.Shader.Define(stage, "/Mat/F/PBR")
    pbr.CreateIdAttr("ND_open_pbr_surface_surfaceshader")
    pbr.CreateInput("geometry_opacity", T.Float).Set(0.5)  # a graph
    pbr.CreateInput("base_metalness", T.Float).ConnectToSource(g.ConnectableAPI(), "m_out")
    pbr.CreateOutput("surface", T.Token)
    mat.CreateSurfaceOutput("mtlx").ConnectToSource(pbr.ConnectableAPI(), "surface")
    bind(plane(stage), mat)
    r = import_stage(stage, path)
    (p,) = nodes_of(r.ir["materials"][0], "principled")
    assert p["inputs"]["metallic"] == pytest.approx(expect, abs=1e-6)
    assert not [w for w in r.diagnostics.messages() if "/Mat/" in w]


def test_vector_modulo_is_floored():
    g = shading_graph.Graph("g", available=frozenset({"vector_math"}))
    assert g.vmath("WRAP", [-1.0, 5.0, 2.5], [3.0, 3.0, 3.0], 0.0) == pytest.approx([2, 2, 2.5])
    out = g.vmath("WRAP", {"node": 0, "output": "uv"}, [2.0, 2.0, 2.0], 0.0)
    assert g.nodes[out["node"]]["params"]["operation"] == "WRAP"


# -- Blender's Principled BSDF inside a Mix Shader: ND_layer_bsdf stacks ------------------------


def _blender_principled(stage, ng, base_color, metallic=0.0, roughness=0.5, ior=1.5,
                        level=0.5, transmission=0.0, coat=0.0, coat_roughness=0.03):
    """The pbrlib network Blender 5.0's exporter writes for a Principled BSDF whose BSDF goes
    into a Mix Shader; returns its top ND_layer_bsdf. ``base_color``: a colour or a (node,
    output) link."""
    def node(name, node_id, out_type=T.Token, **inputs):
        return _mtlx_node(stage, f"{ng}/{name}", node_id, inputs, out_type=out_type)

    def ra(name, r):
        return node(name, "ND_roughness_anisotropy", T.Float2, roughness=(T.Float, r),
                    anisotropy=(T.Float, 0.0))

    def color(shader, name):
        if isinstance(base_color, tuple) and isinstance(base_color[0], UsdShade.Shader):
            shader.CreateInput(name, T.Color3f).ConnectToSource(
                base_color[0].ConnectableAPI(), base_color[1])
        else:
            shader.CreateInput(name, T.Color3f).Set(base_color)
        return shader

    coat_bsdf = node("coat", "ND_dielectric_bsdf", weight=(T.Float, coat),
                     tint=(T.Color3f, (1, 1, 1)), ior=(T.Float, 1.5),
                     scatter_mode=(T.String, "R"), roughness=(ra("coat_ra", coat_roughness), "out"))
    art = node("art", "ND_artistic_ior", T.Color3f, reflectivity=(T.Color3f, (0.8, 0.8, 0.8)),
               edge_color=(T.Color3f, (0.4, 0.4, 0.4)))
    main_ra = ra("main_ra", roughness)
    metal = node("metal", "ND_conductor_bsdf", ior=(art, "out"), extinction=(art, "out"),
                 roughness=(main_ra, "out"))
    spec = node("spec", "ND_dielectric_bsdf", weight=(T.Float, level),
                tint=(T.Color3f, (1, 1, 1)), ior=(T.Float, ior), scatter_mode=(T.String, "R"),
                roughness=(main_ra, "out"))
    trans = color(node("trans", "ND_dielectric_bsdf", ior=(T.Float, ior),
                       roughness=(ra("trans_ra", min(1.0, 2 * roughness)), "out")), "tint")
    sss = node("sss", "ND_subsurface_bsdf", color=(T.Color3f, (0.8, 0.8, 0.8)))
    sheen = node("sheen", "ND_sheen_bsdf", weight=(T.Float, 0.0), color=(T.Color3f, (1, 1, 1)),
                 roughness=(T.Float, 0.5))
    diffuse = color(node("diffuse", "ND_oren_nayar_diffuse_bsdf", weight=(T.Float, 1.0),
                         roughness=(T.Float, 0.0)), "color")
    sss_mix = node("sss_mix", "ND_mix_bsdf", bg=(diffuse, "out"), fg=(sss, "out"),
                   mix=(T.Float, 0.0))
    sheen_layer = node("sheen_layer", "ND_layer_bsdf", top=(sheen, "out"), base=(sss_mix, "out"))
    trans_mix = node("trans_mix", "ND_mix_bsdf", bg=(sheen_layer, "out"), fg=(trans, "out"),
                     mix=(T.Float, transmission))
    spec_layer = node("spec_layer", "ND_layer_bsdf", top=(spec, "out"), base=(trans_mix, "out"))
    metal_mix = node("metal_mix", "ND_mix_bsdf", bg=(spec_layer, "out"), fg=(metal, "out"),
                     mix=(T.Float, metallic))
    film_layer = node("film_layer", "ND_layer_bsdf", base=(metal_mix, "out"))
    att = node("att", "ND_multiply_bsdfC", in1=(film_layer, "out"), in2=(T.Color3f, (1, 1, 1)))
    return node("top", "ND_layer_bsdf", top=(coat_bsdf, "out"), base=(att, "out"))


def test_blender_principled_layers_in_a_mix_shader_are_principled_nodes(stage_factory):
    stage, path = new(stage_factory, sun=True, name="layers")
    ng = "/Mat/L/NodeGraphs"
    tc = _fnode(stage, f"{ng}/uv", "ND_texcoord_vector2", T.Float2)
    rgb = _fnode(stage, f"{ng}/rgb", "ND_combine3_color3", T.Color3f, in1=(T.Float, 0.2),
                 in2=(tc, "out"), in3=(T.Float, 0.1))
    metal = _blender_principled(stage, f"{ng}/A", (0.8, 0.8, 0.82), metallic=1.0,
                                roughness=0.25)
    rough = _blender_principled(stage, f"{ng}/B", (rgb, "out"), roughness=0.9, ior=1.45,
                                level=0.3, transmission=0.1, coat=0.5, coat_roughness=0.2)
    mix = _mtlx_node(stage, f"{ng}/mix", "ND_mix_bsdf",
                     {"bg": (metal, "out"), "fg": (rough, "out"), "mix": (T.Float, 0.3)})
    bind(plane(stage), _mtlx_material(stage, "/Mat/L", mix))
    r = import_stage(stage, path)
    m = r.ir["materials"][0]
    assert m["type"] == "graph"
    assert not [w for w in r.diagnostics.messages() if "layer" in w], r.diagnostics.messages()
    (mx,) = nodes_of(m, "mix_shader")
    assert mx["inputs"]["fac"] == pytest.approx(0.3)
    a = m["nodes"][mx["inputs"]["shader1"]["node"]]
    b = m["nodes"][mx["inputs"]["shader2"]["node"]]
    assert a["type"] == b["type"] == "principled"
    ia, ib = a["inputs"], b["inputs"]
    assert ia["base_color"] == pytest.approx([0.8, 0.8, 0.82])
    assert (ia["metallic"], ia["roughness"], ia["specular_ior_level"]) == pytest.approx(
        (1.0, 0.25, 0.5))
    assert ia["coat_weight"] == 0.0 and ia["transmission_weight"] == 0.0
    assert m["nodes"][ib["base_color"]["node"]]["type"] == "combine_xyz"  # the link
    assert (ib["metallic"], ib["roughness"], ib["ior"], ib["specular_ior_level"],
            ib["transmission_weight"], ib["coat_weight"], ib["coat_roughness"]) == pytest.approx(
        (0.0, 0.9, 1.45, 0.3, 0.1, 0.5, 0.2))
    if {"principled", "mix_shader", "combine_xyz", "tex_coord"} <= shading_graph.available_nodes():
        photonmap.Scene.from_dict(r.ir)  # the core compiles it


def test_other_layering_is_warned_with_its_path(stage_factory):
    stage, path = new(stage_factory, name="layer2")
    ng = "/Mat/L/NodeGraphs"
    coat = _mtlx_node(stage, f"{ng}/coat", "ND_dielectric_bsdf",
                      {"weight": (T.Float, 1.0), "scatter_mode": (T.String, "R")})
    layer = _mtlx_node(stage, f"{ng}/layer", "ND_layer_bsdf",
                       {"top": (coat, "out"), "base": (_diffuse(stage, f"{ng}/d", (0.5, 0.5, 0.5)),
                                                       "out")})
    mix = _mtlx_node(stage, f"{ng}/mix", "ND_mix_bsdf",
                     {"bg": (layer, "out"), "fg": (_diffuse(stage, f"{ng}/e", (0.1, 0.1, 0.1)),
                                                   "out"), "mix": (T.Float, 0.5)})
    bind(plane(stage), _mtlx_material(stage, "/Mat/L", mix))
    r = import_stage(stage, path)
    assert not nodes_of(r.ir["materials"][0], "principled")
    assert [w for w in r.diagnostics.messages() if f"{ng}/layer" in w and "ND_layer_bsdf" in w]


def test_heighttonormal_is_warned_and_the_surface_normal_kept(stage_factory, tmp_path):
    """Blender's Bump as its exporter writes it: ND_heighttonormal_vector3 into
    ND_normalmap_float (scale: the Bump's distance) into OpenPBR's geometry_normal."""
    stage, path = new(stage_factory, name="bump")
    ng = "/Mat/B/NodeGraphs"
    file = write_texture(tmp_path / "h.exr", TEX)
    img = _fnode(stage, f"{ng}/img", "ND_image_float")
    img.CreateInput("file", T.Asset).Set(file)
    h2n = _in(_fnode(stage, f"{ng}/h2n", "ND_heighttonormal_vector3", T.Float3,
                     scale=(T.Float, 1.0)), img)
    nm = _in(_fnode(stage, f"{ng}/bump", "ND_normalmap_float", T.Float3, scale=(T.Float, 0.2)),
             h2n, T.Float3)
    mat = UsdShade.Material.Define(stage, "/Mat/B")
    g = UsdShade.NodeGraph(stage.GetPrimAtPath(ng))
    g.CreateOutput("n_out", T.Float3).ConnectToSource(nm.ConnectableAPI(), "out")
    pbr = UsdShade.Shader.Define(stage, "/Mat/B/PBR")
    pbr.CreateIdAttr("ND_open_pbr_surface_surfaceshader")
    pbr.CreateInput("geometry_normal", T.Float3).ConnectToSource(g.ConnectableAPI(), "n_out")
    pbr.CreateOutput("surface", T.Token)
    mat.CreateSurfaceOutput("mtlx").ConnectToSource(pbr.ConnectableAPI(), "surface")
    bind(plane(stage), mat)
    r = import_stage(stage, path)
    m = r.ir["materials"][0]
    (p,) = nodes_of(m, "principled")
    assert "normal" not in p["inputs"] and not nodes_of(m, "normal_map")
    msgs = r.diagnostics.messages()
    assert [w for w in msgs if f"{ng}/h2n" in w and "ND_heighttonormal_vector3" in w], msgs


def test_black_edfs_emit_nothing(stage_factory):
    """Blender writes an EDF beside every Principled BSDF, black without emission."""
    stage, path = new(stage_factory, name="edf")
    ng = "/Mat/E/NodeGraphs"
    e1 = _mtlx_node(stage, f"{ng}/e1", "ND_uniform_edf", {"color": (T.Color3f, (0, 0, 0))})
    e2 = _mtlx_node(stage, f"{ng}/e2", "ND_uniform_edf", {"color": (T.Color3f, (0, 0, 0))})
    me = _mtlx_node(stage, f"{ng}/me", "ND_mix_edf", {"bg": (e1, "out"), "fg": (e2, "out"),
                                                       "mix": (T.Float, 0.5)})
    mat = _mtlx_material(stage, "/Mat/E", _diffuse(stage, f"{ng}/d", (0.5, 0.5, 0.5)))
    surf = UsdShade.Shader(stage.GetPrimAtPath("/Mat/E/Surface"))
    surf.CreateInput("edf", T.Token).ConnectToSource(me.ConnectableAPI(), "out")
    bind(plane(stage), mat)
    m = import_stage(stage, path).ir["materials"][0]
    assert m["type"] == "graph" and not nodes_of(m, "emission")
    assert not shading_graph.emits(m)


def test_hsvadjust_is_the_hue_saturation_value_node(stage_factory):
    """MaterialX hsvadjust (Blender writes it for a Hue/Saturation/Value node): the hue turned by
    amount.x, saturation and value scaled by amount.y and amount.z."""
    import colorsys

    stage, path = new(stage_factory, name="hsv")
    ng = "/Mat/H/NodeGraphs"
    base, amount = (0.6, 0.3, 0.2), (0.1, 0.5, 0.8)
    hsv = _fnode(stage, f"{ng}/hsv", "ND_hsvadjust_color3", T.Color3f,
                 amount=(T.Float3, Gf.Vec3f(*amount)), **{"in": (T.Color3f, base)})
    bind(plane(stage), _emissive_mtlx(stage, "/Mat/H", hsv))
    r, img = render(stage, path)
    assert not [w for w in r.diagnostics.messages() if "/Mat/" in w]
    h, s, v = colorsys.rgb_to_hsv(*base)
    expect = colorsys.hsv_to_rgb((h + amount[0]) % 1.0, s * amount[1], v * amount[2])
    assert np.abs(np.array(expect) - base).max() > 0.1
    assert np.allclose(img, expect, atol=0.01), (img.mean(axis=(0, 1)), expect)
