"""Small test scenes built with bpy for the add-on's tests (64x64, diffuse, black world,
emitters out of frame). Comparisons with Cycles are the corpus' (tests/blender/corpus/).
"""

from __future__ import annotations

import math

import bpy

SIZE = 64


def diffuse(name, color):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (*color, 1.0)
    nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    return m


def quad(name, corners, mat):
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(c) for c in corners], [], [(0, 1, 2, 3)])
    me.update()
    me.materials.append(mat)
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    return ob


def empty_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.world = None
    sc.render.resolution_x = SIZE
    sc.render.resolution_y = SIZE
    sc.render.resolution_percentage = 100
    return sc


def camera(location, rotation_deg, lens=35.0):
    cam = bpy.data.cameras.new("Camera")
    cam.lens = lens
    ob = bpy.data.objects.new("Camera", cam)
    ob.location = location
    ob.rotation_euler = [math.radians(a) for a in rotation_deg]
    bpy.context.scene.collection.objects.link(ob)
    bpy.context.scene.camera = ob
    return ob


def light(kind, location, rotation_deg=(0, 0, 0), **props):
    data = bpy.data.lights.new(kind.lower(), kind)
    for k, v in props.items():
        setattr(data, k, v)
    ob = bpy.data.objects.new(data.name, data)
    ob.location = location
    ob.rotation_euler = [math.radians(a) for a in rotation_deg]
    ob.visible_camera = False
    bpy.context.scene.collection.objects.link(ob)
    return ob


def cornell_walls():
    """Closed-on-five-sides box [-1,1] x [-1,1] x [0,2], open towards -Y; normals inwards."""
    white = diffuse("white", (0.8, 0.8, 0.8))
    red = diffuse("red", (0.8, 0.1, 0.1))
    green = diffuse("green", (0.1, 0.8, 0.1))
    quad("floor", [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], white)
    quad("ceiling", [(-1, -1, 2), (-1, 1, 2), (1, 1, 2), (1, -1, 2)], white)
    quad("back", [(-1, 1, 0), (1, 1, 0), (1, 1, 2), (-1, 1, 2)], white)
    quad("left", [(-1, -1, 0), (-1, 1, 0), (-1, 1, 2), (-1, -1, 2)], red)
    quad("right", [(1, -1, 0), (1, -1, 2), (1, 1, 2), (1, 1, 0)], green)
    # Camera in the open side, looking slightly down at the back wall; the lights (below the
    # ceiling) stay out of frame.
    camera((0, -3.2, 0.7), (85, 0, 0), lens=40.0)


def cornell_area():
    sc = empty_scene()
    cornell_walls()
    light("AREA", (0, 0, 1.98), size=0.5, energy=60.0)
    return sc


def cornell_point():
    sc = empty_scene()
    cornell_walls()
    light("POINT", (0, -0.3, 1.8), energy=80.0, shadow_soft_size=0.05, use_soft_falloff=False)
    return sc


def sun_floor():
    """A floor and two walls lit by a sun from above at an angle."""
    sc = empty_scene()
    white = diffuse("white", (0.8, 0.8, 0.8))
    blue = diffuse("blue", (0.2, 0.3, 0.8))
    quad("floor", [(-2, -2, 0), (2, -2, 0), (2, 2, 0), (-2, 2, 0)], white)
    quad("back", [(-2, 2, 0), (2, 2, 0), (2, 2, 2), (-2, 2, 2)], white)
    quad("left", [(-2, -2, 0), (-2, 2, 0), (-2, 2, 2), (-2, -2, 2)], blue)
    camera((0.5, -4.5, 2.5), (65, 0, 0), lens=30.0)
    light("SUN", (0, 0, 5), (35, 0, -30), energy=2.0, angle=math.radians(2.0))
    return sc



def volume_material(name, kind="ShaderNodeVolumePrincipled", surface=None, **inputs):
    """A material whose Volume output is fed by the node ``kind`` (inputs set by socket name,
    underscores for spaces), with an optional surface shader node ``surface``."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    vol = nt.nodes.new(kind)
    for key, value in inputs.items():
        sock = vol.inputs[key.replace("_", " ")]
        sock.default_value = (*value, 1.0) if isinstance(value, tuple) and len(value) == 3 \
            else value
    nt.links.new(vol.outputs[0], out.inputs["Volume"])
    if surface is not None:
        s = nt.nodes.new(surface)
        nt.links.new(s.outputs[0], out.inputs["Surface"])
    return m


def cube(name, center, size, mat):
    """A closed cube (outward normals) of edge ``size``."""
    bpy.ops.mesh.primitive_cube_add(size=size, location=center)
    ob = bpy.context.object
    ob.name = name
    ob.data.materials.append(mat)
    return ob


def fog_spot():
    """A spot light shining down through a fog cube onto a white floor, seen from the side; the
    spot is outside the frame. Fog: Principled Volume, density 1, colour 0.8, anisotropy 0."""
    sc = empty_scene()
    white = diffuse("white", (0.8, 0.8, 0.8))
    quad("floor", [(-3, -3, 0), (3, -3, 0), (3, 3, 0), (-3, 3, 0)], white)
    quad("back", [(-3, 3, 0), (3, 3, 0), (3, 3, 3), (-3, 3, 3)], white)
    fog = volume_material("fog", Density=1.0, Color=(0.8, 0.8, 0.8))
    cube("fog", (0, 0, 0.75), 1.5, fog)
    light("SPOT", (0, 0, 3.2), energy=300.0, spot_size=math.radians(50), spot_blend=0.2,
          shadow_soft_size=0.0)
    camera((0, -6, 1.5), (82, 0, 0), lens=30.0)
    return sc

