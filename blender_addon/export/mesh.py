"""Meshes (and anything convertible to one: curves, text, metaballs) -> IR meshes.

The evaluated mesh is triangulated by Blender (``loop_triangles``). Each face corner becomes one
IR vertex carrying the corner's position, split normal and UV of the active layer; triangles
index corners. Material slots map to the scene's IR materials per triangle.
"""

from __future__ import annotations

import numpy as np


def matrix_rows(m) -> list:
    """A mathutils 4x4 matrix as four rows (the IR's convention: column vectors)."""
    return [[float(m[r][c]) for c in range(4)] for r in range(4)]


def mesh_arrays(mesh) -> dict | None:
    """positions, indices, normals, uvs and slot indices (per triangle) of an evaluated mesh."""
    mesh.calc_loop_triangles()
    n_tri = len(mesh.loop_triangles)
    if n_tri == 0:
        return None
    n_loops = len(mesh.loops)
    tri_loops = np.empty(n_tri * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("loops", tri_loops)
    slots = np.empty(n_tri, dtype=np.int32)
    mesh.loop_triangles.foreach_get("material_index", slots)
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    loop_vert = np.empty(n_loops, dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vert)
    positions = co.reshape(-1, 3)[loop_vert]
    normals = np.empty(n_loops * 3, dtype=np.float32)
    corner = getattr(mesh, "corner_normals", None)  # Blender 4.1+
    if corner is not None:
        corner.foreach_get("vector", normals)
    else:
        mesh.loops.foreach_get("normal", normals)
    out = {
        "positions": positions,
        "indices": tri_loops.reshape(-1, 3),
        "normals": normals.reshape(-1, 3),
        "slots": slots,
    }
    uv = mesh.uv_layers.active
    if uv is not None:
        uvs = np.empty(n_loops * 2, dtype=np.float32)
        uv.data.foreach_get("uv", uvs)
        out["uvs"] = uvs.reshape(-1, 2)
    return out


def export_mesh(obj, name: str, slot_materials: list[int]) -> dict | None:
    """The IR mesh of the evaluated object ``obj`` (transform left to the caller), with
    ``slot_materials[i]`` the IR material of slot i."""
    mesh = obj.to_mesh()
    try:
        if mesh is None:
            return None
        a = mesh_arrays(mesh)
    finally:
        obj.to_mesh_clear()
    if a is None:
        return None
    d = {"name": name, "positions": a["positions"], "indices": a["indices"],
         "normals": a["normals"]}
    if "uvs" in a:
        d["uvs"] = a["uvs"]
    slots = a.pop("slots")
    if not slot_materials:
        slot_materials = [0]
    lut = np.asarray(slot_materials, dtype=np.uint32)
    ids = lut[np.clip(slots, 0, len(lut) - 1)]
    if np.all(ids == ids[0]):
        d["material"] = int(ids[0])
    else:
        d["material_indices"] = ids
    return d
