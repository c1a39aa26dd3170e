//! Isotropic GGX (Trowbridge-Reitz) microfacet distribution with the Smith shadowing terms
//! (Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces") and
//! visible-normal sampling (Heitz 2018, "Sampling the GGX Distribution of Visible Normals").

use crate::math::PI;
use glam::{Vec2, Vec3};

/// Smallest GGX alpha; smaller values are numerically a delta and handled as such.
pub const MIN_ALPHA: f32 = 1e-4;

/// Largest perceptual roughness of a near-specular lobe
/// ([`LobeFlags::NEAR_SPECULAR`](super::bsdf::LobeFlags::NEAR_SPECULAR)): a Principled coat
/// (default 0.03) and a polished metal (0.1) are; Blender's default 0.5 is not.
pub const NEAR_SPECULAR_ROUGHNESS: f32 = 0.2;
/// [`NEAR_SPECULAR_ROUGHNESS`] as GGX alpha.
pub const NEAR_SPECULAR_ALPHA: f32 = NEAR_SPECULAR_ROUGHNESS * NEAR_SPECULAR_ROUGHNESS;

/// GGX alpha from perceptual roughness: alpha = roughness^2, clamped to [`MIN_ALPHA`].
#[inline]
pub fn alpha_from_roughness(roughness: f32) -> f32 {
    let r = if roughness.is_finite() {
        roughness.clamp(0.0, 1.0)
    } else {
        1.0
    };
    (r * r).max(MIN_ALPHA)
}

/// GGX distribution of normals with width `alpha`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    pub alpha: f32,
}

impl Ggx {
    pub fn new(alpha: f32) -> Self {
        Ggx {
            alpha: if alpha.is_finite() {
                alpha.clamp(MIN_ALPHA, 1.0)
            } else {
                1.0
            },
        }
    }

    /// D(m), Walter 2007 eq. 33: alpha^2 / (pi cos^4 (alpha^2 + tan^2)^2), in the
    /// equivalent form alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2) for unit m; sin^2 is taken
    /// from the tangential components so that small alpha keeps its precision near the pole.
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let t = a2 * m.z * m.z + (m.x * m.x + m.y * m.y);
        a2 / (PI * t * t)
    }

    /// Smith Lambda(w), from Walter 2007 eq. 34: G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2)).
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let c2 = w.z * w.z;
        if c2 <= 0.0 {
            return f32::INFINITY;
        }
        let tan2 = (w.x * w.x + w.y * w.y) / c2;
        0.5 * (-1.0 + (1.0 + self.alpha * self.alpha * tan2).sqrt())
    }

    /// Smith masking G1(w, m) with the sidedness factor chi+((w.m)/(w.n)) (Walter eq. 34).
    #[inline]
    pub fn g1(&self, w: Vec3, m: Vec3) -> f32 {
        if w.dot(m) * w.z <= 0.0 {
            return 0.0;
        }
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking-shadowing G2 = 1 / (1 + Lambda(wo) + Lambda(wi))
    /// (Heitz 2014, "Understanding the Masking-Shadowing Function", eq. 99).
    #[inline]
    pub fn g2(&self, wo: Vec3, wi: Vec3, m: Vec3) -> f32 {
        if wo.dot(m) * wo.z <= 0.0 || wi.dot(m) * wi.z <= 0.0 {
            return 0.0;
        }
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// Samples a visible normal for `wo` (Heitz 2018, listing 1). `wo` is mirrored to the
    /// upper hemisphere (wo * sign(wo.z)); the result always has m.z >= 0.
    pub fn sample_visible(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let wo = if wo.z < 0.0 { -wo } else { wo };
        let a = self.alpha;
        // Section 3.2: stretch the view direction to the hemisphere configuration.
        let vh = Vec3::new(a * wo.x, a * wo.y, wo.z).normalize_or(Vec3::Z);
        // Section 4.1: orthonormal basis around vh.
        let lensq = vh.x * vh.x + vh.y * vh.y;
        let t1 = if lensq > 0.0 {
            Vec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt()
        } else {
            Vec3::X
        };
        let t2 = vh.cross(t1);
        // Section 4.2: parameterisation of the projected area.
        let r = u.x.max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let p1 = r * phi.cos();
        let mut p2 = r * phi.sin();
        let s = 0.5 * (1.0 + vh.z);
        p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
        // Section 4.3: reprojection onto the hemisphere.
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
        // Section 3.4: unstretch back to the ellipsoid configuration.
        Vec3::new(a * nh.x, a * nh.y, nh.z.max(1e-6)).normalize_or(Vec3::Z)
    }

    /// Density of [`Ggx::sample_visible`]: D_wo(m) = G1(wo, m) max(0, wo.m) D(m) / wo.z
    /// (Heitz 2018 eq. 3), with `wo` mirrored to the upper hemisphere as when sampling.
    #[inline]
    pub fn pdf_visible(&self, wo: Vec3, m: Vec3) -> f32 {
        let wo = if wo.z < 0.0 { -wo } else { wo };
        if wo.z <= 0.0 {
            return 0.0;
        }
        let dot = wo.dot(m);
        if dot <= 0.0 {
            return 0.0;
        }
        self.g1(wo, m) * dot * self.d(m) / wo.z
    }
}

/// Mirror reflection of `w` about `m`.
#[inline]
pub fn reflect(w: Vec3, m: Vec3) -> Vec3 {
    2.0 * w.dot(m) * m - w
}

/// Refraction of `w` through the microfacet `m`, given `cos_t` and `eta_ti` from
/// [`super::fresnel::fresnel_dielectric`] evaluated at w.m (Mitsuba 3 `refract`).
#[inline]
pub fn refract(w: Vec3, m: Vec3, cos_t: f32, eta_ti: f32) -> Vec3 {
    m * (w.dot(m) * eta_ti + cos_t) - w * eta_ti
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::warp::square_to_uniform_hemisphere;
    use crate::sampling::Rng;

    #[test]
    fn projected_area_is_one() {
        // Integral of D(m) cos(theta_m) over the hemisphere is 1 (Walter eq. 4).
        for alpha in [0.1f32, 0.5, 1.0] {
            let g = Ggx::new(alpha);
            let mut rng = Rng::new(9, 0);
            let n = 400_000;
            let mut sum = 0.0f64;
            for _ in 0..n {
                let m = square_to_uniform_hemisphere(rng.vec2());
                sum += (g.d(m) * m.z) as f64 * 2.0 * std::f64::consts::PI;
            }
            let est = sum / n as f64;
            assert!((est - 1.0).abs() < 0.03, "alpha {alpha}: {est}");
        }
    }

    #[test]
    fn visible_normals_face_the_viewer() {
        let g = Ggx::new(0.4);
        let mut rng = Rng::new(10, 0);
        let wo = Vec3::new(0.8, 0.1, 0.2).normalize();
        for _ in 0..10_000 {
            let m = g.sample_visible(wo, rng.vec2());
            assert!(m.z > 0.0 && (m.length() - 1.0).abs() < 1e-4);
            assert!(wo.dot(m) > -1e-4);
        }
    }
}
