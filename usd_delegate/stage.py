"""Walks a USD stage and assembles the scene IR (a dict, mesh arrays as numpy)."""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import numpy as np
from pxr import Sdf, Tf, Usd, UsdGeom, UsdLux

from . import camera as camera_mod
from .diagnostics import Diagnostics, UsdImportError
from .instancing import point_instancer, proxy_prototype
from .lights import read_light
from . import shading_graph
from .materials import MaterialTable
from .mesh import read_mesh
from .textures import TextureTable
from .xform import ir_matrix, to_numpy

_LIGHT_TYPES = ("RectLight", "DiskLight", "SphereLight", "CylinderLight", "DistantLight",
                "DomeLight", "DomeLight_1", "GeometryLight", "PortalLight", "MeshLight")
_IGNORED = ("Xform", "Scope", "", "Material", "Shader", "NodeGraph", "GeomSubset", "Camera",
            "PluginLightFilter", "RenderSettings", "RenderProduct", "RenderVar")


@dataclass
class ImportResult:
    ir: dict
    diagnostics: Diagnostics
    stats: dict = field(default_factory=dict)

    def ir_json_ready(self) -> dict:
        """The IR with numpy arrays as lists (for ``json.dumps``)."""
        def conv(v):
            if isinstance(v, np.ndarray):
                return v.tolist()
            if isinstance(v, dict):
                return {k: conv(x) for k, x in v.items() if x is not None}
            if isinstance(v, list):
                return [conv(x) for x in v]
            if isinstance(v, np.generic):
                return v.item()
            return v
        return conv(self.ir)


def _tf_detail(e) -> str:
    """The message of the first error in a ``Tf.ErrorException``."""
    for ln in str(e).splitlines():
        if " : '" in ln:
            detail = ln.split(" : '", 1)[1].rstrip("'").strip()
            return detail.replace("pxrInternal_v0_", "").split("__pxrReserved__::")[-1]
    return str(e).strip().splitlines()[-1] if str(e).strip() else "USD error"


def open_stage(path: str):
    if not os.path.isfile(path):
        raise UsdImportError(f"{path}: no such file")
    try:
        stage = Usd.Stage.Open(path)
    except Tf.ErrorException as e:
        raise UsdImportError(f"{path}: cannot open the stage: {_tf_detail(e)}") from None
    if stage is None:
        raise UsdImportError(f"{path}: cannot open the stage")
    return stage


def load_stage(path, frame=None, camera=None, purposes=("render",), strict=False,
               width=None) -> ImportResult:
    """Reads a stage at time code ``frame`` (None: the default time) into the scene IR."""
    path = os.fspath(path)
    stage = open_stage(path)
    return import_stage(stage, frame=frame, camera=camera, purposes=purposes, strict=strict,
                        width=width)


def import_stage(stage, frame=None, camera=None, purposes=("render",), strict=False,
                 width=None) -> ImportResult:
    """The IR of an open stage; malformed data (USD errors included) raises UsdImportError."""
    where = [None]
    try:
        return _import_stage(stage, frame, camera, purposes, strict, width, where)
    except Tf.ErrorException as e:
        raise Diagnostics.error(where[0], _tf_detail(e)) from None


#: The attribute naming a prim's light group: a string primvar, inherited down the namespace
#: (set it on a light, an emissive mesh, a dome light, or a scope above them).
LIGHTGROUP_PRIMVAR = "photonmap:lightgroup"


class LightGroups:
    """The IR's ``lightgroups``: each group a prim names (``primvars:photonmap:lightgroup``)
    with its members, in the order the stage names them. Emitters naming none go to the
    core's ``default`` group."""

    def __init__(self, time):
        self.time = time
        self.ir: list[dict] = []
        self.index: dict[str, int] = {}

    def name_of(self, prim) -> str:
        pv = UsdGeom.PrimvarsAPI(prim).FindPrimvarWithInheritance(LIGHTGROUP_PRIMVAR)
        if not pv or not pv.HasAuthoredValue():
            return ""
        v = pv.Get(self.time)
        if not isinstance(v, str):
            raise Diagnostics.error(prim, f"primvars:{LIGHTGROUP_PRIMVAR} must be a string, "
                                          f"got {type(v).__name__}")
        v = v.strip()
        if v and not all(c.isascii() and (c.isalnum() or c in "_-") for c in v):
            raise Diagnostics.error(prim, f"primvars:{LIGHTGROUP_PRIMVAR} `{v}` is not a light "
                                          f"group name: letters, digits, `_` and `-` only")
        return v

    def join(self, prim, kind: str, index) -> None:
        name = self.name_of(prim)
        if not name:
            return
        if name not in self.index:
            self.index[name] = len(self.ir)
            self.ir.append({"name": name})
        g = self.ir[self.index[name]]
        if kind == "environment":
            g["environment"] = True
        else:
            g.setdefault(kind, []).append(int(index))


