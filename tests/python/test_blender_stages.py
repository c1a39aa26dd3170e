"""Stages written by Blender 5.0.1's own USD exporter (tests/python/data/blender/, made by
make_blender_stages.py; bpy is not needed here): assertions on the imported IR, and a tiny
render of each.

What Blender writes, and what these tests pin down:

- Lights: area, point and spot lights as intensity = P/pi with `normalize = 1` (so IR power
  = P); the point light's and spot's `shadow_soft_size` as the SphereLight radius; the spot's
  full cone angle halved in `shaping:cone:angle` and its blend as `shaping:cone:softness`.
  A sun of strength S and angle A becomes a DistantLight with intensity S/4 (read per UsdLux,
  noted) and angle A/2, while UsdLux's `angle` is the angular diameter: doubled back (noted).
  No camera visibility is written: the lights are hidden from the camera, as Blender renders
  them by default (noted).
  `enableColorTemperature = 1` on every light (6500 K fallback): applied per UsdLux, noted.
- Materials: a UsdPreviewSurface (opacity 1 even for glass) and a MaterialX OpenPBR network on
  `outputs:mtlx:surface`; the importer prefers the OpenPBR network.
- Instancing: objects sharing one mesh datablock (linked duplicates) become one Mesh prim per
  object, with the mesh data repeated, even with `use_instancing=True`. Collection instances
  with `use_instancing=True` become instanceable prims referencing a `class "prototypes"`
  prim: one IR mesh and one IR instance each.
"""
import math
import os

import numpy as np
import pytest

import photonmap
import usd_delegate

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "blender")
STAGES = ["cornell", "glass_mirror", "instances", "collection_instances"]
# UsdLux.BlackbodyTemperatureAsRgb(6500), normalised to luminance 1: the tint Blender 5.0.1's
# exporter gets, since it authors enableColorTemperature = 1 on every light.
TINT_6500 = (1.043, 0.984, 1.035)


def load(name, **kw):
    return usd_delegate.load_stage(os.path.join(DATA, name + ".usda"), **kw)


def by_name(items, suffix):
    found = [x for x in items if str(x.get("name", "")).endswith(suffix)]
    assert len(found) == 1, (suffix, [x.get("name") for x in items])
    return found[0]


def material_of(ir, mesh_suffix):
    return ir["materials"][by_name(ir["meshes"], mesh_suffix)["material"]]


def world_positions(mesh, transform):
    p = np.c_[mesh["positions"], np.ones(len(mesh["positions"]))]
    return (p @ np.array(transform, dtype=np.float64).T)[:, :3]


# -- Cornell box --------------------------------------------------------------------------


def test_cornell_walls_materials_and_camera():
    r = load("cornell")
    ir = r.ir
    assert len(ir["meshes"]) == 5 and r.stats["triangles"] == 10
    assert all(len(m["indices"]) == 2 for m in ir["meshes"])
    expected = {"LeftMesh": (0.65, 0.05, 0.05), "RightMesh": (0.12, 0.45, 0.15),
                "FloorMesh": (0.73, 0.73, 0.73), "CeilingMesh": (0.73, 0.73, 0.73),
                "BackMesh": (0.73, 0.73, 0.73)}
    for mesh, color in expected.items():
        m = material_of(ir, mesh)
        assert m["type"] == "principled"
        assert m["base_color"] == pytest.approx(color, abs=1e-6)
        assert m["metallic"] == 0 and m["transmission"] == 0 and m["roughness"] == 1
    assert len(ir["materials"]) == 3  # shared White, Red, Green
    # The walls bound the box [-1, 1] x [-1, 1] x [0, 2] (each plane's Xform applied).
    pts = np.vstack([world_positions(m, m["transform"]) for m in ir["meshes"]])
    assert pts.min(axis=0) == pytest.approx([-1, -1, 0], abs=1e-5)
    assert pts.max(axis=0) == pytest.approx([1, 1, 2], abs=1e-5)
    # Blender's camera: lens 35 mm on a 36 mm sensor (tenths of a unit), at (0, -3.9, 1).
    cam = ir["camera"]
    assert r.stats["camera"] == "/root/Camera/Camera"
    assert cam["focal_length"] == pytest.approx(0.35) and cam["sensor_width"] == pytest.approx(0.36)
    assert np.array(cam["transform"])[:3, 3] == pytest.approx([0, -3.9, 1], abs=1e-6)
    assert r.diagnostics.warnings == []


