"""UsdGeom.Mesh -> IR mesh: n-gon triangulation (ear clipping in the polygon's plane, correct
for concave polygons), orientation, normals and UVs of every interpolation (faceVarying and
uniform data split vertices), GeomSubset material ids, subdivision cages."""

from __future__ import annotations

import numpy as np
from pxr import UsdGeom, UsdShade

_INTERP_OK = ("constant", "uniform", "varying", "vertex", "faceVarying")


def triangulate_polygon(pts2: np.ndarray) -> list[tuple[int, int, int]]:
    """Ear clipping of one simple polygon given in 2D, counter-clockwise or not. Returns
    triangles as local corner indices, wound as the input."""
    n = len(pts2)
    if n == 3:
        return [(0, 1, 2)]
    area2 = 0.0
    for i in range(n):
        x0, y0 = pts2[i]
        x1, y1 = pts2[(i + 1) % n]
        area2 += x0 * y1 - x1 * y0
    sign = 1.0 if area2 >= 0 else -1.0
    idx = list(range(n))
    tris: list[tuple[int, int, int]] = []

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    guard = 0
    while len(idx) > 3 and guard < 4 * n * n:
        guard += 1
        m = len(idx)
        clipped = False
        for k in range(m):
            ia, ib, ic = idx[(k - 1) % m], idx[k], idx[(k + 1) % m]
            a, b, c = pts2[ia], pts2[ib], pts2[ic]
            if sign * cross(a, b, c) <= 1e-12 * max(1.0, abs(area2)):
                continue  # reflex or degenerate corner
            inside = False
            for j in idx:
                if j in (ia, ib, ic):
                    continue
                p = pts2[j]
                if (sign * cross(a, b, p) >= 0 and sign * cross(b, c, p) >= 0
                        and sign * cross(c, a, p) >= 0):
                    inside = True
                    break
            if inside:
                continue
            tris.append((ia, ib, ic))
            idx.pop(k)
            clipped = True
            break
        if not clipped:  # degenerate (collinear or self-intersecting): fan the rest
            break
    for k in range(1, len(idx) - 1):
        tris.append((idx[0], idx[k], idx[k + 1]))
    return tris


def _project(poly: np.ndarray) -> np.ndarray:
    """Projects a 3D polygon onto its plane (Newell normal)."""
    nrm = np.zeros(3)
    for i in range(len(poly)):
        a, b = poly[i], poly[(i + 1) % len(poly)]
        nrm += np.array([(a[1] - b[1]) * (a[2] + b[2]), (a[2] - b[2]) * (a[0] + b[0]),
                         (a[0] - b[0]) * (a[1] + b[1])])
    ln = np.linalg.norm(nrm)
    if ln == 0:
        return poly[:, :2]
    nrm /= ln
    u = np.cross(nrm, [1.0, 0, 0] if abs(nrm[0]) < 0.9 else [0, 1.0, 0])
    u /= np.linalg.norm(u)
    v = np.cross(nrm, u)
    return np.stack([poly @ u, poly @ v], axis=1)


def triangulate(points: np.ndarray, counts: np.ndarray, fvi: np.ndarray):
    """Triangles as (corner indices into faceVertexIndices (T,3), face of each triangle (T,)).
    Triangles and convex polygons are fanned (vectorised); concave ones are ear-clipped."""
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
    corners, faces = [], []
    for k in np.unique(counts):
        k = int(k)
        sel = np.nonzero(counts == k)[0]
        base = starts[sel]
        if k == 3:
            corners.append(base[:, None] + np.arange(3))
            faces.append(sel)
            continue
        ring = base[:, None] + np.arange(k)  # (F,k) corner ids
        poly = points[fvi[ring]]  # (F,k,3)
        e0 = poly - np.roll(poly, 1, axis=1)
        e1 = np.roll(poly, -1, axis=1) - poly
        c = np.cross(e0, e1)  # corner turn vectors
        nrm = c.sum(axis=1)
        d = np.einsum("fkc,fc->fk", c, nrm)
        convex = np.all(d >= -1e-12 * np.maximum(1.0, np.abs(d).max(axis=1, keepdims=True)), axis=1)
        cv = np.nonzero(convex)[0]
        if len(cv):
            fan = np.stack([np.zeros(k - 2, int), np.arange(1, k - 1), np.arange(2, k)], axis=1)
            corners.append(ring[cv][:, fan].reshape(-1, 3))
            faces.append(np.repeat(sel[cv], k - 2))
        for f in np.nonzero(~convex)[0]:
            local = triangulate_polygon(_project(poly[f]))
            corners.append(np.array([[ring[f][a], ring[f][b], ring[f][c]] for a, b, c in local]))
            faces.append(np.full(len(local), sel[f]))
    if not corners:
        return np.zeros((0, 3), np.int64), np.zeros(0, np.int64)
    corners = np.concatenate(corners).astype(np.int64)
    faces = np.concatenate(faces).astype(np.int64)
    order = np.argsort(faces, kind="stable")  # triangles in face order
    return corners[order], faces[order]


