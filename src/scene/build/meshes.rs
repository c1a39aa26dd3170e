//! The IR's meshes as geometry: positions, normals, UVs, material indices and attributes,
//! and the tangents a tangent-space Normal Map reads.

use super::v3;
use crate::geometry::MeshGeom;
use crate::scene::desc::*;
use glam::Vec2;

/// Gives `geom` its tangents when one of its materials has a tangent-space Normal Map
/// (`tangent_materials`, by material index) and it has UVs and no tangents of its own.
pub(super) fn with_tangents(geom: &mut MeshGeom, tangent_materials: &[bool]) -> bool {
    let key = crate::geometry::TANGENT_KEY;
    let reads = |id: &u32| {
        tangent_materials
            .get(*id as usize)
            .copied()
            .unwrap_or(false)
    };
    if !geom.material_ids.iter().any(reads) || geom.attributes.iter().any(|(k, _)| *k == key) {
        return false;
    }
    match crate::geometry::vertex_tangents(geom) {
        Some(t) => {
            geom.attributes.push((key, t));
            if let Some(n) = &geom.normals {
                let n = n.iter().map(|n| n.extend(0.0)).collect();
                geom.attributes
                    .push((crate::geometry::TANGENT_NORMAL_KEY, n));
            }
            true
        }
        None => false,
    }
}

pub(super) fn mesh_geom(m: &MeshDesc) -> MeshGeom {
    MeshGeom {
        positions: m.positions.iter().map(|p| v3(*p)).collect(),
        indices: m.indices.clone(),
        normals: m
            .normals
            .as_ref()
            .map(|n| n.iter().map(|v| v3(*v)).collect()),
        uvs: m
            .uvs
            .as_ref()
            .map(|u| u.iter().map(|v| Vec2::from(*v)).collect()),
        material_ids: match &m.material_indices {
            Some(mi) => mi.clone(),
            None => vec![m.material; m.indices.len()],
        },
        attributes: m
            .attributes
            .iter()
            .flatten()
            .map(|(name, vals)| {
                (
                    crate::geometry::attribute_key(name),
                    vals.iter().map(|v| glam::Vec4::from(*v)).collect(),
                )
            })
            .collect(),
    }
}
