//! Surface interactions and robust spawning of rays from them (pbrt-v4 §6.8.6,
//! "Robust Spawned Ray Origins").

use super::float::{gamma, next_float_down, next_float_up};
use super::ray::Ray;
use glam::{Mat4, Vec2, Vec3};

/// pbrt-v4's `ShadowEpsilon`: shadow rays stop this fraction short of their target.
pub const SHADOW_EPSILON: f32 = 0.0001;

/// Local geometry at a ray hit, in world space.
///
/// | field | meaning |
/// |-------|---------|
/// | `p` | hit point, from the barycentrics and the instance transform |
/// | `p_error` | conservative absolute error bound of `p`, per axis |
/// | `ng` | unit geometric normal, from the winding `(p1 − p0) × (p2 − p0)`; flipped when the instance transform swaps handedness, so it follows the world-space winding |
/// | `ns` | unit shading normal: interpolated vertex normals when the mesh has them, else `ng` |
/// | `uv` | interpolated texture coordinates, or the barycentrics `(b1, b2)` |
/// | `dpdu` | ∂p/∂u in world space (a tangent perpendicular to `ng` when the uv mapping is degenerate) |
/// | `wo` | unit direction back along the incoming ray, `−d/|d|` |
/// | `material`, `instance`, `prim`, `t` | material index of the triangle, and the hit record |
/// | `bary` | the hit's barycentrics `(b1, b2)` in its triangle |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceInteraction {
    pub p: Vec3,
    pub p_error: Vec3,
    pub ng: Vec3,
    pub ns: Vec3,
    pub uv: Vec2,
    pub dpdu: Vec3,
    pub wo: Vec3,
    pub material: u32,
    pub instance: u32,
    pub prim: u32,
    pub t: f32,
    pub bary: Vec2,
}

/// Offsets a point off a surface so that a ray leaving it in direction `w` cannot
/// re-intersect that surface (pbrt-v4 `OffsetRayOrigin`).
///
/// | parameter | meaning |
/// |-----------|---------|
/// | `p` | computed surface point |
/// | `p_error` | its absolute error bound per axis |
/// | `n` | geometric normal (any length, usually unit) |
/// | `w` | direction the new ray will take |
///
/// The point moves along `n` by `dot(|n|, p_error)`, to the side `w` points to, and each
/// moved coordinate is then rounded one more ulp away from the surface.
#[inline]
pub fn offset_ray_origin(p: Vec3, p_error: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    let d = n.abs().dot(p_error);
    let mut offset = d * n;
    if w.dot(n) < 0.0 {
        offset = -offset;
    }
    let mut po = p + offset;
    for i in 0..3 {
        if offset[i] > 0.0 {
            po[i] = next_float_up(po[i]);
        } else if offset[i] < 0.0 {
            po[i] = next_float_down(po[i]);
        }
    }
    po
}

/// Absolute error of `m · p` for an affine `m`, when `p` already carries error `p_error`
/// (pbrt-v4 `Transform::operator()(Point3fi)`, §6.8.5).
#[inline]
pub fn transform_point_error(m: &Mat4, p: Vec3, p_error: Vec3) -> Vec3 {
    let c0 = m.x_axis.truncate().abs();
    let c1 = m.y_axis.truncate().abs();
    let c2 = m.z_axis.truncate().abs();
    let t = m.w_axis.truncate().abs();
    let a = p.abs();
    let g3 = gamma(3);
    let exact = g3 * (c0 * a.x + c1 * a.y + c2 * a.z + t);
    if p_error == Vec3::ZERO {
        exact
    } else {
        (g3 + 1.0) * (c0 * p_error.x + c1 * p_error.y + c2 * p_error.z) + exact
    }
}

impl SurfaceInteraction {
    /// Ray leaving the surface in direction `dir` (any length), unbounded.
    #[inline]
    pub fn spawn_ray(&self, dir: Vec3) -> Ray {
        Ray::new(offset_ray_origin(self.p, self.p_error, self.ng, dir), dir)
    }

    /// Shadow ray towards the point `target`: `d = target − o`, `t_max = 1 − SHADOW_EPSILON`.
    #[inline]
    pub fn spawn_ray_to(&self, target: Vec3) -> Ray {
        let o = offset_ray_origin(self.p, self.p_error, self.ng, target - self.p);
        Ray::with_t_max(o, target - o, 1.0 - SHADOW_EPSILON)
    }

    /// Shadow ray towards another surface point, offsetting both ends off their surfaces.
    ///
    /// | parameter | meaning |
    /// |-----------|---------|
    /// | `other_p` | the other point |
    /// | `other_p_error` | its error bound |
    /// | `other_n` | its geometric normal |
    #[inline]
    pub fn spawn_ray_to_interaction(
        &self,
        other_p: Vec3,
        other_p_error: Vec3,
        other_n: Vec3,
    ) -> Ray {
        let from = offset_ray_origin(self.p, self.p_error, self.ng, other_p - self.p);
        let to = offset_ray_origin(other_p, other_p_error, other_n, from - other_p);
        Ray::with_t_max(from, to - from, 1.0 - SHADOW_EPSILON)
    }
}