def _primvar(mesh, name, time, diag, prim):
    """(values ndarray, indices or None, interpolation) of an authored primvar, or None."""
    pv = UsdGeom.PrimvarsAPI(mesh.GetPrim()).GetPrimvar(name)
    if not pv or not pv.HasAuthoredValue():
        return None
    vals = pv.Get(time)
    if vals is None:
        return None
    idx = pv.GetIndices(time) if pv.IsIndexed() else None
    try:
        values = np.array(vals, dtype=np.float64)
    except (TypeError, ValueError):
        raise diag.error(prim, f"primvars:{name} of type `{pv.GetTypeName()}` is not numeric") from None
    return values, (np.array(idx, np.int64) if idx is not None else None), pv.GetInterpolation()


def _expand(values, indices, interp, n_points, n_faces, n_corners, what, prim, diag):
    """Per-element keys for a primvar: (data rows, key per corner function). Returns a function
    mapping (corner ids, face ids, point ids) to rows of ``data``, or None when unusable."""
    if indices is not None:
        if len(indices) and (indices.min() < 0 or indices.max() >= len(values)):
            raise diag.error(prim, f"{what}: indices out of range (0..{len(values) - 1})")
        n_elem = len(indices)
    else:
        n_elem = len(values)
    expected = {"constant": 1, "uniform": n_faces, "varying": n_points, "vertex": n_points,
                "faceVarying": n_corners}.get(interp)
    if expected is None:
        diag.warn(prim, f"{what}: unknown interpolation `{interp}`, ignored")
        return None
    if n_elem < expected:
        diag.warn(prim, f"{what}: {n_elem} values for {interp} interpolation, expected {expected}; ignored")
        return None
    if not np.all(np.isfinite(values)):
        bad = int(np.argwhere(~np.isfinite(values))[0][0])
        raise diag.error(prim, f"{what}[{bad}] is not finite")

    def rows(corner, face, point):
        e = {"constant": np.zeros_like(corner), "uniform": face, "faceVarying": corner}.get(interp, point)
        return indices[e] if indices is not None else e

    return rows


#: Most primvars one IR mesh carries per vertex (the core's MAX_ATTRIBUTES).
MAX_ATTRIBUTES = 4


