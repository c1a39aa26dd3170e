//! Triangle meshes in object space, and instances placing them in the world.

use crate::math::{Bounds3, Transform};
use glam::{Vec2, Vec3, Vec4};

/// Indexed triangle mesh in object space.
///
/// | field | meaning |
/// |-------|---------|
/// | `positions` | vertex positions |
/// | `indices` | one `[i0, i1, i2]` per triangle; the winding `(p1 − p0) × (p2 − p0)` gives the geometric normal |
/// | `normals` | optional per-vertex shading normals (same length as `positions`) |
/// | `uvs` | optional per-vertex texture coordinates (same length as `positions`) |
/// | `material_ids` | one material index per triangle; missing entries read as material 0 |
/// | `attributes` | named per-vertex RGBA attributes, by [`attribute_key`] of their names |
///
/// Out-of-range vertex indices are tolerated: such triangles read vertex 0 in their place
/// and are usually degenerate, so they are never hit.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshGeom {
    pub positions: Vec<Vec3>,
    pub indices: Vec<[u32; 3]>,
    pub normals: Option<Vec<Vec3>>,
    pub uvs: Option<Vec<Vec2>>,
    pub material_ids: Vec<u32>,
    pub attributes: Vec<(u64, Vec<Vec4>)>,
}

/// Most named attributes a scene gives one mesh.
pub const MAX_NAMED_ATTRIBUTES: usize = 4;

/// Most attributes one mesh carries: the named ones, and its tangents and their normals.
pub const MAX_ATTRIBUTES: usize = MAX_NAMED_ATTRIBUTES + 2;

/// The key of an attribute name (64-bit FNV-1a of its UTF-8 bytes): the Attribute node
/// and the mesh meet on it.
pub const fn attribute_key(name: &str) -> u64 {
    let b = name.as_bytes();
    let (mut h, mut i) = (0xcbf2_9ce4_8422_2325u64, 0);
    while i < b.len() {
        h = (h ^ b[i] as u64).wrapping_mul(0x0100_0000_01b3);
        i += 1;
    }
    h
}

/// The named attributes at a surface point, interpolated (at most [`MAX_ATTRIBUTES`]), with
/// their change across the triangle: `d1`, `d2` per unit of the barycentrics b1, b2, along
/// the triangle's world-space edges `e1`, `e2` (so that a Bump reads them at its offsets).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AttributeValues {
    pub len: u8,
    pub keys: [u64; MAX_ATTRIBUTES],
    pub values: [Vec4; MAX_ATTRIBUTES],
    pub d1: [Vec4; MAX_ATTRIBUTES],
    pub d2: [Vec4; MAX_ATTRIBUTES],
    pub e1: Vec3,
    pub e2: Vec3,
}

impl AttributeValues {
    /// The value of the attribute with key `key`, if the point has it.
    #[inline]
    pub fn get(&self, key: u64) -> Option<Vec4> {
        (0..self.len as usize)
            .find(|&i| self.keys[i] == key)
            .map(|i| self.values[i])
    }

    /// The value of the attribute `key` a small move `dp` away in the triangle's plane (the
    /// least-squares barycentric change along its edges; the value itself when degenerate).
    pub fn get_moved(&self, key: u64, dp: Vec3) -> Option<Vec4> {
        let i = (0..self.len as usize).find(|&i| self.keys[i] == key)?;
        let (a, b) = (self.e1, self.e2);
        let (aa, ab, bb) = (a.dot(a), a.dot(b), b.dot(b));
        let det = aa * bb - ab * ab;
        if !(det.abs() > 1e-30) || !det.is_finite() {
            return Some(self.values[i]);
        }
        let (pa, pb) = (dp.dot(a), dp.dot(b));
        let (b1, b2) = ((pa * bb - pb * ab) / det, (pb * aa - pa * ab) / det);
        Some(self.values[i] + self.d1[i] * b1 + self.d2[i] * b2)
    }
}

impl MeshGeom {
    /// Number of triangles.
    #[inline]
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Position of vertex `i`; `positions[0]` (or the origin) when `i` is out of range.
    #[inline]
    pub(crate) fn position(&self, i: u32) -> Vec3 {
        match self.positions.get(i as usize) {
            Some(p) => *p,
            None => self.positions.first().copied().unwrap_or(Vec3::ZERO),
        }
    }

    /// The three object-space vertices of triangle `prim` (zeros when `prim` is out of range).
    #[inline]
    pub fn triangle(&self, prim: u32) -> [Vec3; 3] {
        match self.indices.get(prim as usize) {
            Some(&[a, b, c]) => [self.position(a), self.position(b), self.position(c)],
            None => [Vec3::ZERO; 3],
        }
    }

    /// Material of triangle `prim` (0 when not given).
    #[inline]
    pub fn material(&self, prim: u32) -> u32 {
        self.material_ids.get(prim as usize).copied().unwrap_or(0)
    }

    /// Object-space bounds of all referenced vertices.
    pub fn bounds(&self) -> Bounds3 {
        let mut b = Bounds3::EMPTY;
        for t in 0..self.indices.len() as u32 {
            for p in self.triangle(t) {
                b.extend(p);
            }
        }
        b
    }
}

/// One placement of a mesh in the world. Instances share their mesh: nothing is copied.
///
/// | field | meaning |
/// |-------|---------|
/// | `mesh` | index into the mesh list given to [`super::Accel::build`]; out-of-range instances are ignored |
/// | `transform` | object-to-world transform |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    pub mesh: u32,
    pub transform: Transform,
}
