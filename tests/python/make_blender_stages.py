"""Builds small scenes in Blender and exports them with Blender's own USD exporter, as test
inputs for the USD importer (tests/python/test_blender_stages.py).

Regenerate (needs the `bpy` module from PyPI, 5.0.1, headless; the tests themselves do not):

    python -m venv venv-bpy && venv-bpy/bin/pip install bpy==5.0.1
    venv-bpy/bin/python tests/python/make_blender_stages.py

Writes to tests/python/data/blender/:

- cornell.usda       Cornell box (white/red/green Principled walls), 100 W square area light
                     (size 0.5) under the ceiling, a camera looking in.
- glass_mirror.usda  the same box with a Principled glass sphere (transmission 1, IOR 1.5,
                     roughness 0) and a mirror sphere (metallic 1, roughness 0), a point light
                     (radius 0.1, 200 W), a sun (strength 3, angle 2 deg), a spot (45 deg,
                     blend 0.15, 500 W).
- instances.usda     one mesh linked-duplicated 5 times (objects sharing one mesh datablock),
                     exported with `use_instancing=True` (Blender still writes one Mesh prim
                     per object; `use_instancing=False` writes the same prims).
- collection_instances.usda  a collection holding one mesh, instanced 5 times by empties
                     (Add > Collection Instance), exported with `use_instancing=True`.

Every stage is exported with `generate_materialx_network=True` (Blender writes glass only in
the MaterialX OpenPBR network) and `generate_preview_surface=True`.
"""

import math
import os
import sys

import bpy

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "blender")


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.render.resolution_x = 64
    scene.render.resolution_y = 64
    return scene


def principled(name, color=(0.8, 0.8, 0.8), **inputs):
    m = bpy.data.materials.new(name)
    if not m.use_nodes:  # always on since Blender 5.0 (the property is deprecated)
        m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    for k, v in inputs.items():
        bsdf.inputs[k].default_value = v
    return m


def plane(name, location, rotation, size, material):
    bpy.ops.mesh.primitive_plane_add(size=size, location=location, rotation=rotation)
    ob = bpy.context.active_object
    ob.name = name
    ob.data.name = name + "Mesh"
    ob.data.materials.append(material)
    return ob


def cornell_box():
    """A 2x2x2 box centred at (0, 0, 1), open towards -Y; walls face inwards."""
    white = principled("White", (0.73, 0.73, 0.73), Roughness=1.0)
    red = principled("Red", (0.65, 0.05, 0.05), Roughness=1.0)
    green = principled("Green", (0.12, 0.45, 0.15), Roughness=1.0)
    h = math.pi / 2
    plane("Floor", (0, 0, 0), (0, 0, 0), 2, white)             # normal +Z
    plane("Ceiling", (0, 0, 2), (math.pi, 0, 0), 2, white)     # normal -Z
    plane("Back", (0, 1, 1), (h, 0, 0), 2, white)              # normal -Y
    plane("Left", (-1, 0, 1), (0, h, 0), 2, red)               # normal +X
    plane("Right", (1, 0, 1), (0, -h, 0), 2, green)            # normal -X


def camera(scene):
    bpy.ops.object.camera_add(location=(0, -3.9, 1), rotation=(math.pi / 2, 0, 0))
    cam = bpy.context.active_object
    cam.name = "Camera"
    cam.data.lens = 35
    scene.camera = cam


def area_light():
    bpy.ops.object.light_add(type="AREA", location=(0, 0, 1.98))
    lt = bpy.context.active_object
    lt.name = "AreaLight"
    lt.data.shape = "SQUARE"
    lt.data.size = 0.5
    lt.data.energy = 100.0
    return lt


def sphere(name, location, radius, material):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=12, ring_count=6, radius=radius, location=location)
    ob = bpy.context.active_object
    ob.name = name
    ob.data.name = name + "Mesh"
    ob.data.materials.append(material)
    bpy.ops.object.shade_smooth()
    return ob


def export(name, **kw):
    path = os.path.join(OUT, name)
    args = dict(filepath=path, export_materials=True, generate_preview_surface=True,
                generate_materialx_network=True, export_animation=False,
                export_textures_mode="KEEP", relative_paths=True, evaluation_mode="RENDER")
    args.update(kw)
    bpy.ops.wm.usd_export(**args)
    print("wrote", path)


def make_cornell():
    scene = reset()
    cornell_box()
    area_light()
    camera(scene)
    export("cornell.usda")


