//! Perfect specular reflection off a smooth conductor or mirror.

use super::bsdf::{BsdfSample, LobeFlags};
use super::fresnel::Fresnel;
use crate::math::Spectrum;
use glam::{Vec2, Vec3};

/// Dirac delta reflection about the normal, scaled by a Fresnel term.
///
/// | parameter | meaning |
/// |---|---|
/// | `fresnel` | [`Fresnel::Conductor`] (complex IOR), [`Fresnel::Schlick`] (F0 tint), [`Fresnel::Constant`] (mirror reflectance) or [`Fresnel::Dielectric`] (a clear coat) |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecularReflection {
    pub fresnel: Fresnel,
}

impl SpecularReflection {
    pub fn flags(&self) -> u8 {
        LobeFlags::REFLECTION | LobeFlags::SPECULAR
    }

    pub fn eval(&self, _wo: Vec3, _wi: Vec3, _mask: u8) -> Spectrum {
        Vec3::ZERO
    }

    pub fn pdf(&self, _wo: Vec3, _wi: Vec3, _mask: u8) -> f32 {
        0.0
    }

    pub fn sample(&self, wo: Vec3, _uc: f32, _u: Vec2, mask: u8) -> Option<BsdfSample> {
        if mask & LobeFlags::REFLECTION == 0 || wo.z <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            weight: self.fresnel.eval(wo.z),
            pdf: 1.0,
            flags: self.flags(),
            eta: 1.0,
        })
    }

    /// Exact: F(cos theta_o).
    pub fn albedo(&self, wo: Vec3, mask: u8) -> Spectrum {
        if mask & LobeFlags::REFLECTION == 0 || wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.fresnel.eval(wo.z)
    }
}
