//! Checks of the IR's meshes.

use super::Ctx;
use crate::error::Result;
use crate::scene::desc::*;

pub(super) fn validate_mesh(i: usize, m: &MeshDesc, scene: &SceneDesc) -> Result<()> {
    let c = Ctx::new(format!("/meshes/{i}"), &m.name);
    if m.positions.is_empty() {
        return Err(c.err("positions", "mesh has no vertices"));
    }
    if m.indices.is_empty() {
        return Err(c.err("indices", "mesh has no triangles"));
    }
    if m.positions.len() > u32::MAX as usize {
        return Err(c.err("positions", "too many vertices"));
    }
    // The pointers are formatted only for a bad element: a mesh of millions of vertices
    // would otherwise spend most of its validation formatting strings.
    let finite3 = |p: &[f32; 3]| p.iter().all(|v| v.is_finite());
    for (j, p) in m.positions.iter().enumerate() {
        if !finite3(p) {
            c.vec3(&format!("positions/{j}"), p)?;
        }
    }
    let n = m.positions.len() as u32;
    for (j, tri) in m.indices.iter().enumerate() {
        for (k, &v) in tri.iter().enumerate() {
            if v >= n {
                return Err(c.err(
                    &format!("indices/{j}/{k}"),
                    format!("vertex index {v} out of range ({n} vertices)"),
                ));
            }
        }
    }
    if let Some(normals) = &m.normals {
        if normals.len() != m.positions.len() {
            return Err(c.err(
                "normals",
                format!(
                    "has {} entries for {} vertices",
                    normals.len(),
                    m.positions.len()
                ),
            ));
        }
        for (j, nrm) in normals.iter().enumerate() {
            if !finite3(nrm) {
                c.vec3(&format!("normals/{j}"), nrm)?;
            }
        }
    }
    if let Some(uvs) = &m.uvs {
        if uvs.len() != m.positions.len() {
            return Err(c.err(
                "uvs",
                format!(
                    "has {} entries for {} vertices",
                    uvs.len(),
                    m.positions.len()
                ),
            ));
        }
        for (j, uv) in uvs.iter().enumerate() {
            if !(uv[0].is_finite() && uv[1].is_finite()) {
                c.finite(&format!("uvs/{j}/0"), uv[0])?;
                c.finite(&format!("uvs/{j}/1"), uv[1])?;
            }
        }
    }
    if let Some(attrs) = &m.attributes {
        if attrs.len() > crate::geometry::MAX_NAMED_ATTRIBUTES {
            return Err(c.err(
                "attributes",
                format!(
                    "has {} attributes; at most {} per mesh are read",
                    attrs.len(),
                    crate::geometry::MAX_NAMED_ATTRIBUTES
                ),
            ));
        }
        for (name, vals) in attrs {
            if vals.len() != m.positions.len() {
                return Err(c.err(
                    &format!("attributes/{name}"),
                    format!(
                        "has {} entries for {} vertices",
                        vals.len(),
                        m.positions.len()
                    ),
                ));
            }
            for (j, v) in vals.iter().enumerate() {
                for (k, x) in v.iter().enumerate() {
                    if !x.is_finite() {
                        c.finite(&format!("attributes/{name}/{j}/{k}"), *x)?;
                    }
                }
            }
        }
    }
    let nm = scene.materials.len();
    let check_mat = |field: &str, idx: u32| -> Result<()> {
        if (idx as usize) < nm {
            Ok(())
        } else {
            Err(c.err(
                field,
                format!("material index {idx} out of range ({nm} materials)"),
            ))
        }
    };
    match &m.material_indices {
        Some(mi) => {
            if mi.len() != m.indices.len() {
                return Err(c.err(
                    "material_indices",
                    format!("has {} entries for {} triangles", mi.len(), m.indices.len()),
                ));
            }
            for (j, &idx) in mi.iter().enumerate() {
                if idx as usize >= nm {
                    check_mat(&format!("material_indices/{j}"), idx)?;
                }
            }
        }
        None => check_mat("material", m.material)?,
    }
    if let Some(mi) = m.interior_medium {
        if mi as usize >= scene.media.len() {
            return Err(c.err(
                "interior_medium",
                format!(
                    "medium index {mi} out of range ({} media)",
                    scene.media.len()
                ),
            ));
        }
    }
    c.matrix("transform", &m.transform)
}
