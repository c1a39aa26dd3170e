"""Meshes (and anything convertible to one: curves, text, metaballs) -> IR meshes.

The evaluated mesh is triangulated by Blender (``loop_triangles``). Each face corner carries its
position, split normal and UV of the active layer; corners equal in all three are one IR vertex,
and vertices and triangles are put in an order that depends only on their data (``canonical``).
Material slots map to the scene's IR materials per triangle.
"""

from __future__ import annotations

import numpy as np


def matrix_rows(m) -> list:
    """A mathutils 4x4 matrix as four rows (the IR's convention: column vectors)."""
    return [[float(m[r][c]) for c in range(4)] for r in range(4)]


#: Most named attributes one IR mesh carries (the core's MAX_ATTRIBUTES).
MAX_ATTRIBUTES = 4


def _attribute_rgba(mesh, name: str, loop_vert, warn):
    """The attribute ``name`` of ``mesh`` per face corner as linear RGBA (n_loops x 4), or
    None when the mesh has no such attribute. The empty name is the default colour attribute
    (what an unnamed Color Attribute node reads)."""
    if name == "":
        ca = mesh.color_attributes
        name = getattr(ca, "default_color_name", "") or ""
        if not name and len(ca):
            name = ca[max(0, getattr(ca, "render_color_index", 0))].name
    a = mesh.attributes.get(name) if name else None
    if a is None:
        return None
    n = len(a.data)
    if a.data_type in ("FLOAT_COLOR", "BYTE_COLOR"):
        v = np.empty(n * 4, dtype=np.float32)
        a.data.foreach_get("color", v)
        v = v.reshape(-1, 4)
    elif a.data_type in ("FLOAT_VECTOR", "FLOAT2"):
        w = 3 if a.data_type == "FLOAT_VECTOR" else 2
        raw = np.empty(n * w, dtype=np.float32)
        a.data.foreach_get("vector", raw)
        v = np.zeros((n, 4), dtype=np.float32)
        v[:, :w] = raw.reshape(-1, w)
        v[:, 3] = 1.0
    elif a.data_type in ("FLOAT", "INT", "BOOLEAN", "INT8"):
        raw = np.empty(n, dtype=np.float32 if a.data_type == "FLOAT" else np.int32)
        a.data.foreach_get("value", raw)
        v = np.repeat(raw.astype(np.float32)[:, None], 4, axis=1)
        v[:, 3] = 1.0
    else:
        warn(f"attribute '{name}' of mesh '{mesh.name}': type {a.data_type} is not read")
        return None
    if a.domain == "POINT":
        return v[loop_vert]
    if a.domain == "CORNER":
        return v
    if a.domain == "FACE":
        starts = np.empty(len(mesh.polygons), dtype=np.int32)
        mesh.polygons.foreach_get("loop_start", starts)
        totals = np.empty(len(mesh.polygons), dtype=np.int32)
        mesh.polygons.foreach_get("loop_total", totals)
        face = np.empty(len(mesh.loops), dtype=np.int64)
        for f, (s, t) in enumerate(zip(starts, totals)):
            face[s:s + t] = f
        return v[face]
    warn(f"attribute '{name}' of mesh '{mesh.name}': the {a.domain.lower()} domain is not read")
    return None


