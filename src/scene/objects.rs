//! What shading graphs read of the object a point lies on: object space, the texture space
//! (Generated coordinates) and Object Info.

use super::desc::SceneDesc;
use crate::geometry::Accel;
use crate::materials::graph::point::ObjectCoords;
use crate::materials::Material;
use glam::Vec3;

/// A hash of `s` in [0, 1): Object Info's Random for an object of that name.
fn name_random(s: &str) -> f32 {
    let mut h: u32 = 0x811c_9dc5;
    for b in s.bytes() {
        h ^= b as u32;
        h = h.wrapping_mul(0x0100_0193);
    }
    (crate::sampling::mix64(h as u64) >> 40) as f32 / (1u64 << 24) as f32
}

/// Per instance of `accel`, the coordinates graphs read; empty when no graph reads them.
pub fn object_coords(
    _desc: &SceneDesc,
    accel: &Accel,
    materials: &[Material],
    names: &[String],
) -> Vec<ObjectCoords> {
    let needed = materials
        .iter()
        .any(|m| matches!(m, Material::Graph(g) if g.needs_object));
    if !needed {
        return Vec::new();
    }
    // The texture space of each mesh: its bounding box, in object space.
    let spaces: Vec<(Vec3, Vec3)> = accel
        .meshes()
        .iter()
        .map(|m| {
            let (lo, hi) = m.positions.iter().fold(
                (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            );
            ObjectCoords::texture_space(lo, hi)
        })
        .collect();
    accel
        .instances()
        .iter()
        .enumerate()
        .map(|(i, inst)| {
            let (loc, size) = spaces
                .get(inst.mesh as usize)
                .copied()
                .unwrap_or((Vec3::ZERO, Vec3::ONE));
            ObjectCoords {
                to_object: inst.transform.inv,
                random: names.get(i).map_or(0.0, |n| name_random(n)),
                index: 0.0,
                location: inst.transform.point(Vec3::ZERO),
                ..ObjectCoords::default()
            }
            .with_texture_space(loc, size)
        })
        .collect()
}