def _import_stage(stage, frame, camera, purposes, strict, width, where) -> ImportResult:
    diag = Diagnostics(strict)
    time = Usd.TimeCode.Default() if frame is None else Usd.TimeCode(float(frame))
    purposes = [p for p in (purposes or []) if p]
    allowed = {"default", *purposes}
    up_axis = str(UsdGeom.GetStageUpAxis(stage))
    mpu = float(UsdGeom.GetStageMetersPerUnit(stage))
    xcache = UsdGeom.XformCache(time)
    textures = TextureTable(diag)
    materials = MaterialTable(diag, textures, time)
    meshes: list[dict] = []
    instances: list[dict] = []
    lights: list[dict] = []
    env = None
    stats = {"prims_read": 0, "meshes": 0, "triangles": 0, "instances": 0, "lights": 0,
             "single_sided_meshes": 0}
    proto_mesh: dict[str, tuple[int, np.ndarray]] = {}
    groups = LightGroups(time)

    def add_mesh(prim, local: np.ndarray):
        m = read_mesh(prim, time, diag, materials.index_of, materials.attribute_names)
        if m is None:
            return None
        m["transform"] = ir_matrix(local)
        groups.join(prim, "meshes", len(meshes))
        meshes.append(m)
        stats["meshes"] += 1
        stats["triangles"] += int(len(m["indices"]))
        if not UsdGeom.Mesh(prim).GetDoubleSidedAttr().Get(time):
            stats["single_sided_meshes"] += 1
        return len(meshes) - 1

    def add_instance(mesh_index, world, name):
        instances.append({"name": name, "mesh": int(mesh_index), "transform": ir_matrix(world)})
        stats["instances"] += 1

    def add_mesh_tree(root):
        """Meshes under a PointInstancer prototype root: (mesh index, mesh-to-root-parent)."""
        out = []
        parent = to_numpy(xcache.GetLocalToWorldTransform(root.GetParent())) if root.GetParent() else np.eye(4)
        inv_parent = np.linalg.inv(parent)
        for p in Usd.PrimRange(root, Usd.TraverseInstanceProxies(Usd.PrimAllPrimsPredicate)):
            if p.IsA(UsdGeom.Mesh) and _visible(p):
                key = "pi:" + str(p.GetPath())
                if key not in proto_mesh:
                    local = inv_parent @ to_numpy(xcache.GetLocalToWorldTransform(p))
                    idx = add_mesh(p, local)
                    proto_mesh[key] = (idx, np.eye(4))
                idx = proto_mesh[key][0]
                if idx is not None:
                    out.append((idx, np.eye(4)))
            elif p.IsA(UsdGeom.Gprim) and not p.IsA(UsdGeom.Mesh):
                diag.warn(p, f"unsupported geometry `{p.GetTypeName()}` in a PointInstancer prototype; skipped")
        return out

    def _visible(p):
        img = UsdGeom.Imageable(p)
        return img.ComputeVisibility(time) != UsdGeom.Tokens.invisible

    it = iter(Usd.PrimRange(stage.GetPseudoRoot(), Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)))
    for prim in it:
        if prim.IsPseudoRoot():
            continue
        where[0] = prim
        stats["prims_read"] += 1
        t = prim.GetTypeName()
        if prim.IsA(UsdGeom.Imageable):
            img = UsdGeom.Imageable(prim)
            if img.GetVisibilityAttr().Get(time) == UsdGeom.Tokens.invisible:
                it.PruneChildren()
                continue
            purpose = img.GetPurposeAttr().Get(time)
            if purpose and purpose != "default" and purpose not in allowed:
                it.PruneChildren()
                continue
        if prim.IsA(UsdGeom.PointInstancer):
            point_instancer(prim, xcache, time, diag, add_mesh_tree, add_instance, stats)
            it.PruneChildren()
            continue
        if prim.IsA(UsdGeom.Mesh):
            proto = proxy_prototype(prim)
            world = to_numpy(xcache.GetLocalToWorldTransform(prim))
            if proto is None:
                add_mesh(prim, world)
            else:
                key = str(proto.GetPath())
                if key not in proto_mesh:
                    local = to_numpy(xcache.GetLocalToWorldTransform(proto))
                    # Bindings are read on the proxy (they may come from outside the prototype).
                    idx = add_mesh(prim, local)
                    if idx is not None:
                        meshes[idx]["name"] = str(prim.GetPath())
                    proto_mesh[key] = (idx, local)
                idx, local = proto_mesh[key]
                if idx is not None:
                    groups.join(prim, "instances", len(instances))
                    add_instance(idx, world @ np.linalg.inv(local), str(prim.GetPath()))
            continue
        if t in _LIGHT_TYPES or prim.HasAPI(UsdLux.LightAPI):
            world = to_numpy(xcache.GetLocalToWorldTransform(prim))
            r = read_light(prim, world, time, diag, up_axis, textures)
            if r is None:
                continue
            kind, d = r
            if kind == "environment":
                if env is not None:
                    diag.warn(prim, "more than one dome light: only the first is used")
                else:
                    env = d
                    groups.join(prim, "environment", None)
            else:
                groups.join(prim, "lights", len(lights))
                lights.append(d)
                stats["lights"] += 1
            continue
        if prim.IsA(UsdGeom.Gprim):
            diag.warn(prim, f"unsupported geometry `{t}`; skipped (convert it to a Mesh)")
            continue
        if t in ("Volume", "OpenVDBAsset", "Field3DAsset"):
            diag.warn(prim, f"`{t}` is not supported; skipped")
            it.PruneChildren()
            continue
        if prim.IsA(UsdGeom.Xformable) or t in _IGNORED or prim.IsA(UsdGeom.Imageable):
            continue
        if t:
            diag.warn(prim, f"unsupported prim type `{t}`; skipped")

    # Meshes referenced by instances must be prototypes only: instanced meshes are read once,
    # in prototype space, and drawn only through their instances.
    where[0] = None
    cam_prim = camera_mod.find_camera(stage, camera, diag)
    where[0] = cam_prim
    if cam_prim is not None:
        cam, film = camera_mod.read_camera(cam_prim, xcache, time, diag, width)
        stats["camera"] = str(cam_prim.GetPath())
    else:
        cam, film = camera_mod.default_camera(stage, time, purposes, up_axis, diag)
        stats["camera"] = None
    if not meshes and not lights and env is None:
        diag.warn(None, "the stage has no supported geometry or lights")
    emissive = any(m.get("type") == "emission" or m.get("emission_strength", 0) > 0
                   or (m.get("type") == "graph" and shading_graph.emits(m))
                   for m in materials.materials)
    if not lights and env is None and not emissive:
        diag.warn(None, "the stage has no supported lights: the image will be black")
    ir = {"camera": cam, "film": film, "meshes": meshes, "instances": instances,
          "materials": materials.materials or [{"type": "diffuse", "name": "default"}],
          "textures": textures.textures, "lights": lights}
    if env is not None:
        ir["environment"] = env
    if groups.ir:
        ir["lightgroups"] = groups.ir
        stats["lightgroups"] = [g["name"] for g in groups.ir]
    stats.update({
        "materials": len(ir["materials"]), "textures": len(textures.textures),
        "meters_per_unit": mpu, "up_axis": up_axis,
        "time_code": None if frame is None else float(frame),
        "warnings": len(diag.warnings), "notes": len(diag.notes),
        "messages": diag.messages(),
    })
    diag.finish()
    return ImportResult(ir=ir, diagnostics=diag, stats=stats)
