//! Diffuse transmission (Cycles' Translucent BSDF).

use super::bsdf::{BsdfSample, LobeFlags};
use crate::math::{Spectrum, INV_PI};
use crate::sampling::warp::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use glam::{Vec2, Vec3};

/// Lambertian transmission, f = albedo / pi for `wi` on the other side of the surface than
/// `wo` and zero on its side, sampled with the cosine-weighted hemisphere on the other side.
///
/// | parameter | meaning |
/// |---|---|
/// | `albedo` | the share of the light passed through, in [0, 1] per channel |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Translucent {
    pub albedo: Spectrum,
}

impl Translucent {
    pub fn flags(&self) -> u8 {
        LobeFlags::TRANSMISSION | LobeFlags::DIFFUSE
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3, mask: u8) -> Spectrum {
        if mask & LobeFlags::TRANSMISSION == 0 || !(wo.z * wi.z < 0.0) {
            return Vec3::ZERO;
        }
        self.albedo * INV_PI
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3, mask: u8) -> f32 {
        if mask & LobeFlags::TRANSMISSION == 0 || !(wo.z * wi.z < 0.0) {
            return 0.0;
        }
        cosine_hemisphere_pdf(Vec3::new(wi.x, wi.y, wi.z.abs()))
    }

    pub fn sample(&self, wo: Vec3, _uc: f32, u: Vec2, mask: u8) -> Option<BsdfSample> {
        if mask & LobeFlags::TRANSMISSION == 0 || wo.z == 0.0 {
            return None;
        }
        let w = square_to_cosine_hemisphere(u);
        if w.z <= 0.0 {
            return None;
        }
        let wi = Vec3::new(w.x, w.y, -w.z.copysign(wo.z));
        Some(BsdfSample {
            wi,
            weight: self.albedo,
            pdf: cosine_hemisphere_pdf(w),
            flags: self.flags(),
            eta: 1.0,
        })
    }

    /// Exact: the albedo itself, on the transmission side.
    pub fn albedo(&self, wo: Vec3, mask: u8) -> Spectrum {
        if mask & LobeFlags::TRANSMISSION == 0 || wo.z == 0.0 {
            return Vec3::ZERO;
        }
        self.albedo
    }
}
