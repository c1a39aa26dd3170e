//! Lambertian reflection.

use super::bsdf::{BsdfSample, LobeFlags};
use crate::math::{Spectrum, INV_PI};
use crate::sampling::warp::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use glam::{Vec2, Vec3};

/// Lambertian reflection, f = albedo / pi, sampled with the cosine-weighted hemisphere.
///
/// | parameter | meaning |
/// |---|---|
/// | `albedo` | directional albedo (reflectance), in [0, 1] per channel |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lambert {
    pub albedo: Spectrum,
}

impl Lambert {
    pub fn flags(&self) -> u8 {
        LobeFlags::REFLECTION | LobeFlags::DIFFUSE
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3, mask: u8) -> Spectrum {
        if mask & LobeFlags::REFLECTION == 0 || wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo * INV_PI
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3, mask: u8) -> f32 {
        if mask & LobeFlags::REFLECTION == 0 || wo.z <= 0.0 {
            return 0.0;
        }
        cosine_hemisphere_pdf(wi)
    }

    pub fn sample(&self, wo: Vec3, _uc: f32, u: Vec2, mask: u8) -> Option<BsdfSample> {
        if mask & LobeFlags::REFLECTION == 0 || wo.z <= 0.0 {
            return None;
        }
        let wi = square_to_cosine_hemisphere(u);
        if wi.z <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.albedo,
            pdf: cosine_hemisphere_pdf(wi),
            flags: self.flags(),
            eta: 1.0,
        })
    }

    /// Radiance towards `wo` per unit irradiance: albedo / pi.
    pub fn irradiance_response(&self, wo: Vec3) -> Spectrum {
        if wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo * INV_PI
    }

    /// Exact: the albedo itself.
    pub fn albedo(&self, wo: Vec3, mask: u8) -> Spectrum {
        if mask & LobeFlags::REFLECTION == 0 || wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo
    }
}
