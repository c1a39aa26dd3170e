//! What the scene says about its subsurface materials before rendering: warnings, each
//! naming the material or the mesh (and, through them, the Blender object or USD prim).
//!
//! - a radius of 0 (every channel): the material renders as its diffuse base;
//! - a negative, NaN or infinite radius channel (that channel renders as the diffuse base), or
//!   one above `MAX_RADIUS` (clamped);
//! - a textured base colour: the walk's colour is one per material, the texture's scale;
//! - a mesh holding the material that is not closed (an edge not shared by exactly two
//!   triangles, vertices matched by position): walks leave through its holes and are lost;
//! - a mesh whose normals point inwards (negative signed volume): walks do not depend on the
//!   winding, but the mesh is likely broken for other renderers.

use super::desc::{ColorInput, MaterialDesc, MeshDesc, SceneDesc};
use crate::materials::subsurface::{MAX_RADIUS, MIN_RADIUS};
use crate::math::Transform;
use std::collections::HashMap;

/// The warnings of `desc`'s subsurface materials and meshes, in material then mesh order.
pub fn warnings(desc: &SceneDesc) -> Vec<String> {
    let mut out = Vec::new();
    let mut active = vec![false; desc.materials.len()];
    for (i, m) in desc.materials.iter().enumerate() {
        let MaterialDesc::Principled(p) = m else {
            continue;
        };
        let Some(ss) = &p.subsurface else { continue };
        let name = if p.name.is_empty() {
            format!("material{i}")
        } else {
            p.name.clone()
        };
        if !(ss.weight.is_finite() && ss.weight > 0.0) {
            continue;
        }
        let r = ss.radius;
        if r.iter().all(|&v| v == 0.0) {
            out.push(format!(
                "material '{name}': subsurface radius 0; it renders as its diffuse base"
            ));
            continue;
        }
        let bad: Vec<String> = r
            .iter()
            .filter(|v| !(v.is_finite() && **v >= 0.0))
            .map(|v| v.to_string())
            .collect();
        if !bad.is_empty() {
            out.push(format!(
                "material '{name}': subsurface radius {:?} has negative or non-finite \
                 channels ({}); they render as the diffuse base",
                r,
                bad.join(", ")
            ));
        }
        if !r.iter().any(|&v| v.is_finite() && v > MIN_RADIUS) {
            out.push(format!(
                "material '{name}': no usable subsurface radius in {r:?}; it renders as its \
                 diffuse base"
            ));
            continue;
        }
        if r.iter().any(|&v| v.is_finite() && v > MAX_RADIUS) {
            out.push(format!(
                "material '{name}': subsurface radius {r:?} above {MAX_RADIUS:e} scene units \
                 is clamped"
            ));
        }
        if ss.color.is_none() && matches!(p.base_color, ColorInput::Texture { .. }) {
            out.push(format!(
                "material '{name}': a textured base colour under subsurface scattering; the \
                 walk takes the texture's scale as its colour"
            ));
        }
        active[i] = true;
    }
    if !active.contains(&true) {
        return out;
    }
    for (i, m) in desc.meshes.iter().enumerate() {
        let is_active = |k: &u32| active.get(*k as usize) == Some(&true);
        let uses = match &m.material_indices {
            Some(mi) => mi.iter().any(is_active),
            None => is_active(&m.material),
        };
        if !uses {
            continue;
        }
        let name = if m.name.is_empty() {
            format!("mesh{i}")
        } else {
            m.name.clone()
        };
        match closed_volume(m) {
            None => out.push(format!(
                "mesh '{name}': a subsurface material needs a closed mesh (every edge shared \
                 by two faces); light that walks out through its holes is lost"
            )),
            Some(v) if v < 0.0 => out.push(format!(
                "mesh '{name}': its normals point inwards under a subsurface material; it \
                 renders the same, but check the mesh (Blender: Recalculate Outside)"
            )),
            Some(_) => {}
        }
    }
    out
}

/// The signed volume of `m` in world space (positive for outward normals), or `None` when
/// it is not closed: some edge, with vertices matched by position, is not shared by exactly
/// two triangles.
fn closed_volume(m: &MeshDesc) -> Option<f64> {
    let key = |i: u32| m.positions.get(i as usize).map(|p| p.map(f32::to_bits));
    let mut edges: HashMap<([u32; 3], [u32; 3]), u32> = HashMap::new();
    let mut volume = 0.0f64;
    for t in &m.indices {
        let k = [key(t[0])?, key(t[1])?, key(t[2])?];
        for e in 0..3 {
            let (a, b) = (k[e], k[(e + 1) % 3]);
            let edge = if a <= b { (a, b) } else { (b, a) };
            *edges.entry(edge).or_insert(0) += 1;
        }
        let p = |i: u32| {
            let v = m.positions[i as usize];
            glam::DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
        };
        volume += p(t[0]).dot(p(t[1]).cross(p(t[2]))) / 6.0;
    }
    if m.indices.is_empty() || edges.values().any(|&c| c != 2) {
        return None;
    }
    // A mirroring transform turns the winding inside out.
    let mirrored = Transform::from_rows(&m.transform).is_some_and(|t| t.swaps_handedness());
    Some(if mirrored { -volume } else { volume })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scene_without_subsurface_has_no_warnings() {
        assert!(warnings(&SceneDesc::default()).is_empty());
    }
}
