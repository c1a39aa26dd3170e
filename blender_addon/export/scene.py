"""Depsgraph -> scene IR: walks ``depsgraph.object_instances`` and hands each Blender ID to its
converter. Each unique mesh is exported once; repeated placements (linked duplicates,
collection instances, particles, geometry-node instances) become IR instances of it."""

from __future__ import annotations

from dataclasses import dataclass, field

from .camera import Window, export_camera, render_window
from .image import ImageCache
from .light import export_light
from .material import MaterialExporter
from .mesh import export_mesh, matrix_rows
from .world import export_world

GEOMETRY = {"MESH", "CURVE", "SURFACE", "FONT", "META"}


@dataclass
class ExportResult:
    ir: dict
    window: Window
    warnings: list = field(default_factory=list)
    counts: dict = field(default_factory=dict)


class _Materials:
    def __init__(self, ir_materials, exporter):
        self.ir = ir_materials
        self.exporter = exporter
        self.index: dict = {}

    def get(self, mat) -> int:
        key = None if mat is None else mat.name_full
        if key not in self.index:
            self.ir.append(self.exporter.export(mat))
            self.index[key] = len(self.ir) - 1
        return self.index[key]


def export_scene(depsgraph, camera: dict | None = None, window: Window | None = None) -> ExportResult:
    """The IR of the evaluated scene. ``camera``/``window`` replace the scene camera and the
    render window (the viewport passes its own view)."""
    scene = depsgraph.scene
    warnings: list[str] = []
    seen = set()

    def warn(msg: str) -> None:
        if msg not in seen:
            seen.add(msg)
            warnings.append(msg)

    ir = {"materials": [], "textures": [], "meshes": [], "instances": [], "lights": []}
    images = ImageCache(ir["textures"], warn)
    materials = _Materials(ir["materials"], MaterialExporter(images, warn))

    meshes: dict = {}  # key -> (ir mesh, [world matrices])
    for inst in depsgraph.object_instances:
        obj = inst.object
        kind = obj.type
        if kind == "LIGHT":
            if inst.show_self:
                light = export_light(obj, inst.matrix_world, warn)
                if light is not None:
                    ir["lights"].append(light)
            continue
        if kind == "VOLUME":
            warn(f"object '{obj.name}': volumes are not supported yet; skipped")
            continue
        if kind not in GEOMETRY or not inst.show_self:
            continue
        slots = [materials.get(s.material) for s in obj.material_slots]
        if kind == "MESH" and obj.data is not None:
            key = ("mesh", obj.data.as_pointer(), tuple(slots))
        else:
            key = ("object", obj.name_full, tuple(slots))
        entry = meshes.get(key)
        if entry is None:
            name = obj.name if kind != "MESH" else f"{obj.name} ({obj.data.name})"
            m = export_mesh(obj, name, slots or [materials.get(None)])
            entry = meshes[key] = (m, [])
        if entry[0] is not None:
            entry[1].append(inst.matrix_world.copy())

    n_inst = 0
    for m, placements in meshes.values():
        if m is None:
            continue
        idx = len(ir["meshes"])
        ir["meshes"].append(m)
        if len(placements) == 1:
            m["transform"] = matrix_rows(placements[0])
        else:
            for k, mw in enumerate(placements):
                ir["instances"].append({"name": f"{m['name']} #{k}", "mesh": idx,
                                        "transform": matrix_rows(mw)})
            n_inst += len(placements)
    if not ir["materials"]:
        materials.get(None)

    env = export_world(scene.world, images, warn)
    if env is not None:
        ir["environment"] = env
    win = window or render_window(scene)
    if camera is None:
        cam = scene.camera.evaluated_get(depsgraph) if scene.camera else None
        camera = export_camera(scene, cam, win, warn)
    ir["camera"] = camera
    ir["film"] = {"width": win.w, "height": win.h}
    counts = {
        "meshes": len(ir["meshes"]), "instances": n_inst, "lights": len(ir["lights"]),
        "materials": len(ir["materials"]), "textures": len(ir["textures"]),
        "triangles": sum(len(m["indices"]) for m in ir["meshes"]),
    }
    return ExportResult(ir=ir, window=win, warnings=warnings, counts=counts)