def read_mesh(prim, time, diag, material_of, attribute_names=()):
    """The IR mesh of a UsdGeom.Mesh, in the prim's local space, or None if it has no faces.

    ``material_of(prim)`` gives the IR material index of a prim's bound material;
    ``attribute_names`` (filled as materials are read) the primvars some material reads per
    vertex: those the mesh has become its ``attributes`` (linear RGBA per vertex).
    """
    mesh = UsdGeom.Mesh(prim)
    pts = mesh.GetPointsAttr().Get(time)
    counts = mesh.GetFaceVertexCountsAttr().Get(time)
    fvi = mesh.GetFaceVertexIndicesAttr().Get(time)
    if pts is None or counts is None or fvi is None:
        missing = [n for n, v in (("points", pts), ("faceVertexCounts", counts),
                                  ("faceVertexIndices", fvi)) if v is None]
        if len(missing) == 3 or (pts is not None and len(pts) == 0):
            diag.warn(prim, "mesh has no geometry; skipped")
            return None
        raise diag.error(prim, f"mesh lacks {', '.join(missing)}")
    points = np.array(pts, dtype=np.float64).reshape(-1, 3)
    counts = np.array(counts, dtype=np.int64)
    fvi = np.array(fvi, dtype=np.int64)
    if len(counts) == 0:
        diag.warn(prim, "mesh has no faces; skipped")
        return None
    if not np.all(np.isfinite(points)):
        bad = int(np.argwhere(~np.isfinite(points))[0][0])
        raise diag.error(prim, f"points[{bad}] is not finite ({points[bad].tolist()})")
    if np.any(counts < 3):
        bad = int(np.argmax(counts < 3))
        raise diag.error(prim, f"faceVertexCounts[{bad}] = {counts[bad]}: a face needs at least 3 vertices")
    if counts.sum() != len(fvi):
        raise diag.error(prim, f"faceVertexCounts sum to {counts.sum()} but there are {len(fvi)} faceVertexIndices")
    if len(fvi) and (fvi.min() < 0 or fvi.max() >= len(points)):
        bad = int(np.argmax((fvi < 0) | (fvi >= len(points))))
        raise diag.error(prim, f"faceVertexIndices[{bad}] = {fvi[bad]} out of range ({len(points)} points)")

    corners, tri_face = triangulate(points, counts, fvi)
    if mesh.GetOrientationAttr().Get(time) == UsdGeom.Tokens.leftHanded:
        corners = corners[:, [0, 2, 1]]
    n_faces, n_corners = len(counts), len(fvi)
    corner_ids = corners.reshape(-1)
    face_ids = np.repeat(tri_face, 3)
    point_ids = fvi[corner_ids]
    # The materials first: reading them names the primvars they read per vertex.
    material, material_ids = subset_materials(prim, n_faces, tri_face, diag, material_of)

    # Normals: primvars:normals wins over normals.
    nrm_rows = nrm_data = None
    pv = _primvar(mesh, "normals", time, diag, prim)
    if pv is None:
        attr = mesh.GetNormalsAttr()
        v = attr.Get(time) if attr.HasAuthoredValue() else None
        if v is not None and len(v):
            pv = (np.array(v, np.float64), None, mesh.GetNormalsInterpolation())
    if pv is not None:
        vals, ind, interp = pv
        f = _expand(vals.reshape(-1, 3), ind, interp, len(points), n_faces, n_corners, "normals", prim, diag)
        if f is not None:
            nrm_data, nrm_rows = vals.reshape(-1, 3), f(corner_ids, face_ids, point_ids)

    uv_rows = uv_data = None
    st_name = "st"
    pv = _primvar(mesh, st_name, time, diag, prim)
    if pv is None:
        for cand in UsdGeom.PrimvarsAPI(prim).GetPrimvars():
            if cand.GetTypeName() == "texCoord2f[]" and cand.HasAuthoredValue():
                pv = _primvar(mesh, cand.GetPrimvarName(), time, diag, prim)
                st_name = str(cand.GetPrimvarName())
                break
    if pv is not None:
        vals, ind, interp = pv
        f = _expand(vals.reshape(-1, 2), ind, interp, len(points), n_faces, n_corners, f"primvars:{st_name}", prim, diag)
        if f is not None:
            uv_data, uv_rows = vals.reshape(-1, 2), f(corner_ids, face_ids, point_ids)

    # Primvars read per vertex, as RGBA rows.
    attrs = []  # (name, data rows, row per corner)
    for name in sorted(attribute_names):
        pv = _primvar(mesh, name, time, diag, prim) if name else None
        if pv is None:
            continue
        vals, ind, interp = pv
        width = vals.shape[1] if vals.ndim == 2 else 1
        if width > 4:
            diag.warn(prim, f"primvars:{name}: {width} components; not read")
            continue
        data = np.zeros((len(vals), 4))
        flat = vals.reshape(len(vals), width)
        data[:, :width] = flat
        if width == 1:
            data[:, 1:3] = flat
        if width < 4:
            data[:, 3] = 1.0
        f = _expand(data, ind, interp, len(points), n_faces, n_corners, f"primvars:{name}", prim, diag)
        if f is None:
            continue
        if len(attrs) == MAX_ATTRIBUTES:
            diag.warn(prim, f"more than {MAX_ATTRIBUTES} primvars are read per vertex; "
                            f"primvars:{name} reads zero")
            continue
        attrs.append((name, data, f(corner_ids, face_ids, point_ids)))

    # One vertex per distinct (point, normal row, uv row, primvar rows) used by a corner.
    keys = [point_ids]
    if nrm_rows is not None:
        keys.append(nrm_rows)
    if uv_rows is not None:
        keys.append(uv_rows)
    keys += [rows for _, _, rows in attrs]
    attributes = {}
    if len(keys) == 1:
        positions = points
        indices = point_ids.reshape(-1, 3)
        vert_point = np.arange(len(points))
        normals = uvs = None
    else:
        uniq, inverse = np.unique(np.stack(keys, axis=1), axis=0, return_inverse=True)
        inverse = inverse.reshape(-1)
        vert_point = uniq[:, 0]
        positions = points[vert_point]
        indices = inverse.reshape(-1, 3)
        col = 1
        normals = uvs = None
        if nrm_rows is not None:
            normals = nrm_data[uniq[:, col]]
            col += 1
        if uv_rows is not None:
            uvs = uv_data[uniq[:, col]]
            col += 1
        for name, data, _ in attrs:
            attributes[name] = data[uniq[:, col]].astype(np.float32)
            col += 1

    scheme = mesh.GetSubdivisionSchemeAttr().Get(time)
    if scheme not in (None, UsdGeom.Tokens.none):
        diag.warn(prim, f"subdivisionScheme `{scheme}`: rendered as the cage with smooth normals")
        if normals is None:
            normals = smooth_normals(positions, indices, vert_point)

    if normals is not None:
        ln = np.linalg.norm(normals, axis=1, keepdims=True)
        zero = ln[:, 0] < 1e-20
        if np.any(zero):
            diag.warn(prim, f"{int(zero.sum())} zero-length normals replaced")
            normals = np.where(zero[:, None], smooth_normals(positions, indices, vert_point), normals)
            ln = np.linalg.norm(normals, axis=1, keepdims=True)
        normals = normals / np.maximum(ln, 1e-20)

    if not mesh.GetDoubleSidedAttr().Get(time):
        pass  # surfaces are shaded on both sides, as Cycles does; recorded in the stats

    return {
        "name": str(prim.GetPath()),
        "positions": positions.astype(np.float32),
        "indices": indices.astype(np.uint32),
        "normals": None if normals is None else normals.astype(np.float32),
        "uvs": None if uvs is None else uvs.astype(np.float32),
        "material": material,
        "material_indices": material_ids,
        **({"attributes": attributes} if attributes else {}),
    }


