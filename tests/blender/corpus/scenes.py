"""The Cycles parity corpus: small scenes (160x120) built the way Blender users build them.

Each scene is made with the operators of the Add menu (``bpy.ops.mesh.primitive_*_add``,
``bpy.ops.object.light_add``, ``bpy.ops.object.camera_add``) and, unless the scene is about
another material, Blender's default Principled BSDF (a new material's node tree: Specular IOR
Level 0.5, Roughness 0.5; only the Base Color is changed). Each is named for one concern and
kept a small room or box so that both renderers converge.

Lights made by ``light_add`` are invisible to camera rays in Blender 5.0 (``visible_camera``
False). Where seeing the light is the concern, the scene turns camera visibility on, as a user
would (Object > Visibility > Camera); the scene's description says so.

Used by make_references.py (Cycles references, USD export), test_corpus.py and
scripts/corpus_compare.py. ``SCENES`` maps each name to a :class:`CorpusScene`.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Callable

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
TEXTURES = os.path.join(HERE, "textures")
WIDTH, HEIGHT = 160, 120


@dataclass
class CorpusScene:
    name: str
    build: Callable[[], "bpy.types.Scene"]
    description: str
    #: Why Blender's USD exporter does not carry the scene (None: it does).
    no_usd: str | None = None
    tags: tuple = field(default_factory=tuple)


SCENES: dict[str, CorpusScene] = {}


def scene(name, description, no_usd=None, tags=()):
    def deco(fn):
        SCENES[name] = CorpusScene(name, fn, description, no_usd, tuple(tags))
        return fn
    return deco


NO_USD_VOLUME = ("Blender's USD exporter does not write a mesh's volume material (the fog "
                 "cube is exported as an opaque mesh)")

# -- building blocks ----------------------------------------------------------------------


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.resolution_x = WIDTH
    sc.render.resolution_y = HEIGHT
    sc.render.resolution_percentage = 100
    sc.world = None  # black: the empty factory scene has no world
    return sc


def active():
    return bpy.context.active_object


def principled(name, color=(0.8, 0.8, 0.8), **inputs):
    """A new material: Blender's default Principled BSDF, Base Color and ``inputs`` (socket
    names with underscores for spaces) changed."""
    m = bpy.data.materials.new(name)
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    for k, v in inputs.items():
        sock = bsdf.inputs[k.replace("_", " ")]
        sock.default_value = (*v, 1.0) if isinstance(v, tuple) and len(v) == 3 else v
    return m


def shader_material(name, node, **inputs):
    """A new material whose Principled BSDF is replaced by the shader node ``node``."""
    m = bpy.data.materials.new(name)
    nt = m.node_tree
    nt.nodes.remove(nt.nodes["Principled BSDF"])
    out = nt.nodes["Material Output"]
    s = nt.nodes.new(node)
    for k, v in inputs.items():
        sock = s.inputs[k.replace("_", " ")]
        sock.default_value = (*v, 1.0) if isinstance(v, tuple) and len(v) == 3 else v
    nt.links.new(s.outputs[0], out.inputs["Surface"])
    return m


def fog_material(name="Fog", density=1.0, color=(0.8, 0.8, 0.8), anisotropy=0.0):
    """Surface: none; Volume: Principled Volume (as the Add > Shader menu gives it)."""
    m = bpy.data.materials.new(name)
    nt = m.node_tree
    nt.nodes.remove(nt.nodes["Principled BSDF"])
    out = nt.nodes["Material Output"]
    v = nt.nodes.new("ShaderNodeVolumePrincipled")
    v.inputs["Density"].default_value = density
    v.inputs["Color"].default_value = (*color, 1.0)
    v.inputs["Anisotropy"].default_value = anisotropy
    nt.links.new(v.outputs["Volume"], out.inputs["Volume"])
    return m


def assign(ob, mat):
    ob.data.materials.clear()
    ob.data.materials.append(mat)
    return ob


def plane(name, location, rotation_deg, size, mat, scale=(1, 1, 1)):
    bpy.ops.mesh.primitive_plane_add(size=size, location=location,
                                     rotation=[math.radians(a) for a in rotation_deg],
                                     scale=scale)
    ob = active()
    ob.name = name
    return assign(ob, mat)


def cube(name, location, size, mat, rotation_deg=(0, 0, 0)):
    bpy.ops.mesh.primitive_cube_add(size=size, location=location,
                                    rotation=[math.radians(a) for a in rotation_deg])
    ob = active()
    ob.name = name
    return assign(ob, mat)


def sphere(name, location, radius, mat, smooth=True):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=radius,
                                         location=location)
    ob = active()
    ob.name = name
    if smooth:
        bpy.ops.object.shade_smooth()
    return assign(ob, mat)


def camera(location=(0, -0.99, 1.2), rotation_deg=(70, 0, 0), lens=20.0):
    bpy.ops.object.camera_add(location=location,
                              rotation=[math.radians(a) for a in rotation_deg])
    cam = active()
    cam.name = "Camera"
    cam.data.lens = lens
    bpy.context.scene.camera = cam
    return cam


def light(kind, location, rotation_deg=(0, 0, 0), energy=10.0, visible_camera=None, **props):
    bpy.ops.object.light_add(type=kind, location=location,
                             rotation=[math.radians(a) for a in rotation_deg])
    ob = active()
    ob.data.energy = energy
    for k, v in props.items():
        setattr(ob.data, k, v)
    if visible_camera is not None:
        ob.visible_camera = visible_camera
    return ob


def room(walls=None, size=2.0, height=2.0, ceiling=True):
    """An open-fronted room [-s/2, s/2] x [-s/2, s/2] x [0, height] of planes, as the stage
    makers build it: default Principled walls (light grey), the left one reddish and the right
    one greenish, open towards -Y where the camera stands."""
    walls = walls or {}
    white = walls.get("white") or principled("Wall", (0.8, 0.8, 0.8))
    red = walls.get("red") or principled("RedWall", (0.8, 0.25, 0.2))
    green = walls.get("green") or principled("GreenWall", (0.25, 0.7, 0.3))
    h = size / 2
    zs = height / size
    plane("Floor", (0, 0, 0), (0, 0, 0), size, walls.get("floor") or white)
    if ceiling:
        plane("Ceiling", (0, 0, height), (180, 0, 0), size, white)
    plane("Back", (0, h, height / 2), (90, 0, 0), size, white, scale=(1, zs, 1))
    plane("Left", (-h, 0, height / 2), (0, 90, 0), size, red, scale=(zs, 1, 1))
    plane("Right", (h, 0, height / 2), (0, -90, 0), size, green, scale=(zs, 1, 1))


def props(mat_sphere=None, mat_cube=None):
    """A cube and a sphere on the floor (the cube 1 mm above it: no coincident faces)."""
    grey = principled("Object", (0.8, 0.8, 0.8))
    cube("Cube", (-0.45, 0.35, 0.251), 0.5, mat_cube or grey, rotation_deg=(0, 0, 25))
    sphere("Sphere", (0.4, 0.1, 0.3), 0.3, mat_sphere or grey)


def ceiling_area(energy=60.0, size=0.6, **kw):
    """A square area light just under the ceiling, pointing down (out of frame)."""
    return light("AREA", (0, 0, 1.95), energy=energy, size=size, **kw)


def lit_room(material=None):
    """The room with the ceiling light; ``material()`` (called after the reset) makes the
    material of the sphere and the cube."""
    sc = reset()
    room()
    m = material() if material is not None else None
    props(mat_sphere=m, mat_cube=m)
    ceiling_area()
    camera()
    return sc


# -- lights -------------------------------------------------------------------------------


@scene("room_empty", "The empty room (default Principled walls) lit by a square area light "
       "(0.6, 60 W) under the ceiling, out of frame: the plainest case.")
def room_empty():
    sc = reset()
    room()
    ceiling_area()
    camera()
    return sc


@scene("point_r0", "Point light of radius 0 (40 W) under the ceiling; a cube and a sphere cast "
       "hard shadows.")
def point_r0():
    sc = reset()
    room()
    props()
    light("POINT", (0.1, 0.2, 1.6), energy=40.0, shadow_soft_size=0.0)
    camera()
    return sc


def _point_near_wall(soft):
    sc = reset()
    room()
    props()
    # 0.25 from the back wall: the wall's light there depends on how the sphere is read.
    light("POINT", (-0.2, 0.75, 1.3), energy=20.0, shadow_soft_size=0.1,
          use_soft_falloff=soft, visible_camera=True)
    camera()
    return sc


@scene("point_r01_soft", "Point light of radius 0.1 (Blender's default Soft Falloff on) 0.25 "
       "from the back wall, visible to the camera.")
def point_r01_soft():
    return _point_near_wall(True)


@scene("point_r01_hard", "The same point light with Soft Falloff off: a true sphere light.")
def point_r01_hard():
    return _point_near_wall(False)


@scene("spot_blend", "Spot light (size 50 deg, blend 0.5, radius 0, 150 W) pointing straight "
       "down: a soft-edged pool on the floor.")
def spot_blend():
    sc = reset()
    room()
    props()
    light("SPOT", (0, 0.2, 1.9), energy=150.0, spot_size=math.radians(50), spot_blend=0.5,
          shadow_soft_size=0.0)
    camera()
    return sc


@scene("spot_radius", "Spot light with a radius (0.2; size 40 deg, blend 0.05, 150 W) tilted "
       "25 deg towards the back wall: Cycles keeps the cone's edge sharp.")
def spot_radius():
    sc = reset()
    room()
    props()
    light("SPOT", (0, 0.2, 1.9), rotation_deg=(25, 0, 0), energy=150.0,
          spot_size=math.radians(40), spot_blend=0.05, shadow_soft_size=0.2)
    camera()
    return sc


@scene("spot_offaxis", "Spot light (size 35 deg, blend 0.15) aimed from the front right at the "
       "back-left corner: an elliptical pool across floor and walls.")
def spot_offaxis():
    sc = reset()
    room()
    props()
    light("SPOT", (0.7, -0.5, 1.8), rotation_deg=(55, 0, 35), energy=200.0,
          spot_size=math.radians(35), spot_blend=0.15, shadow_soft_size=0.0)
    camera()
    return sc


def _area_facing_camera(shape, size, size_y=None):
    """An area light high in the back of the room, tilted 35 deg towards the camera, visible
    to it (its front face is in frame)."""
    sc = reset()
    room()
    props()
    kw = {"shape": shape, "size": size}
    if size_y is not None:
        kw["size_y"] = size_y
    light("AREA", (0, 0.6, 1.35), rotation_deg=(-35, 0, 0), energy=30.0,
          visible_camera=True, **kw)
    camera()
    return sc


@scene("area_square", "Square area light (0.5, 30 W) in the back of the room tilted towards "
       "the camera; its front face is seen (camera visibility on).")
def area_square():
    return _area_facing_camera("SQUARE", 0.5)


@scene("area_rect", "Rectangular area light (0.8 x 0.25) tilted towards the camera, front seen.")
def area_rect():
    return _area_facing_camera("RECTANGLE", 0.8, 0.25)


@scene("area_disk", "Disk area light (diameter 0.5) tilted towards the camera, front seen.")
def area_disk():
    return _area_facing_camera("DISK", 0.5)


@scene("area_ellipse", "Ellipse area light (0.8 x 0.3) tilted towards the camera, front seen.")
def area_ellipse():
    return _area_facing_camera("ELLIPSE", 0.8, 0.3)


def _spread(deg):
    sc = reset()
    room()
    props()
    # Under the ceiling, pointing down; out of frame: only its light on the room is seen.
    light("AREA", (0, 0.3, 1.9), energy=60.0, size=0.6, spread=math.radians(deg))
    camera()
    return sc


@scene("area_spread180", "Square area light (0.6, 60 W) under the ceiling, Spread 180 deg (the "
       "default); out of frame.")
def area_spread180():
    return _spread(180)


@scene("area_spread60", "The same light with Spread 60 deg: a narrower, brighter pool under it.")
def area_spread60():
    return _spread(60)


@scene("area_back", "Square area light (0.5) in mid-room facing the back wall; the camera sees "
       "its back (camera visibility on): Cycles shows the lit wall through it.")
def area_back():
    sc = reset()
    room()
    props()
    light("AREA", (0, 0.2, 1.1), rotation_deg=(90, 0, 0), energy=20.0, size=0.5,
          visible_camera=True)
    camera()
    return sc


@scene("area_edge", "Square area light (0.5) at the camera's height pointing down, seen "
       "edge-on (camera visibility on): a line at most.")
def area_edge():
    sc = reset()
    room()
    props()
    light("AREA", (0, 0.4, 1.2), energy=30.0, size=0.5, visible_camera=True)
    camera(rotation_deg=(90, 0, 0))
    return sc


@scene("area_hidden", "Square area light in frame facing the camera with Blender's default "
       "camera visibility (off): Cycles does not draw it, only its light.")
def area_hidden():
    sc = reset()
    room()
    props()
    light("AREA", (0, 0.6, 1.35), rotation_deg=(-35, 0, 0), energy=30.0, size=0.5)
    camera()
    return sc


def courtyard(wall_height=1.2):
    """A floor with three low walls and no ceiling, for suns and worlds."""
    room(height=wall_height, ceiling=False)
    props()


@scene("sun_angle", "Sun (strength 3, angle 10 deg) from the front left at 50 deg elevation "
       "into a roofless courtyard: soft shadows.", tags=("sun",))
def sun_angle():
    sc = reset()
    courtyard()
    light("SUN", (0, 0, 4), rotation_deg=(40, 0, -35), energy=3.0, angle=math.radians(10))
    camera()
    return sc


@scene("light_exposure", "Square area light of 15 W with Exposure 1.5 (x 2.83) under the "
       "ceiling.")
def light_exposure():
    sc = reset()
    room()
    props()
    ceiling_area(energy=15.0, exposure=1.5)
    camera()
    return sc


@scene("emission_principled", "No lights: a sphere of Principled BSDF with Emission Strength 8 "
       "(warm colour) floating in the room.")
def emission_principled():
    sc = reset()
    room()
    props()
    glow = principled("Glow", (0.8, 0.8, 0.8), Emission_Color=(1.0, 0.6, 0.3),
                      Emission_Strength=8.0)
    sphere("GlowSphere", (-0.1, 0.2, 1.2), 0.2, glow)
    camera()
    return sc


@scene("emission_shader", "No lights: a panel (plane 0.8 x 0.4) with an Emission shader of "
       "strength 6 on the back wall.")
def emission_shader():
    sc = reset()
    room()
    props()
    panel = shader_material("Panel", "ShaderNodeEmission", Strength=6.0)
    plane("Panel", (0, 0.97, 1.35), (90, 0, 0), 1.0, panel, scale=(0.8, 0.4, 1))
    camera()
    return sc


@scene("world_color", "No lights: a world colour (0.4, 0.55, 0.9) over the roofless "
       "courtyard; the sky is in frame.")
def world_color():
    sc = reset()
    courtyard()
    w = bpy.data.worlds.new("World")
    w.node_tree.nodes["Background"].inputs["Color"].default_value = (0.4, 0.55, 0.9, 1.0)
    sc.world = w
    camera()
    return sc


def hdri_path():
    return os.path.join(TEXTURES, "sky.exr")


@scene("world_hdri", "No lights: an equirectangular HDRI world (a sky gradient and a small "
       "bright sun to the front left, textures/sky.exr) over the courtyard.")
def world_hdri():
    sc = reset()
    courtyard()
    w = bpy.data.worlds.new("World")
    nt = w.node_tree
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    env.image = bpy.data.images.load(hdri_path())
    nt.links.new(env.outputs["Color"], nt.nodes["Background"].inputs["Color"])
    sc.world = w
    camera()
    return sc


# -- materials ----------------------------------------------------------------------------


@scene("mat_default", "Default Principled BSDF on every surface (grey sphere and cube, walls).")
def mat_default():
    return lit_room()


@scene("metal_rough", "Gold-coloured metal sphere and cube (Metallic 1, Roughness 0.4).")
def metal_rough():
    return lit_room(lambda: principled("RoughMetal", (0.9, 0.65, 0.3), Metallic=1.0,
                                       Roughness=0.4))


@scene("metal_smooth", "Smooth metal sphere and cube (Metallic 1, Roughness 0.1).")
def metal_smooth():
    return lit_room(lambda: principled("SmoothMetal", (0.9, 0.9, 0.9), Metallic=1.0,
                                       Roughness=0.1))


@scene("glass_r0", "Principled glass sphere and cube (Transmission 1, Roughness 0, IOR 1.5): "
       "caustics on the floor.")
def glass_r0():
    return lit_room(lambda: principled("Glass", (1.0, 1.0, 1.0), Transmission_Weight=1.0,
                                       Roughness=0.0, IOR=1.5))


@scene("glass_r03", "Rough Principled glass (Transmission 1, Roughness 0.3, IOR 1.5).")
def glass_r03():
    return lit_room(lambda: principled("RoughGlass", (1.0, 1.0, 1.0), Transmission_Weight=1.0,
                                       Roughness=0.3, IOR=1.5))


@scene("coat", "Red Principled sphere and cube with a clear coat (Coat Weight 1, Coat "
       "Roughness 0.03).")
def coat():
    return lit_room(lambda: principled("Coated", (0.8, 0.1, 0.1), Coat_Weight=1.0))


def checker_path():
    return os.path.join(TEXTURES, "checker.png")


@scene("textured", "Image texture (textures/checker.png, sRGB) on the Base Color of the floor "
       "and the cube.")
def textured():
    sc = reset()
    m = principled("Checker")
    nt = m.node_tree
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = bpy.data.images.load(checker_path())
    nt.links.new(tex.outputs["Color"], nt.nodes["Principled BSDF"].inputs["Base Color"])
    room(walls={"floor": m})
    props(mat_cube=m)
    ceiling_area()
    camera()
    return sc


@scene("diffuse_bsdf", "Diffuse BSDF node (colour 0.8, 0.5, 0.2) on the sphere and the cube.")
def diffuse_bsdf():
    return lit_room(lambda: shader_material("Diffuse", "ShaderNodeBsdfDiffuse",
                                            Color=(0.8, 0.5, 0.2)))


@scene("glossy_bsdf", "Glossy BSDF node (roughness 0.2, GGX multiscatter default) on the "
       "sphere and the cube.")
def glossy_bsdf():
    return lit_room(lambda: shader_material("Glossy", "ShaderNodeBsdfAnisotropic",
                                            Roughness=0.2))


@scene("glass_bsdf", "Glass BSDF node (roughness 0, IOR 1.5) on the sphere and the cube (Cycles "
       "renders it exactly as glass_r0; the add-on exports the two differently).")
def glass_bsdf():
    return lit_room(lambda: shader_material("GlassNode", "ShaderNodeBsdfGlass", Roughness=0.0,
                                            IOR=1.5))


@scene("mirror_light", "A mirror (Metallic 1, Roughness 0) on the back wall of a closed room "
       "shows the room and an area light above the camera, which is out of frame and hidden "
       "from camera rays (Blender's default).")
def mirror_light():
    sc = reset()
    room()
    plane("Front", (0, -1, 1), (-90, 0, 0), 2.0, principled("FrontWall", (0.8, 0.8, 0.8)))
    props()
    mirror = principled("Mirror", (0.95, 0.95, 0.95), Metallic=1.0, Roughness=0.0)
    plane("Mirror", (0, 0.97, 1.2), (90, 0, 0), 1.0, mirror, scale=(1.2, 1.0, 1))
    light("AREA", (0, -0.3, 1.75), rotation_deg=(45, 0, 0), energy=30.0, size=0.4)
    camera()
    return sc


# -- subsurface -------------------------------------------------------------------------------


@scene("sss_wax", "Wax sphere and cube: the default Principled BSDF with Subsurface Weight 1 "
       "and a warm Base Color, every other subsurface input as Blender sets it (Random Walk, "
       "Radius (1, 0.2, 0.1), Scale 0.05).", tags=("subsurface",))
def sss_wax():
    return lit_room(lambda: principled("Wax", (0.9, 0.7, 0.5), Subsurface_Weight=1.0))


@scene("sss_jade", "Jade sphere and cube: Subsurface Weight 1, Scale 0.3 (light crosses the "
       "objects), green Base Color, Roughness 0.2.", tags=("subsurface",))
def sss_jade():
    return lit_room(lambda: principled("Jade", (0.35, 0.75, 0.45), Subsurface_Weight=1.0,
                                       Subsurface_Scale=0.3, Roughness=0.2))


@scene("sss_backlit", "A thin plate (3 cm) of a subsurface material (Weight 1, Scale 0.05, "
       "near-white) standing in the room, lit from behind by an area light facing the camera "
       "and hidden by the plate; a weak ceiling light shows the room.", tags=("subsurface",))
def sss_backlit():
    sc = reset()
    room()
    mat = principled("Translucent", (0.9, 0.85, 0.75), Subsurface_Weight=1.0)
    plate = cube("Plate", (0, 0.3, 0.55), 1.0, mat)
    plate.scale = (0.8, 0.03, 0.6)
    light("AREA", (0, 0.55, 0.55), rotation_deg=(-90, 0, 0), energy=30.0, size=0.4)
    ceiling_area(energy=10.0)
    camera()
    return sc


# -- media ----------------------------------------------------------------------------------


def _fog_cube(location=(0, 0.25, 0.61), size=1.2, density=1.0):
    return cube("FogCube", location, size, fog_material(density=density))


def _fog_room(light_fn, fog_size=1.2, fog_location=(0, 0.25, 0.61), density=1.0,
              ceiling=True, camera_kw=None):
    sc = reset()
    if ceiling:
        room()
    else:
        room(height=1.2, ceiling=False)
    # A sphere inside the fog casts a shadow through it.
    sphere("Sphere", (0.3, 0.1, 0.21), 0.2, principled("Object", (0.8, 0.8, 0.8)))
    _fog_cube(fog_location, fog_size, density)
    light_fn()
    camera(**(camera_kw or {}))
    return sc


@scene("fog_spot_out", "Principled Volume fog cube (density 1, 1.2 wide) on the floor, lit by a "
       "spot (size 35 deg) from above, outside the fog: a visible beam.", no_usd=NO_USD_VOLUME,
       tags=("fog",))
def fog_spot_out():
    return _fog_room(lambda: light("SPOT", (0, 0.25, 1.9), energy=150.0,
                                   spot_size=math.radians(35), spot_blend=0.2))


@scene("fog_spot_in", "A spot inside a fog cube (1.5 wide, density 0.7) filling most of the "
       "room, pointing down.", no_usd=NO_USD_VOLUME, tags=("fog",))
def fog_spot_in():
    return _fog_room(lambda: light("SPOT", (0, 0.2, 1.4), energy=150.0,
                                   spot_size=math.radians(40), spot_blend=0.2),
                     fog_size=1.5, fog_location=(0, 0.2, 0.76), density=0.7)


@scene("fog_area_out", "The fog cube lit by a square area light (0.5, 60 W) above it.",
       no_usd=NO_USD_VOLUME, tags=("fog",))
def fog_area_out():
    return _fog_room(lambda: light("AREA", (0, 0.25, 1.9), energy=60.0, size=0.5))


@scene("fog_area_in", "A square area light (0.4, 60 W) inside the large fog cube, pointing "
       "down, just out of frame.", no_usd=NO_USD_VOLUME, tags=("fog",))
def fog_area_in():
    return _fog_room(lambda: light("AREA", (0, -0.3, 1.45), energy=60.0, size=0.4),
                     fog_size=1.5, fog_location=(0, 0.2, 0.76), density=0.7)


def _sun():
    return light("SUN", (0, 0, 4), rotation_deg=(40, 0, -35), energy=3.0,
                 angle=math.radians(2))


@scene("fog_sun_out", "Sun (strength 3, angle 2 deg) on the fog cube in the roofless courtyard.",
       no_usd=NO_USD_VOLUME, tags=("fog",))
def fog_sun_out():
    return _fog_room(_sun, ceiling=False)


@scene("fog_sun_in", "Sun into a fog box (density 0.4) that holds the whole courtyard and the "
       "camera.", no_usd=NO_USD_VOLUME, tags=("fog",))
def fog_sun_in():
    sc = reset()
    courtyard()
    fog = cube("FogBox", (0, -0.25, 0.75), 1.0, fog_material(density=0.4))
    fog.scale = (2.3, 2.6, 1.6)  # x [-1.15, 1.15], y [-1.55, 1.05], z [-0.05, 1.55]
    _sun()
    camera()
    return sc


@scene("fog_camera_in", "Camera inside fog: a fog box (density 0.5) fills the room below the "
       "ceiling light, camera included.", no_usd=NO_USD_VOLUME, tags=("fog",))
def fog_camera_in():
    sc = reset()
    room()
    props()
    fog = cube("FogBox", (0, -0.06, 0.86), 1.0, fog_material(density=0.5))
    fog.scale = (1.96, 2.08, 1.7)  # x [-0.98, 0.98], y [-1.1, 0.98], z [0.01, 1.71]
    ceiling_area()
    camera()
    return sc


# -- camera -----------------------------------------------------------------------------------


@scene("dof", "Depth of field: three spheres at about 0.9, 1.5 and 1.9 from the camera, "
       "focused on the middle one, f/1.0.")
def dof():
    sc = reset()
    room()
    grey = principled("Object", (0.8, 0.8, 0.8))
    red = principled("RedBall", (0.8, 0.2, 0.1))
    blue = principled("BlueBall", (0.1, 0.3, 0.8))
    sphere("Near", (-0.4, -0.2, 0.25), 0.25, red)
    sphere("Middle", (0.05, 0.3, 0.25), 0.25, grey)
    sphere("Far", (0.5, 0.7, 0.25), 0.25, blue)
    ceiling_area()
    cam = camera()
    cam.data.dof.use_dof = True
    cam.data.dof.focus_distance = 1.48
    cam.data.dof.aperture_fstop = 1.0
    return sc


# The node scenes register themselves in SCENES.
from corpus import node_scenes  # noqa: E402,F401
