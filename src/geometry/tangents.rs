//! Per-vertex tangent frames for tangent-space normal maps, after MikkTSpace (the frames
//! Blender computes for its Normal Map node): each triangle's tangent and bitangent from its
//! UV derivatives, projected onto each corner's shading normal, summed over the triangles
//! that share a vertex weighted by the corner's angle, and normalised; the bitangent's sign
//! is the side on which the summed bitangent lies. Vertices here are already split where
//! position, normal or UV differ, as MikkTSpace splits them.

use super::mesh::{attribute_key, MeshGeom};
use glam::{Vec3, Vec4};

/// The name under which a mesh carries its tangents: `xyz` the unit tangent in object space,
/// `w` the bitangent's sign (+1 or -1).
pub const TANGENT_ATTRIBUTE: &str = ".tangent";

/// The key of [`TANGENT_ATTRIBUTE`].
pub const TANGENT_KEY: u64 = attribute_key(TANGENT_ATTRIBUTE);

/// The name under which a mesh given tangents carries its vertex normals (object space,
/// `w` 0): interpolated and not normalised, the frame's normal as Cycles takes it.
pub const TANGENT_NORMAL_ATTRIBUTE: &str = ".tangent_normal";

/// The key of [`TANGENT_NORMAL_ATTRIBUTE`].
pub const TANGENT_NORMAL_KEY: u64 = attribute_key(TANGENT_NORMAL_ATTRIBUTE);

fn project(v: Vec3, n: Vec3) -> Vec3 {
    (v - n * n.dot(v)).normalize_or_zero()
}

/// The tangents of `mesh`'s vertices, or `None` when it has no UVs. A vertex no triangle
/// with a UV area touches gets a tangent of the normal's frame, sign +1.
pub fn vertex_tangents(mesh: &MeshGeom) -> Option<Vec<Vec4>> {
    let uvs = mesh.uvs.as_ref()?;
    let n_v = mesh.positions.len();
    // Vertices with equal position, normal and UV are one (a mesh may repeat them per face).
    let mut ids = std::collections::HashMap::new();
    let weld: Vec<usize> = (0..n_v)
        .map(|i| {
            let n = mesh.normals.as_ref().and_then(|n| n.get(i)).copied();
            let key = (
                mesh.positions[i].to_array().map(|x| (x + 0.0).to_bits()),
                n.unwrap_or(Vec3::ZERO)
                    .to_array()
                    .map(|x| (x + 0.0).to_bits()),
                uvs.get(i)
                    .copied()
                    .unwrap_or_default()
                    .to_array()
                    .map(|x| (x + 0.0).to_bits()),
            );
            let next = ids.len();
            *ids.entry(key).or_insert(next)
        })
        .collect();
    let mut t_sum = vec![Vec3::ZERO; ids.len()];
    let mut b_sum = vec![Vec3::ZERO; ids.len()];
    let normal = |i: usize, face: Vec3| {
        mesh.normals
            .as_ref()
            .and_then(|n| n.get(i))
            .copied()
            .filter(|n| n.length_squared() > 0.0)
            .map_or(face, |n| n.normalize())
    };
    for tri in &mesh.indices {
        let idx = tri.map(|i| i as usize);
        if idx.iter().any(|&i| i >= n_v || i >= uvs.len()) {
            continue;
        }
        let p = idx.map(|i| mesh.positions[i]);
        let uv = idx.map(|i| uvs[i]);
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
        let area = d1.x * d2.y - d2.x * d1.y;
        if area == 0.0 {
            continue;
        }
        let s = area.signum();
        // Orientation-preserving derivatives dp/du and dp/dv, scaled by |area|.
        let t = (e1 * d2.y - e2 * d1.y) * s;
        let b = (e2 * d1.x - e1 * d2.x) * s;
        let face = e1.cross(e2).normalize_or_zero();
        for k in 0..3 {
            let i = idx[k];
            let n = normal(i, face);
            let a = p[(k + 1) % 3] - p[k];
            let c = p[(k + 2) % 3] - p[k];
            let (a, c) = (project(a, n), project(c, n));
            let angle = a.dot(c).clamp(-1.0, 1.0).acos();
            if !angle.is_finite() {
                continue;
            }
            t_sum[weld[i]] += project(t, n) * angle;
            b_sum[weld[i]] += project(b, n) * angle;
        }
    }
    Some(
        (0..n_v)
            .map(|i| {
                let n = normal(i, Vec3::Z);
                let (t_sum, b_sum) = (t_sum[weld[i]], b_sum[weld[i]]);
                let t = project(t_sum, n);
                if t == Vec3::ZERO {
                    return n.any_orthonormal_vector().extend(1.0);
                }
                let sign = if n.cross(t).dot(b_sum) < 0.0 {
                    -1.0
                } else {
                    1.0
                };
                t.extend(sign)
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    fn quad(uvs: [Vec2; 4]) -> MeshGeom {
        MeshGeom {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            normals: Some(vec![Vec3::Z; 4]),
            uvs: Some(uvs.to_vec()),
            material_ids: vec![0, 0],
            attributes: Vec::new(),
        }
    }

    #[test]
    fn tangent_follows_u_and_sign_follows_v() {
        let uv = |x, y| Vec2::new(x, y);
        let m = quad([uv(0., 0.), uv(1., 0.), uv(1., 1.), uv(0., 1.)]);
        for t in vertex_tangents(&m).unwrap() {
            assert!((t.truncate() - Vec3::X).length() < 1e-6, "{t}");
            assert_eq!(t.w, 1.0);
        }
        // v mirrored: the bitangent points along -y.
        let m = quad([uv(0., 1.), uv(1., 1.), uv(1., 0.), uv(0., 0.)]);
        for t in vertex_tangents(&m).unwrap() {
            assert!((t.truncate() - Vec3::X).length() < 1e-6, "{t}");
            assert_eq!(t.w, -1.0);
        }
        // u along y: the tangent is +y; v along x, mirrored against the normal: sign -1.
        let m = quad([uv(0., 0.), uv(0., 1.), uv(1., 1.), uv(1., 0.)]);
        for t in vertex_tangents(&m).unwrap() {
            assert!((t.truncate() - Vec3::Y).length() < 1e-6, "{t}");
            assert_eq!(t.w, -1.0);
        }
    }

    #[test]
    fn shared_vertex_averages_by_angle_in_the_normals_plane() {
        // Two triangles folded about the y axis share vertices 0 and 2 with one normal.
        let m = MeshGeom {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, -0.5),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(-1.0, 0.0, -0.5),
            ],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            normals: Some(vec![Vec3::Z; 4]),
            uvs: Some(vec![
                Vec2::new(0.5, 0.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(0.5, 1.0),
                Vec2::new(0.0, 0.0),
            ]),
            material_ids: vec![0, 0],
            attributes: Vec::new(),
        };
        let t = vertex_tangents(&m).unwrap();
        for v in [0, 2] {
            assert!((t[v].truncate() - Vec3::X).length() < 1e-5, "{}", t[v]);
            assert!(t[v].truncate().dot(Vec3::Z).abs() < 1e-6);
        }
        assert!(vertex_tangents(&MeshGeom {
            uvs: None,
            ..m.clone()
        })
        .is_none());
    }
}