def make_glass_mirror():
    scene = reset()
    cornell_box()
    glass = principled("Glass", (1.0, 1.0, 1.0), Roughness=0.0, IOR=1.5,
                       **{"Transmission Weight": 1.0})
    mirror = principled("Mirror", (0.9, 0.9, 0.9), Roughness=0.0, Metallic=1.0)
    sphere("GlassSphere", (0.45, -0.2, 0.4), 0.4, glass)
    sphere("MirrorSphere", (-0.45, 0.35, 0.4), 0.4, mirror)

    bpy.ops.object.light_add(type="POINT", location=(0, 0, 1.7))
    pt = bpy.context.active_object
    pt.name = "PointLight"
    pt.data.shadow_soft_size = 0.1
    pt.data.energy = 200.0

    bpy.ops.object.light_add(type="SUN", location=(0, 0, 5), rotation=(0.3, 0.2, 0))
    sun = bpy.context.active_object
    sun.name = "Sun"
    sun.data.energy = 3.0
    sun.data.angle = math.radians(2.0)

    bpy.ops.object.light_add(type="SPOT", location=(0, -0.5, 1.9), rotation=(0.2, 0, 0))
    spot = bpy.context.active_object
    spot.name = "Spot"
    spot.data.spot_size = math.radians(45.0)
    spot.data.spot_blend = 0.15
    spot.data.energy = 500.0
    spot.data.shadow_soft_size = 0.05

    camera(scene)
    export("glass_mirror.usda")


def make_instances():
    scene = reset()
    mat = principled("Clay", (0.6, 0.5, 0.4), Roughness=0.7)
    plane("Floor", (0, 0, 0), (0, 0, 0), 6, principled("White", (0.73, 0.73, 0.73)))
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=1, radius=0.3, location=(-2, 0, 0.3))
    src = bpy.context.active_object
    src.name = "Rock"
    src.data.name = "RockMesh"
    src.data.materials.append(mat)
    for i in range(5):  # Alt+D five times: objects sharing the mesh datablock RockMesh
        bpy.ops.object.select_all(action="DESELECT")
        src.select_set(True)
        bpy.context.view_layer.objects.active = src
        bpy.ops.object.duplicate_move_linked(TRANSFORM_OT_translate={"value": (0.8 * (i + 1), 0, 0)})
        dup = bpy.context.active_object
        dup.name = f"Rock.{i + 1:03d}"
    assert len({o.data.name for o in bpy.data.objects if o.type == "MESH" and o.name.startswith("Rock")}) == 1
    area_light()
    bpy.context.active_object.location = (0, 0, 3)
    camera(scene)
    cam = scene.camera
    cam.location = (0, -6, 1.5)
    cam.rotation_euler = (math.radians(80), 0, 0)
    export("instances.usda", use_instancing=True)


def make_collection_instances():
    scene = reset()
    mat = principled("Clay", (0.6, 0.5, 0.4), Roughness=0.7)
    plane("Floor", (0, 0, 0), (0, 0, 0), 6, principled("White", (0.73, 0.73, 0.73)))
    coll = bpy.data.collections.new("RockSet")
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=1, radius=0.3, location=(0, 0, 0.3))
    src = bpy.context.active_object
    src.name = "Rock"
    src.data.name = "RockMesh"
    src.data.materials.append(mat)
    for c in list(src.users_collection):
        c.objects.unlink(src)
    coll.objects.link(src)  # not linked to the scene: only its instances are drawn
    for i in range(5):
        empty = bpy.data.objects.new(f"RockInstance.{i:03d}", None)
        empty.instance_type = "COLLECTION"
        empty.instance_collection = coll
        empty.location = (-2 + 1.0 * i, 0.2 * i, 0)
        empty.rotation_euler = (0, 0, 0.4 * i)
        scene.collection.objects.link(empty)
    area_light()
    bpy.context.active_object.location = (0, 0, 3)
    camera(scene)
    cam = scene.camera
    cam.location = (0, -6, 1.5)
    cam.rotation_euler = (math.radians(80), 0, 0)
    export("collection_instances.usda", use_instancing=True)


def main():
    os.makedirs(OUT, exist_ok=True)
    make_cornell()
    make_glass_mirror()
    make_instances()
    make_collection_instances()


if __name__ == "__main__":
    main()
    sys.stdout.flush()
