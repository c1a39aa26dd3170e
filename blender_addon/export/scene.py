"""Depsgraph -> scene IR: walks ``depsgraph.object_instances`` and hands each Blender ID to its
converter. Each unique mesh is exported once; repeated placements (linked duplicates,
collection instances, particles, geometry-node instances) become IR instances of it.

Light groups: the view layer's light groups become the IR's ``lightgroups``, with the lights,
emissive objects (``Object.lightgroup``) and the world (``World.lightgroup``) that name them;
the rest goes to the core's ``default`` group, as do members of a group the view layer does not
have (warned). Without light groups in the view layer, none are exported (as Cycles writes no
light-group passes then).

Volumes: a mesh whose material has a Volume shader becomes the closed boundary of an IR medium
(``interior_medium``; its surface is ``null`` when the material has no Surface shader), and the
World's Volume shader becomes ``world_medium`` (volume.py). Volume objects (OpenVDB grids) are
skipped with a warning: the core has homogeneous media only."""

from __future__ import annotations

from dataclasses import dataclass, field

from .camera import Window, export_camera, render_window
from .image import ImageCache
from .light import export_light
from .material import MaterialExporter
from .mesh import export_mesh, matrix_rows
from .volume import material_volume_socket, read_volume, world_volume_socket
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


class _Media:
    """IR media of materials' Volume shaders, one per material."""

    def __init__(self, ir_media):
        self.ir = ir_media
        self.index: dict = {}
        self.issues: dict = {}

    def get(self, mat) -> int | None:
        """The IR medium of ``mat``'s volume, None when it has none (``issues_of`` says why)."""
        key = None if mat is None else mat.name_full
        if key not in self.index:
            sock = material_volume_socket(mat)
            medium, issues = (None, []) if sock is None else read_volume(sock)
            self.issues[key] = issues
            if medium is None:
                self.index[key] = None
            else:
                self.ir.append(dict(medium, name=mat.name))
                self.index[key] = len(self.ir) - 1
        return self.index[key]

    def issues_of(self, mat) -> list:
        return self.issues.get(None if mat is None else mat.name_full, [])


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
    if getattr(scene.render, "film_transparent", False):
        if getattr(getattr(scene, "cycles", None), "film_transparent_glass", False):
            warn(f"scene '{scene.name}': Film > Transparent Glass is not supported: glass "
                 f"in front of the background stays opaque")
    groups = _LightGroups(depsgraph.view_layer, warn)
    images = ImageCache(ir["textures"], warn)
    mat_exporter = MaterialExporter(images, warn)
    materials = _Materials(ir["materials"], mat_exporter)
    ir["media"] = []
    media = _Media(ir["media"])

    meshes: dict = {}  # key -> (ir mesh, [world matrices])
    for inst in depsgraph.object_instances:
        obj = inst.object
        kind = obj.type
        if kind == "LIGHT":
            if inst.show_self:
                light = export_light(obj, inst.matrix_world, warn)
                if light is not None:
                    groups.add(obj, "lights", len(ir["lights"]))
                    ir["lights"].append(light)
            continue
        if kind == "VOLUME":
            if inst.show_self:
                warn(f"object '{obj.name}': Volume objects (OpenVDB grids) are not supported; "
                     f"skipped")
            continue
        if kind not in GEOMETRY or not inst.show_self:
            continue
        mats = [s.material for s in obj.material_slots]
        slots = [materials.get(m) for m in mats]
        medium = _object_medium(obj, mats, media, warn)
        if kind == "MESH" and obj.data is not None:
            key = ("mesh", obj.data.as_pointer(), tuple(slots))
        else:
            key = ("object", obj.name_full, tuple(slots))
        entry = meshes.get(key)
        if entry is None:
            name = obj.name if kind != "MESH" else f"{obj.name} ({obj.data.name})"
            shape = {} if medium is not None else None
            m = export_mesh(obj, name, slots or [materials.get(None)], shape,
                            mat_exporter.stats.get("attributes", ()), warn)
            if m is not None and medium is not None:
                m["interior_medium"] = medium
                _check_boundary(obj, shape, inst.matrix_world, warn)
            entry = meshes[key] = (m, [])
        if entry[0] is not None:
            entry[1].append((inst.matrix_world.copy(), _object_name(inst), inst.object,
                             _is_holdout(obj, depsgraph.view_layer)))

    n_inst = 0
    for m, placements in meshes.values():
        if m is None:
            continue
        idx = len(ir["meshes"])
        ir["meshes"].append(m)
        if len(placements) == 1:
            mw, obj_name, obj, holdout = placements[0]
            m["transform"] = matrix_rows(mw)
            m["object"] = obj_name
            if holdout:
                m["holdout"] = True
            groups.add(obj, "meshes", idx)
        else:
            for k, (mw, obj_name, obj, holdout) in enumerate(placements):
                groups.add(obj, "instances", len(ir["instances"]))
                placed = {"name": f"{m['name']} #{k}", "mesh": idx,
                          "transform": matrix_rows(mw), "object": obj_name}
                if holdout:
                    placed["holdout"] = True
                ir["instances"].append(placed)
            n_inst += len(placements)
    if not ir["materials"]:
        materials.get(None)

    env = export_world(scene.world, images, warn)
    if env is not None:
        ir["environment"] = env
        groups.add(scene.world, "environment", None)
    if groups.ir:
        ir["lightgroups"] = groups.ir
    sock = world_volume_socket(scene.world)
    if sock is not None:
        medium, issues = read_volume(sock)
        for msg in issues:
            warn(f"world '{scene.world.name}': {msg}")
        if medium is not None:
            ir["media"].append(dict(medium, name=f"world '{scene.world.name}'"))
            ir["world_medium"] = len(ir["media"]) - 1
    if not ir["media"]:
        del ir["media"]
    win = window or render_window(scene)
    if camera is None:
        cam = scene.camera.evaluated_get(depsgraph) if scene.camera else None
        camera = export_camera(scene, cam, win, warn)
    ir["camera"] = camera
    ir["film"] = {"width": win.w, "height": win.h}
    if getattr(scene.render, "film_transparent", False):
        ir["film"]["transparent"] = True
    counts = {
        "meshes": len(ir["meshes"]), "instances": n_inst, "lights": len(ir["lights"]),
        "materials": len(ir["materials"]), "textures": len(ir["textures"]),
        "media": len(ir.get("media", [])),
        "triangles": sum(len(m["indices"]) for m in ir["meshes"]),
        # Shader nodes the shading graphs could not translate (each warned).
        "unsupported_nodes": mat_exporter.stats.get("unsupported", 0),
    }
    return ExportResult(ir=ir, window=win, warnings=warnings, counts=counts)