def test_cornell_area_light_is_100_watts_with_the_colour_temperature_noted():
    r = load("cornell")
    (light,) = r.ir["lights"]
    # RectLight, intensity 100/pi, normalize 1: radiance I/A, power (I/A) pi A = 100 W.
    assert light["type"] == "rect"
    assert light["width"] == pytest.approx(0.5) and light["height"] == pytest.approx(0.5)
    assert light["power"] == pytest.approx(100.0, rel=1e-6)
    t = np.array(light["transform"])
    assert t[:3, 3] == pytest.approx([0, 0, 1.98], abs=1e-6)
    assert -t[:3, 2] == pytest.approx([0, 0, -1], abs=1e-6)  # emits down, along its -Z
    # Blender authors enableColorTemperature = 1 (fallback 6500 K): tinted per UsdLux, noted.
    assert light["color"] == pytest.approx(TINT_6500, abs=1e-3)
    notes = [m for p, m in r.diagnostics.notes if p == "/root/AreaLight/Area"]
    assert any("colour temperature 6500 K" in m for m in notes), r.diagnostics.notes
    assert light["camera_visible"] is False  # Blender's default; not written


# -- glass, mirror and every light kind ---------------------------------------------------


def test_glass_comes_from_the_openpbr_network_and_the_mirror_is_metallic():
    r = load("glass_mirror")
    ir = r.ir
    glass = material_of(ir, "GlassSphereMesh")
    # Blender's UsdPreviewSurface for this material says opacity 1 (no transmission): the
    # OpenPBR network beside it carries the glass.
    assert glass["transmission"] == 1.0
    assert glass["ior"] == pytest.approx(1.5) and glass["roughness"] == 0.0
    assert glass["metallic"] == 0.0
    assert glass["base_color"] == pytest.approx([1, 1, 1])
    mirror = material_of(ir, "MirrorSphereMesh")
    assert mirror["metallic"] == 1.0 and mirror["roughness"] == 0.0
    assert mirror["transmission"] == 0.0
    assert mirror["base_color"] == pytest.approx([0.9, 0.9, 0.9], abs=1e-6)
    # Low-poly UV spheres: 12 segments x 6 rings = 24 cap triangles + 48 quads.
    for name in ("GlassSphereMesh", "MirrorSphereMesh"):
        assert len(by_name(ir["meshes"], name)["indices"]) == 120
    assert r.stats["triangles"] == 5 * 2 + 2 * 120
    assert r.diagnostics.warnings == []


def test_glass_preview_surface_alone_would_say_opaque():
    """The fact the importer works around: the UsdPreviewSurface of the glass is opaque."""
    from pxr import Usd, UsdShade

    stage = Usd.Stage.Open(os.path.join(DATA, "glass_mirror.usda"))
    mat = UsdShade.Material(stage.GetPrimAtPath("/root/_materials/Glass"))
    preview = mat.GetSurfaceOutput().GetConnectedSources()[0][0].source
    assert preview.GetPrim().GetAttribute("info:id").Get() == "UsdPreviewSurface"
    assert preview.GetInput("opacity").Get() == 1.0
    openpbr = mat.GetSurfaceOutput("mtlx").GetConnectedSources()[0][0].source
    assert openpbr.GetInput("transmission_weight").Get() == 1.0


def test_point_light_200_watts_radius_0_1():
    r = load("glass_mirror")
    pt = by_name(r.ir["lights"], "/PointLight/Point")
    # Blender's default Soft Falloff, which its exporter does not write (noted).
    assert pt["type"] == "point" and pt["soft_falloff"] is True
    assert pt["radius"] == pytest.approx(0.1)
    assert any("Soft Falloff" in m for m in r.diagnostics.messages())
    assert pt["power"] == pytest.approx(200.0, rel=1e-6)
    assert pt["position"] == pytest.approx([0, 0, 1.7], abs=1e-6)
    assert pt["color"] == pytest.approx(TINT_6500, abs=1e-3)
    # Blender hides lights from the camera by default; its exporter writes no visibility.
    assert pt["camera_visible"] is False
    assert any("hidden from the camera" in m for p, m in r.diagnostics.notes
               if p == "/root/PointLight/Point")


def test_sun_angle_doubled_back_intensity_read_per_usdlux_both_noted():
    r = load("glass_mirror")
    sun = by_name(r.ir["lights"], "/Sun/Sun")
    assert sun["type"] == "distant"
    # Blender's sun: strength 3, angle 2 deg. Its exporter writes intensity 3/4 = 0.75 and
    # angle 1 (half the angle), while UsdLux's `angle` is the angular diameter in degrees:
    # the angle is doubled back (Blender 5.0), the intensity read per UsdLux.
    assert sun["irradiance"] == pytest.approx(0.75)
    assert sun["angle"] == pytest.approx(math.radians(2.0))
    assert 4 * sun["irradiance"] == pytest.approx(3.0)
    # Rotation (0.3, 0.2, 0) rad XYZ applied to -Z.
    rx, ry = 0.3, 0.2
    d = np.array([-math.sin(ry) * math.cos(rx), math.sin(rx), -math.cos(ry) * math.cos(rx)])
    assert sun["direction"] == pytest.approx(d, abs=1e-5)
    notes = [m for p, m in r.diagnostics.notes if p == "/root/Sun/Sun"]
    assert any("S/4" in m and "strength 3" in m for m in notes), notes
    assert any("Blender v5.0.1" in m and "angle 1 deg read as 2 deg" in m for m in notes), notes
    assert any("colour temperature" in m for m in notes)


