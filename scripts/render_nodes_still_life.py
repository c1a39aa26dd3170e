"""Renders the node still life (a checker floor, a Layer Weight plastic, a noise-bumped wall
with noise colours, a checker alpha cut-out) with PhotonMap or Cycles, for the contact sheet
docs/images/nodes_still_life.png.

    python scripts/render_nodes_still_life.py WHEEL OUT_DIR pm|cy

with the bpy venv's Python; writes OUT_DIR/pm.exr or OUT_DIR/cy.exr."""
import math
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "blender"))
import bpy  # noqa: E402

wheel, outdir = sys.argv[-3], sys.argv[-2]
zipd = os.path.join(outdir, "ext")
os.makedirs(zipd, exist_ok=True)
res = subprocess.run([sys.executable, str(ROOT / "scripts" / "build_blender_extension.py"),
                      "--out", zipd, "--wheel", wheel],
                     check=True, capture_output=True, text=True)
z = res.stdout.strip().splitlines()[-1]
bpy.ops.wm.read_factory_settings(use_empty=True)
assert bpy.ops.extensions.package_install_files(repo="user_default", filepath=z, enable_on_install=True) == {"FINISHED"}
import addon_utils
addon_utils.enable("bl_ext.user_default.photonmap", default_set=True)
import scenes

def build():
    sc = scenes.empty_scene()
    scenes.cornell_walls()
    scenes.light("AREA", (0, 0, 1.98), size=0.5, energy=60.0)
    sc.render.resolution_x = 160; sc.render.resolution_y = 120
    # checker floor
    m = bpy.data.materials["white"].copy(); m.name = "checker floor"
    nt = m.node_tree; d = nt.nodes["Diffuse BSDF"]
    ck = nt.nodes.new("ShaderNodeTexChecker"); ck.inputs["Scale"].default_value = 4.0
    ck.inputs["Color1"].default_value = (0.8, 0.7, 0.5, 1); ck.inputs["Color2"].default_value = (0.1, 0.1, 0.3, 1)
    nt.links.new(ck.outputs["Color"], d.inputs["Color"])
    bpy.data.objects["floor"].data.materials[0] = m
    # plastic sphere
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.45, location=(-0.35, 0.2, 0.45), segments=48, ring_count=24)
    sph = bpy.context.object
    bpy.ops.object.shade_smooth()
    pm = bpy.data.materials.new("plastic"); pm.use_nodes = True
    nt = pm.node_tree; nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    mix = nt.nodes.new("ShaderNodeMixShader"); lw = nt.nodes.new("ShaderNodeLayerWeight")
    lw.inputs["Blend"].default_value = 0.3
    dif = nt.nodes.new("ShaderNodeBsdfDiffuse"); dif.inputs["Color"].default_value = (0.1, 0.3, 0.8, 1)
    gl = nt.nodes.new("ShaderNodeBsdfGlossy"); gl.inputs["Roughness"].default_value = 0.25
    nt.links.new(lw.outputs["Fresnel"], mix.inputs[0]); nt.links.new(dif.outputs[0], mix.inputs[1]); nt.links.new(gl.outputs[0], mix.inputs[2])
    nt.links.new(mix.outputs[0], out.inputs["Surface"])
    sph.data.materials.append(pm)
    # noise bump on the back wall
    bm = bpy.data.materials["white"].copy(); bm.name = "bumpy"
    nt = bm.node_tree; d = nt.nodes["Diffuse BSDF"]
    nz = nt.nodes.new("ShaderNodeTexNoise"); nz.inputs["Scale"].default_value = 6.0
    bu = nt.nodes.new("ShaderNodeBump"); bu.inputs["Distance"].default_value = 0.05
    nt.links.new(nz.outputs["Fac"], bu.inputs["Height"]); nt.links.new(bu.outputs["Normal"], d.inputs["Normal"])
    nz2 = nt.nodes.new("ShaderNodeTexNoise"); nz2.inputs["Scale"].default_value = 3.0
    nt.links.new(nz2.outputs["Color"], d.inputs["Color"])
    bpy.data.objects["back"].data.materials[0] = bm
    # alpha card
    ob = scenes.quad("leaf", [(0.2, 0.0, 0.2), (0.9, 0.0, 0.2), (0.9, 0.0, 0.9), (0.2, 0.0, 0.9)], None)
    am = bpy.data.materials.new("leaf"); am.use_nodes = True
    nt = am.node_tree; pr = nt.nodes["Principled BSDF"]
    pr.inputs["Base Color"].default_value = (0.2, 0.6, 0.1, 1)
    ck = nt.nodes.new("ShaderNodeTexChecker"); ck.inputs["Scale"].default_value = 3.0
    ck.inputs["Color1"].default_value = (1, 1, 1, 1); ck.inputs["Color2"].default_value = (0, 0, 0, 1)
    nt.links.new(ck.outputs["Fac"], pr.inputs["Alpha"])
    ob.data.materials.clear(); ob.data.materials.append(am)
    return sc

sc = build()
addon_utils.enable("bl_ext.user_default.photonmap", default_set=True)
which = sys.argv[-1]
if which == "pm":
    sc.render.engine = "PHOTONMAP"; sc.photonmap.quality = "medium"
else:
    sc.render.engine = "CYCLES"; sc.cycles.samples = 256; sc.cycles.device = "CPU"
sc.view_settings.view_transform = "Standard"
sc.render.image_settings.file_format = "OPEN_EXR"
sc.render.filepath = os.path.join(outdir, f"{which}.exr")
bpy.ops.render.render(write_still=True)
print("DONE", which)