class _LightGroups:
    """The IR's light groups: the view layer's, each with the members that name it."""

    def __init__(self, view_layer, warn):
        self.warn = warn
        names = [g.name for g in getattr(view_layer, "lightgroups", [])]
        self.ir = [{"name": n} for n in names]
        self.index = {n: i for i, n in enumerate(names)}

    def add(self, id_block, kind: str, index) -> None:
        """``id_block`` (an object or the world) is IR ``kind`` ``index`` (``environment``:
        no index); it joins the group it names."""
        name = getattr(getattr(id_block, "original", id_block), "lightgroup", "") or ""
        if not name or not self.ir:
            return
        i = self.index.get(name)
        if i is None:
            what = "world" if kind == "environment" else "object"
            self.warn(f"{what} '{id_block.name}': light group '{name}' is not one of the view "
                      f"layer's light groups; its light goes to the default group")
            return
        if kind == "environment":
            self.ir[i]["environment"] = True
        else:
            self.ir[i].setdefault(kind, []).append(index)


def _is_holdout(obj, view_layer) -> bool:
    """Whether Cycles holds ``obj`` out: its Object > Visibility > Holdout, or a holdout
    collection of the view layer (as Cycles reads them, ``Object.holdout_get``)."""
    original = getattr(obj, "original", obj)
    try:
        return bool(original.holdout_get(view_layer=view_layer))
    except (AttributeError, TypeError, RuntimeError):
        return bool(getattr(original, "is_holdout", False))


def _object_name(inst) -> str:
    """The name of an instance's Cryptomatte object matte, as Cycles names it: that of the
    (original, unevaluated) object placed, for instances made by particles, collections and
    geometry nodes too."""
    obj = inst.object
    return obj.original.name if obj.original is not None else obj.name


def _object_medium(obj, mats, media, warn) -> int | None:
    """The IR medium inside ``obj``: that of its first material with a volume."""
    found = []
    for mat in mats:
        m = media.get(mat)
        for msg in media.issues_of(mat):
            warn(f"object '{obj.name}' (material '{mat.name}'): {msg}")
        if m is not None and m not in found:
            found.append(m)
    if len(found) > 1:
        warn(f"object '{obj.name}': materials with different volumes; the core has one medium "
             f"per mesh, uses that of its first volume material")
    return found[0] if found else None


def _check_boundary(obj, shape, matrix_world, warn) -> None:
    if not shape:
        return
    if matrix_world.determinant() < 0:  # a mirroring placement turns the winding inside out
        shape["volume"] = -shape["volume"]
    if not shape["closed"]:
        warn(f"object '{obj.name}': its volume needs a closed mesh (every edge shared by two "
             f"faces); rays may leave the medium wrongly")
    elif shape["volume"] < 0:
        warn(f"object '{obj.name}': its normals point inwards; a volume's boundary needs them "
             f"outwards (Recalculate Outside)")
