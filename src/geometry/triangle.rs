//! Watertight ray-triangle intersection (Woop, Benthin & Wald 2013, "Watertight
//! Ray/Triangle Intersection", JCGT 2(1)), following pbrt-v4's `IntersectTriangle`.
//!
//! The ray is sheared so that it points along +z from the origin; the triangle is then
//! tested in 2D with edge functions. The edge functions are evaluated with exact products
//! in `f64`, so their signs are exact and two triangles sharing an edge can never both
//! miss a ray that crosses that edge.

use super::float::gamma;
use glam::Vec3;

/// Per-ray constants of the shear transform, computed once per ray and reused for every
/// triangle it meets.
///
/// | field | meaning |
/// |-------|---------|
/// | `o` | ray origin |
/// | `k` | permutation `[kx, ky, kz]`, `kz` the dominant axis of the direction |
/// | `s` | shear `(−dx/dz, −dy/dz, 1/dz)` in the permuted frame |
#[derive(Clone, Copy, Debug)]
pub struct TriRay {
    pub o: Vec3,
    pub k: [usize; 3],
    pub s: Vec3,
}

impl TriRay {
    /// Shear constants for a ray with origin `o` and direction `d` (`d` need not be unit).
    #[inline]
    pub fn new(o: Vec3, d: Vec3) -> Self {
        let a = d.abs();
        let kz = if a.x > a.y {
            if a.x > a.z {
                0
            } else {
                2
            }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let kx = if kz == 2 { 0 } else { kz + 1 };
        let ky = if kx == 2 { 0 } else { kx + 1 };
        let dz = d[kz];
        let s = Vec3::new(-d[kx] / dz, -d[ky] / dz, 1.0 / dz);
        TriRay {
            o,
            k: [kx, ky, kz],
            s,
        }
    }
}

/// Result of a ray-triangle test: `p = b0·p0 + b1·p1 + b2·p2` with `b0 = 1 − b1 − b2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriHit {
    pub t: f32,
    pub b1: f32,
    pub b2: f32,
}

#[inline(always)]
fn edge(ax: f32, ay: f32, bx: f32, by: f32) -> f64 {
    // Products of two f32 are exact in f64; the difference is rounded once, so its sign is exact.
    ax as f64 * by as f64 - ay as f64 * bx as f64
}

/// Intersects a ray with triangle `(p0, p1, p2)`; both faces are hit.
///
/// | parameter | meaning |
/// |-----------|---------|
/// | `r` | per-ray shear constants ([`TriRay::new`]) |
/// | `t_max` | exclusive bound: only hits with `0 < t < t_max` are returned |
/// | `p0, p1, p2` | vertices, in the same space as the ray |
///
/// Returns `None` for rays in the triangle's plane, NaN input, and hits whose `t` is not
/// provably positive. A zero-area triangle never yields NaN; the acceleration structure
/// drops such triangles at build time (see [`is_degenerate`]).
#[inline]
pub fn intersect_triangle(r: &TriRay, t_max: f32, p0: Vec3, p1: Vec3, p2: Vec3) -> Option<TriHit> {
    intersect::<true>(r, t_max, p0, p1, p2)
}

/// [`intersect_triangle`] for a ray from a point inside a volume, not on a surface: every hit
/// with a computed `t > 0` is returned, with no margin for the error of `t`. A walk below a
/// surface that scatters within that margin of the surface (a few micrometres on a triangle
/// of 2 m) and then heads out must still meet it; the conservative test would let it
/// through.
#[inline]
pub fn intersect_triangle_from_volume(
    r: &TriRay,
    t_max: f32,
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
) -> Option<TriHit> {
    intersect::<false>(r, t_max, p0, p1, p2)
}

#[inline(always)]
fn intersect<const CONSERVATIVE: bool>(
    r: &TriRay,
    t_max: f32,
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
) -> Option<TriHit> {
    let [kx, ky, kz] = r.k;
    let a = p0 - r.o;
    let b = p1 - r.o;
    let c = p2 - r.o;
    let (az, bz, cz) = (a[kz], b[kz], c[kz]);
    let ax = a[kx] + r.s.x * az;
    let ay = a[ky] + r.s.y * az;
    let bx = b[kx] + r.s.x * bz;
    let by = b[ky] + r.s.y * bz;
    let cx = c[kx] + r.s.x * cz;
    let cy = c[ky] + r.s.y * cz;

    let e0 = edge(bx, by, cx, cy);
    let e1 = edge(cx, cy, ax, ay);
    let e2 = edge(ax, ay, bx, by);
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return None;
    }
    let (e0, e1, e2) = (e0 as f32, e1 as f32, e2 as f32);
    let det = e0 + e1 + e2;
    // `!(det != 0)` also rejects NaN.
    if det == 0.0 || det.is_nan() {
        return None;
    }
    let az = az * r.s.z;
    let bz = bz * r.s.z;
    let cz = cz * r.s.z;
    let t_scaled = e0 * az + e1 * bz + e2 * cz;
    if det < 0.0 && (t_scaled >= 0.0 || t_scaled < t_max * det) {
        return None;
    }
    if det > 0.0 && (t_scaled <= 0.0 || t_scaled > t_max * det) {
        return None;
    }
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    // Also rejects a NaN t.
    if t.partial_cmp(&t_max) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    let b1 = e1 * inv_det;
    let b2 = e2 * inv_det;
    if !CONSERVATIVE {
        return (t > 0.0 && b1.is_finite() && b2.is_finite()).then_some(TriHit { t, b1, b2 });
    }

    // Conservative check that t is positive (pbrt-v4 §6.8.4).
    let max_zt = az.abs().max(bz.abs()).max(cz.abs());
    let delta_z = gamma(3) * max_zt;
    let max_xt = ax.abs().max(bx.abs()).max(cx.abs());
    let max_yt = ay.abs().max(by.abs()).max(cy.abs());
    let delta_x = gamma(5) * (max_xt + max_zt);
    let delta_y = gamma(5) * (max_yt + max_zt);
    let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = e0.abs().max(e1.abs()).max(e2.abs());
    let delta_t =
        3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
    if t <= delta_t || !b1.is_finite() || !b2.is_finite() {
        return None;
    }
    Some(TriHit { t, b1, b2 })
}

/// True when the triangle has zero area (or non-finite vertices): it can never be hit.
#[inline]
pub fn is_degenerate(p: &[Vec3; 3]) -> bool {
    let n = face_normal(p);
    n == Vec3::ZERO || !n.is_finite()
}

/// Unnormalised geometric normal `(p1 − p0) × (p2 − p0)`.
#[inline]
pub fn face_normal(p: &[Vec3; 3]) -> Vec3 {
    (p[1] - p[0]).cross(p[2] - p[0])
}

#[cfg(test)]
#[path = "triangle_tests.rs"]
mod tests;
