//! Warps from [0,1)^2 to shapes, each with its density and, where useful, its inverse.
//! Densities are with respect to solid angle for directions and area for points.

use crate::math::{INV_2PI, INV_4PI, INV_PI, PI};
use glam::{Vec2, Vec3};

#[inline]
pub fn square_to_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}
pub const UNIFORM_SPHERE_PDF: f32 = INV_4PI;
pub fn uniform_sphere_to_square(d: Vec3) -> Vec2 {
    let mut phi = d.y.atan2(d.x) * INV_2PI;
    if phi < 0.0 {
        phi += 1.0;
    }
    Vec2::new((1.0 - d.z) * 0.5, phi)
}

#[inline]
pub fn square_to_uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}
pub const UNIFORM_HEMISPHERE_PDF: f32 = INV_2PI;

/// Concentric map (Shirley & Chiu 1997) to the unit disk.
#[inline]
pub fn square_to_uniform_disk_concentric(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, PI / 4.0 * (o.y / o.x))
    } else {
        (o.y, PI / 2.0 - PI / 4.0 * (o.x / o.y))
    };
    Vec2::new(r * theta.cos(), r * theta.sin())
}
pub fn uniform_disk_concentric_to_square(p: Vec2) -> Vec2 {
    let r = p.length();
    if r == 0.0 {
        return Vec2::splat(0.5);
    }
    let mut phi = p.y.atan2(p.x);
    if phi < -PI / 4.0 {
        phi += 2.0 * PI;
    }
    let (a, b) = if phi < PI / 4.0 {
        (r, phi * a_over(r))
    } else if phi < 3.0 * PI / 4.0 {
        (-(phi - PI / 2.0) * a_over(r), r)
    } else if phi < 5.0 * PI / 4.0 {
        (-r, -(phi - PI) * a_over(r))
    } else {
        ((phi - 3.0 * PI / 2.0) * a_over(r), -r)
    };
    Vec2::new(0.5 * (a + 1.0), 0.5 * (b + 1.0))
}
#[inline]
fn a_over(r: f32) -> f32 {
    4.0 * r / PI
}

/// Cosine-weighted hemisphere (Malley's method), density cos(theta)/pi.
#[inline]
pub fn square_to_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = square_to_uniform_disk_concentric(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}
#[inline]
pub fn cosine_hemisphere_pdf(d: Vec3) -> f32 {
    if d.z > 0.0 {
        d.z * INV_PI
    } else {
        0.0
    }
}
pub fn cosine_hemisphere_to_square(d: Vec3) -> Vec2 {
    uniform_disk_concentric_to_square(Vec2::new(d.x, d.y))
}

/// Uniform direction in the cone around +z with half-angle acos(cos_max).
#[inline]
pub fn square_to_uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    let cos_t = 1.0 - u.x * (1.0 - cos_max);
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
}
#[inline]
pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_max))
}

/// Uniform barycentrics on a triangle (Heitz 2019 low-distortion map).
#[inline]
pub fn square_to_uniform_triangle(u: Vec2) -> (f32, f32) {
    let (b0, b1);
    if u.x < u.y {
        b0 = u.x / 2.0;
        b1 = u.y - b0;
    } else {
        b1 = u.y / 2.0;
        b0 = u.x - b1;
    }
    (b0, b1)
}

/// Density conversion from area at `p_light` (normal `n_light`) to solid angle at the origin of `d`.
#[inline]
pub fn area_to_solid_angle(pdf_area: f32, dist2: f32, cos_light: f32) -> f32 {
    if cos_light.abs() <= 0.0 {
        0.0
    } else {
        pdf_area * dist2 / cos_light.abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn inverses_round_trip() {
        let mut rng = Rng::new(3, 0);
        for _ in 0..10_000 {
            let u = rng.vec2().clamp(Vec2::splat(1e-3), Vec2::splat(1.0 - 1e-3));
            let d = square_to_uniform_sphere(u);
            assert!(
                (uniform_sphere_to_square(d) - u).abs().max_element() < 1e-3,
                "{u:?}"
            );
            let c = square_to_cosine_hemisphere(u);
            assert!(
                (cosine_hemisphere_to_square(c) - u).abs().max_element() < 1e-3,
                "{u:?}"
            );
        }
    }

    #[test]
    fn unit_length_outputs() {
        let mut rng = Rng::new(4, 0);
        for _ in 0..10_000 {
            let u = rng.vec2();
            for d in [
                square_to_uniform_sphere(u),
                square_to_uniform_hemisphere(u),
                square_to_cosine_hemisphere(u),
                square_to_uniform_cone(u, 0.3),
            ] {
                assert!((d.length() - 1.0).abs() < 1e-4);
            }
            let (b0, b1) = square_to_uniform_triangle(u);
            assert!(b0 >= 0.0 && b1 >= 0.0 && b0 + b1 <= 1.0 + 1e-6);
        }
    }
}