def smooth_normals(positions, indices, vert_point):
    """Area-weighted vertex normals, shared by every vertex split from the same point."""
    p = positions[indices]
    fn = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    acc = np.zeros((int(vert_point.max()) + 1, 3))
    for k in range(3):
        np.add.at(acc, vert_point[indices[:, k]], fn)
    n = acc[vert_point]
    ln = np.linalg.norm(n, axis=1, keepdims=True)
    return np.where(ln > 1e-20, n / np.maximum(ln, 1e-20), np.array([0.0, 0.0, 1.0]))


def subset_materials(prim, n_faces, tri_face, diag, material_of):
    """(material of the mesh, per-triangle material ids or None) from the mesh's binding and
    its GeomSubsets of family `materialBind`."""
    base = material_of(prim)
    subsets = UsdGeom.Subset.GetGeomSubsets(UsdGeom.Imageable(prim), UsdGeom.Tokens.face, "materialBind")
    if not subsets:
        return base, None
    face_mat = np.full(n_faces, base, dtype=np.int64)
    any_set = False
    for s in subsets:
        idx = np.array(s.GetIndicesAttr().Get() or [], dtype=np.int64)
        if len(idx) and (idx.min() < 0 or idx.max() >= n_faces):
            raise diag.error(s.GetPrim(), f"GeomSubset indices out of range ({n_faces} faces)")
        bound, _ = UsdShade.MaterialBindingAPI(s.GetPrim()).ComputeBoundMaterial()
        if not bound:
            continue
        face_mat[idx] = material_of(s.GetPrim())
        any_set = True
    if not any_set:
        return base, None
    return base, face_mat[tri_face].astype(np.uint32)