def mesh_arrays(mesh, check_closed: bool = False, attributes=(), warn=None) -> dict | None:
    """positions, indices, normals, uvs and slot indices (per triangle) of an evaluated mesh;
    with ``check_closed``, also ``closed`` (every edge shared by exactly two triangles) and
    ``volume`` (signed, positive when the winding faces outwards); ``attrs``: the named
    ``attributes`` the mesh has, per vertex as linear RGBA."""
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
    if check_closed:
        tri_verts = loop_vert[tri_loops].reshape(-1, 3).astype(np.int64)
        edges = np.sort(np.concatenate([tri_verts[:, [0, 1]], tri_verts[:, [1, 2]],
                                        tri_verts[:, [2, 0]]]), axis=1)
        _, counts = np.unique(edges[:, 0] * (len(mesh.vertices) + 1) + edges[:, 1],
                              return_counts=True)
        out["closed"] = bool(np.all(counts == 2))
        p = co.reshape(-1, 3).astype(np.float64)[tri_verts]
        out["volume"] = float(np.einsum("ij,ij->", p[:, 0], np.cross(p[:, 1], p[:, 2])) / 6.0)
    # The default UV map is the one active for rendering, as in Cycles.
    uv = next((u for u in mesh.uv_layers if u.active_render), mesh.uv_layers.active)
    if uv is not None:
        uvs = np.empty(n_loops * 2, dtype=np.float32)
        uv.data.foreach_get("uv", uvs)
        out["uvs"] = uvs.reshape(-1, 2)
    attrs = {}
    for name in sorted(attributes):
        v = _attribute_rgba(mesh, name, loop_vert, warn or (lambda m: None))
        if v is None:
            continue
        if len(attrs) == MAX_ATTRIBUTES:
            (warn or (lambda m: None))(
                f"mesh '{mesh.name}': more than {MAX_ATTRIBUTES} attributes are read by its "
                f"materials; '{name}' reads zero")
            continue
        attrs[name] = v
    if attrs:
        out["attrs"] = attrs
    return canonical(out)


def canonical(arrays: dict) -> dict:
    """The same triangles in an order that depends only on their data: corners with equal
    position, normal and UV become one vertex, vertices sorted by their data, each triangle
    rotated to start at its lowest vertex (winding kept), triangles sorted. Blender's evaluated
    mesh may hand the same triangles over in another order from one export to the next; the
    render (BVH, photon paths) follows the order, so this keeps a seed's image the same."""
    cols = [arrays["positions"], arrays["normals"]] + ([arrays["uvs"]] if "uvs" in arrays else [])
    names = list(arrays.get("attrs", {}))
    cols += [arrays["attrs"][n] for n in names]
    data = np.concatenate(cols, axis=1).astype(np.float32)
    data = data + np.float32(0.0)  # -0.0 -> 0.0: equal corners compare equal
    uniq, inverse = np.unique(data, axis=0, return_inverse=True)
    tri = inverse.reshape(-1)[arrays["indices"]]
    k = np.argmin(tri, axis=1)
    tri = np.take_along_axis(tri, (k[:, None] + np.arange(3)[None, :]) % 3, axis=1)
    slots = arrays["slots"]
    order = np.lexsort((tri[:, 2], tri[:, 1], tri[:, 0], slots))
    out = dict(arrays)
    out["positions"] = np.ascontiguousarray(uniq[:, 0:3])
    out["normals"] = np.ascontiguousarray(uniq[:, 3:6])
    c = 6
    if "uvs" in arrays:
        out["uvs"] = np.ascontiguousarray(uniq[:, 6:8])
        c = 8
    if names:
        out["attrs"] = {n: np.ascontiguousarray(uniq[:, c + 4 * k:c + 4 * k + 4])
                        for k, n in enumerate(names)}
    out["indices"] = np.ascontiguousarray(tri[order], dtype=np.int32)
    out["slots"] = np.ascontiguousarray(slots[order])
    return out


def export_mesh(obj, name: str, slot_materials: list[int],
                shape: dict | None = None, attributes=(), warn=None) -> dict | None:
    """The IR mesh of the evaluated object ``obj`` (transform left to the caller), with
    ``slot_materials[i]`` the IR material of slot i. A ``shape`` dict receives ``closed`` and
    ``volume`` (see ``mesh_arrays``): the checks a medium's boundary needs."""
    mesh = obj.to_mesh()
    try:
        if mesh is None:
            return None
        a = mesh_arrays(mesh, check_closed=shape is not None, attributes=attributes,
                        warn=warn)
    finally:
        obj.to_mesh_clear()
    if a is None:
        return None
    if shape is not None:
        shape.update(closed=a.pop("closed"), volume=a.pop("volume"))
    d = {"name": name, "positions": a["positions"], "indices": a["indices"],
         "normals": a["normals"]}
    if "uvs" in a:
        d["uvs"] = a["uvs"]
    if "attrs" in a:
        d["attributes"] = a["attrs"]
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