def test_spot_cone_and_blend():
    r = load("glass_mirror")
    spot = by_name(r.ir["lights"], "/Spot/Spot")
    assert spot["type"] == "spot"
    # Blender spot_size 45 deg (the full cone) -> shaping:cone:angle 22.5 -> IR full cone 45.
    assert spot["cone_angle"] == pytest.approx(math.radians(45.0))
    assert spot["blend"] == pytest.approx(0.15)
    assert spot["power"] == pytest.approx(500.0, rel=1e-6)
    assert spot["radius"] == pytest.approx(0.05)
    assert spot["position"] == pytest.approx([0, -0.5, 1.9], abs=1e-6)
    assert spot["direction"] == pytest.approx([0, math.sin(0.2), -math.cos(0.2)], abs=1e-6)
    assert spot["camera_visible"] is False


def test_every_blender_light_notes_its_colour_temperature():
    r = load("glass_mirror")
    assert len(r.ir["lights"]) == 3
    noted = {p for p, m in r.diagnostics.notes if "colour temperature 6500 K" in m}
    assert noted == {"/root/PointLight/Point", "/root/Sun/Sun", "/root/Spot/Spot"}
    for light in r.ir["lights"]:
        assert light["color"] == pytest.approx(TINT_6500, abs=1e-3)


# -- instancing ---------------------------------------------------------------------------


def test_linked_duplicates_are_written_as_separate_meshes():
    """Blender writes one Mesh prim per object for linked duplicates (shared mesh datablock),
    with the mesh data repeated, even with use_instancing=True: the importer reads six
    meshes of identical data and no instances."""
    r = load("instances")
    ir = r.ir
    rocks = [m for m in ir["meshes"] if m["name"].endswith("/RockMesh")]
    assert len(rocks) == 6 and ir["instances"] == []
    for m in rocks[1:]:
        assert np.array_equal(m["positions"], rocks[0]["positions"])
        assert np.array_equal(m["indices"], rocks[0]["indices"])
        assert m["material"] == rocks[0]["material"]
    assert len(rocks[0]["indices"]) == 20  # an icosphere of subdivision 1
    xs = sorted(np.array(m["transform"])[0, 3] for m in rocks)
    assert xs == pytest.approx([-2 + 0.8 * i for i in range(6)], abs=1e-5)
    assert material_of(ir, "/Rock/RockMesh")["base_color"] == pytest.approx([0.6, 0.5, 0.4], abs=1e-6)


def test_collection_instances_share_one_ir_mesh():
    r = load("collection_instances")
    ir = r.ir
    rocks = [m for m in ir["meshes"] if m["name"].endswith("/RockMesh")]
    assert len(rocks) == 1
    assert len(ir["instances"]) == 5 and r.stats["instances"] == 5
    assert {i["mesh"] for i in ir["instances"]} == {ir["meshes"].index(rocks[0])}
    assert ir["materials"][rocks[0]["material"]]["base_color"] == pytest.approx([0.6, 0.5, 0.4], abs=1e-6)
    # Empty i at (-2 + i, 0.2 i, 0) turned 0.4 i about Z; the rock 0.3 above it.
    centres = sorted(np.mean(world_positions(rocks[0], i["transform"]), axis=0)[0] for i in ir["instances"])
    assert centres == pytest.approx([-2 + i for i in range(5)], abs=1e-5)
    for inst in ir["instances"]:
        k = int(inst["name"].split("RockInstance_")[1][:3])
        t = np.array(inst["transform"])
        c = world_positions(rocks[0], t).mean(axis=0)
        assert c == pytest.approx([-2 + k, 0.2 * k, 0.3], abs=1e-5)
        a = 0.4 * k
        rz = [[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]]
        assert np.allclose(t[:3, :3], rz, atol=1e-5)
    assert len({i["name"] for i in ir["instances"]}) == 5
    assert r.diagnostics.warnings == []


# -- every stage renders --------------------------------------------------------------------


@pytest.mark.parametrize("name", STAGES)
def test_every_blender_stage_renders(name):
    r = load(name, width=16)
    assert r.ir["film"]["width"] == 16
    out = photonmap.render(photonmap.Scene.from_dict(r.ir), quality="draft", spp=1, seed=1)
    assert out["combined"].shape == (r.ir["film"]["height"], 16, 3)
    for term in ("combined", *photonmap.TERMS):
        assert np.all(np.isfinite(out[term])), term
        assert np.all(out[term] >= 0), term
    assert out["combined"].mean() > 0  # the box is lit
