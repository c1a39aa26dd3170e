//! Procedural closed meshes for defaults, tests and benchmarks. Every mesh here shares
//! its vertices between neighbouring triangles and winds them outwards, so
//! `(p1 − p0) × (p2 − p0)` points out of the solid.

use super::mesh::MeshGeom;
use glam::Vec3;

/// Closed UV sphere.
///
/// | parameter | meaning |
/// |-----------|---------|
/// | `center`, `radius` | the sphere |
/// | `rings` | latitude bands (at least 2) |
/// | `segments` | longitude slices (at least 3) |
///
/// Each pole is a single vertex; `2·segments·(rings − 1)` triangles.
pub fn sphere(center: Vec3, radius: f32, rings: u32, segments: u32) -> MeshGeom {
    sphere_displaced(center, radius, rings, segments, |_| 0.0)
}

/// Closed UV sphere whose radius is scaled by `1 + displace(unit_direction)`.
pub fn sphere_displaced(
    center: Vec3,
    radius: f32,
    rings: u32,
    segments: u32,
    displace: impl Fn(Vec3) -> f32,
) -> MeshGeom {
    let rings = rings.max(2);
    let segments = segments.max(3);
    let mut positions = Vec::with_capacity((segments * (rings - 1) + 2) as usize);
    let put = |d: Vec3| center + d * radius * (1.0 + displace(d));
    positions.push(put(Vec3::Z));
    for r in 1..rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..segments {
            let phi = 2.0 * std::f32::consts::PI * s as f32 / segments as f32;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            positions.push(put(d));
        }
    }
    positions.push(put(-Vec3::Z));
    let south = positions.len() as u32 - 1;
    let at = |r: u32, s: u32| 1 + (r - 1) * segments + (s % segments);
    let mut indices = Vec::with_capacity((2 * segments * (rings - 1)) as usize);
    for s in 0..segments {
        indices.push([0, at(1, s), at(1, s + 1)]);
    }
    for r in 1..rings - 1 {
        for s in 0..segments {
            let (a, b, c, d) = (at(r, s), at(r + 1, s), at(r + 1, s + 1), at(r, s + 1));
            indices.push([a, b, c]);
            indices.push([a, c, d]);
        }
    }
    for s in 0..segments {
        indices.push([south, at(rings - 1, s + 1), at(rings - 1, s)]);
    }
    let material_ids = vec![0; indices.len()];
    MeshGeom {
        positions,
        indices,
        normals: None,
        uvs: None,
        material_ids,
        attributes: Vec::new(),
    }
}

/// Closed axis-aligned box of 12 triangles between `min` and `max`.
pub fn cuboid(min: Vec3, max: Vec3) -> MeshGeom {
    let positions: Vec<Vec3> = (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            )
        })
        .collect();
    // Faces as quads (counter-clockwise seen from outside).
    let quads = [
        [0, 2, 3, 1], // -z
        [4, 5, 7, 6], // +z
        [0, 1, 5, 4], // -y
        [2, 6, 7, 3], // +y
        [0, 4, 6, 2], // -x
        [1, 3, 7, 5], // +x
    ];
    let mut indices = Vec::with_capacity(12);
    for q in quads {
        indices.push([q[0], q[1], q[2]]);
        indices.push([q[0], q[2], q[3]]);
    }
    MeshGeom {
        positions,
        indices,
        normals: None,
        uvs: None,
        material_ids: vec![0; 12],
        attributes: Vec::new(),
    }
}

/// Height field over the square `[x0, x0 + size] × [y0, y0 + size]`, `n × n` cells, two
/// triangles per cell, facing +z (an open surface).
pub fn terrain(x0: f32, y0: f32, size: f32, n: u32, height: impl Fn(f32, f32) -> f32) -> MeshGeom {
    let n = n.max(1);
    let mut positions = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
    for j in 0..=n {
        for i in 0..=n {
            let x = x0 + size * i as f32 / n as f32;
            let y = y0 + size * j as f32 / n as f32;
            positions.push(Vec3::new(x, y, height(x, y)));
        }
    }
    let at = |i: u32, j: u32| j * (n + 1) + i;
    let mut indices = Vec::with_capacity((2 * n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            indices.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            indices.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    let material_ids = vec![0; indices.len()];
    MeshGeom {
        positions,
        indices,
        normals: None,
        uvs: None,
        material_ids,
        attributes: Vec::new(),
    }
}
