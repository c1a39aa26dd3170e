"""The beauty's alpha through the add-on against Cycles: Film > Transparent, a Holdout mixed
into a material, a full Holdout, objects held out (Object > Visibility > Holdout, and a
holdout collection) and a leaf card cut out by a checker in Principled Alpha.
Both renderers write Combined as RGBA to an EXR, as a user saves a render; the alphas are
compared per 8x8 block and per pixel.

The tolerance comes from the noise of a pixel's alpha: each camera sample is transparent or
not, so a pixel of alpha a after N samples has a variance of at most a(1 - a)/N (less with
stratified samples); a block's is the mean of its pixels'. A block fails beyond four standard
errors of the difference plus 0.005 (filters and edges), and the mean of the pixels' squared
z-scores must stay below 2. A Holdout mix factor 0.05 off either way fails.
"""

from __future__ import annotations

import math

import bpy
import numpy as np
import pytest

SPP = 256
W, H = 64, 48


def _material(name, build):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    out = nt.nodes["Material Output"]
    build(nt, nt.nodes["Principled BSDF"], out)
    return m


def _mesh_object(name, op, mat, **kw):
    op(**kw)
    ob = bpy.context.active_object
    ob.name = name
    ob.data.materials.append(mat)
    return ob


def build(holdout_fac: float = 0.5):
    """A floor, a sphere half held out (Mix Shader of the Principled and a Holdout), a cube
    wholly held out and a leaf card cut out by a checker, in a grey world, on a transparent
    film: built with operators and Blender's default nodes, as an artist builds it."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.resolution_x, sc.render.resolution_y = W, H
    sc.render.resolution_percentage = 100
    sc.render.film_transparent = True
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.4, 0.45, 0.5, 1)
    sc.world = world

    floor = _material("Floor", lambda nt, p, out: None)
    _mesh_object("Floor", bpy.ops.mesh.primitive_plane_add, floor, size=6, location=(0, 0, 0))

    def half_held(nt, p, out):
        mix = nt.nodes.new("ShaderNodeMixShader")
        hold = nt.nodes.new("ShaderNodeHoldout")
        mix.inputs["Fac"].default_value = holdout_fac
        nt.links.new(p.outputs["BSDF"], mix.inputs[1])
        nt.links.new(hold.outputs["Holdout"], mix.inputs[2])
        nt.links.new(mix.outputs["Shader"], out.inputs["Surface"])

    _mesh_object("Sphere", bpy.ops.mesh.primitive_uv_sphere_add,
                 _material("HalfHeld", half_held), radius=0.8, location=(-0.6, 0, 0.8))
    bpy.ops.object.shade_smooth()

    def held(nt, p, out):
        hold = nt.nodes.new("ShaderNodeHoldout")
        nt.links.new(hold.outputs["Holdout"], out.inputs["Surface"])

    _mesh_object("Cube", bpy.ops.mesh.primitive_cube_add, _material("Held", held),
                 size=0.6, location=(1.0, -0.4, 0.3))

    def leaf(nt, p, out):
        checker = nt.nodes.new("ShaderNodeTexChecker")
        checker.inputs["Scale"].default_value = 3.0
        checker.inputs["Color1"].default_value = (1, 1, 1, 1)
        checker.inputs["Color2"].default_value = (0, 0, 0, 1)
        p.inputs["Base Color"].default_value = (0.2, 0.6, 0.1, 1)
        nt.links.new(checker.outputs["Fac"], p.inputs["Alpha"])

    card = _mesh_object("Leaf", bpy.ops.mesh.primitive_plane_add, _material("Leaf", leaf),
                        size=1.2, location=(0.7, 0.4, 1.2), rotation=(math.radians(80), 0, 0))
    card.rotation_euler[2] = math.radians(-10)

    # Held out by the object's Visibility > Holdout, and by a holdout collection.
    cone = _mesh_object("Cone", bpy.ops.mesh.primitive_cone_add, floor, radius1=0.3,
                        depth=0.7, location=(-1.9, -0.8, 0.35))
    cone.is_holdout = True
    masked = bpy.data.collections.new("Masked")
    sc.collection.children.link(masked)
    cyl = _mesh_object("Cylinder", bpy.ops.mesh.primitive_cylinder_add, floor, radius=0.25,
                       depth=0.6, location=(0.1, -1.2, 0.3))
    for c in list(cyl.users_collection):
        c.objects.unlink(cyl)
    masked.objects.link(cyl)
    bpy.context.view_layer.layer_collection.children["Masked"].holdout = True

    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    sc.collection.objects.link(cam)
    cam.location = (0, -6, 3)
    cam.rotation_euler = (math.radians(68), 0, 0)
    sc.camera = cam
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.data.energy = 3.0
    sun.rotation_euler = (math.radians(40), math.radians(20), 0)
    sc.collection.objects.link(sun)
    return sc


def _alpha_of_render(sc, path) -> np.ndarray:
    """Renders ``sc`` to an RGBA float EXR at ``path``, as a user saves a render; its alpha."""
    import OpenImageIO as oiio

    sc.render.filepath = str(path)
    im = sc.render.image_settings
    im.media_type = "IMAGE"
    im.file_format = "OPEN_EXR"
    im.color_mode = "RGBA"
    im.color_depth = "32"
    bpy.ops.render.render(write_still=True)
    px = oiio.ImageBuf(str(path)).get_pixels(oiio.FLOAT)
    assert px.shape[2] == 4, px.shape
    return px[..., 3].astype(np.float64)


def _cycles(sc):
    sc.render.engine = "CYCLES"
    c = sc.cycles
    c.device = "CPU"
    c.samples = SPP
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.max_bounces = 2
    c.seed = 3
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0


def _photonmap(sc, enable):
    enable()
    sc.render.engine = "PHOTONMAP"
    pm = sc.photonmap
    pm.quality = "draft"
    pm.spp = SPP
    pm.adaptive_sampling = False
    pm.filter = "box"
    pm.seed = 3


def _verdict(ours: np.ndarray, ref: np.ndarray) -> tuple[float, float]:
    """(largest block |difference| over its tolerance, mean squared pixel z-score)."""
    a = np.clip(ref, 0, 1)
    var = 2 * np.maximum(a * (1 - a), 1e-4) / SPP
    blocks = lambda x: x.reshape(H // 8, 8, W // 8, 8).mean((1, 3))  # noqa: E731
    d = np.abs(blocks(ours) - blocks(ref))
    tol = 4 * np.sqrt(blocks(var) / 64) + 0.005
    z2 = (ours - ref) ** 2 / var
    return float((d / tol).max()), float(z2.mean())


@pytest.fixture(scope="module", autouse=True)
def fresh_blender_after(addon):
    """Leaves Blender as the other test files expect it: factory settings, the add-on on."""
    yield
    from conftest import enable

    bpy.ops.wm.read_factory_settings()
    enable()


@pytest.fixture(scope="module")
def cycles_alpha(addon, tmp_path_factory):
    sc = build()
    _cycles(sc)
    return _alpha_of_render(sc, tmp_path_factory.mktemp("cycles") / "alpha.exr")


def test_alpha_matches_cycles(addon, cycles_alpha, tmp_path):
    from conftest import enable

    ref = cycles_alpha
    # The scene holds every case: background, held-out and cut-out pixels, opaque ones.
    assert (ref < 0.02).mean() > 0.2 and (ref > 0.98).mean() > 0.2
    assert ((ref > 0.4) & (ref < 0.6)).mean() > 0.03
    sc = build()
    _photonmap(sc, enable)
    ours = _alpha_of_render(sc, tmp_path / "ours.exr")
    block, pixel = _verdict(ours, ref)
    assert block <= 1.0 and pixel < 2.0, (block, pixel)


@pytest.mark.parametrize("fac", [0.45, 0.55])
def test_alpha_comparison_catches_a_holdout_off_by_5_percent(addon, cycles_alpha, tmp_path,
                                                             fac):
    from conftest import enable

    sc = build(holdout_fac=fac)
    _photonmap(sc, enable)
    ours = _alpha_of_render(sc, tmp_path / "ours.exr")
    block, _ = _verdict(ours, cycles_alpha)
    assert block > 1.0, block
