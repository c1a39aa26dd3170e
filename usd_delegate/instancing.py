"""Instancing: meshes under instanceable prims (reached with ``Usd.TraverseInstanceProxies``)
and the prototypes of ``UsdGeom.PointInstancer`` become one IR mesh each, placed by IR
`instances` (the mesh data is never copied per instance)."""

from __future__ import annotations

import numpy as np
from pxr import Usd, UsdGeom

from .xform import ir_matrix, to_numpy


def proxy_prototype(prim):
    """The prototype prim behind an instance proxy, or None."""
    if not prim.IsInstanceProxy():
        return None
    return prim.GetPrimInPrototype()


def point_instancer(prim, xcache, time, diag, add_mesh_tree, add_instance, stats):
    """Adds every instance of a PointInstancer. ``add_mesh_tree(root)`` returns a list of
    (IR mesh index, mesh-to-prototype-root matrix) for the meshes under a prototype root."""
    pi = UsdGeom.PointInstancer(prim)
    protos = pi.GetPrototypesRel().GetTargets()
    proto_idx = pi.GetProtoIndicesAttr().Get(time)
    if proto_idx is None or len(proto_idx) == 0:
        diag.warn(prim, "PointInstancer has no protoIndices; nothing instanced")
        return
    proto_idx = np.array(proto_idx, dtype=np.int64)
    if proto_idx.min() < 0 or proto_idx.max() >= len(protos):
        raise diag.error(prim, f"protoIndices out of range ({len(protos)} prototypes)")
    xforms = pi.ComputeInstanceTransformsAtTime(time, time)
    if xforms is None or len(xforms) != len(proto_idx):
        raise diag.error(prim, "cannot compute instance transforms (positions missing or of the wrong length?)")
    mask = pi.ComputeMaskAtTime(time)
    world = to_numpy(xcache.GetLocalToWorldTransform(prim))
    stage = prim.GetStage()
    proto_meshes = []
    for path in protos:
        root = stage.GetPrimAtPath(path)
        if not root:
            raise diag.error(prim, f"prototype `{path}` does not exist")
        proto_meshes.append(add_mesh_tree(root))
    count = 0
    for i, (p, m) in enumerate(zip(proto_idx, xforms)):
        if mask and not mask[i]:
            continue
        inst = world @ to_numpy(m)
        for mesh_index, local in proto_meshes[p]:
            add_instance(mesh_index, inst @ local, f"{prim.GetPath()}[{i}]")
            count += 1
    stats["point_instances"] = stats.get("point_instances", 0) + int(len(proto_idx))
