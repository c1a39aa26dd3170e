//! Smooth dielectric interface: delta reflection and refraction.

use super::bsdf::{BsdfSample, LobeFlags};
use super::fresnel::fresnel_dielectric;
use crate::math::Spectrum;
use glam::{Vec2, Vec3};

/// Smooth dielectric boundary (glass, water). Reflection and refraction are both Dirac
/// deltas; one is chosen with probability R or T = 1 - R (exact Fresnel, total internal
/// reflection included). Refraction scales by (1 - R) and the tint, not by 1/eta^2: radiance
/// is carried as Cycles carries it (see [`crate::materials::bsdf`]).
///
/// | parameter | meaning |
/// |---|---|
/// | `eta` | relative IOR, inside / outside (the normal points outside) |
/// | `tint` | transmittance multiplier (1 = clear) |
/// | `refraction_only` | Cycles' Refraction BSDF: no reflection, and refraction not scaled by 1 - R (none under total internal reflection) |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmoothDielectric {
    pub eta: f32,
    pub tint: Spectrum,
    pub refraction_only: bool,
}

impl SmoothDielectric {
    pub fn flags(&self) -> u8 {
        LobeFlags::REFLECTION | LobeFlags::TRANSMISSION | LobeFlags::SPECULAR
    }

    pub fn eval(&self, _wo: Vec3, _wi: Vec3, _mask: u8) -> Spectrum {
        Vec3::ZERO
    }

    pub fn pdf(&self, _wo: Vec3, _wi: Vec3, _mask: u8) -> f32 {
        0.0
    }

    pub fn sample(&self, wo: Vec3, uc: f32, _u: Vec2, mask: u8) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let (r, cos_t, eta_it, eta_ti) = fresnel_dielectric(wo.z, self.eta);
        let can_r = mask & LobeFlags::REFLECTION != 0 && !self.refraction_only;
        let can_t = mask & LobeFlags::TRANSMISSION != 0;
        let (reflect, prob) = match (can_r, can_t) {
            (true, true) => {
                if uc < r {
                    (true, r)
                } else {
                    (false, 1.0 - r)
                }
            }
            (true, false) => (true, 1.0),
            (false, true) => (false, 1.0),
            (false, false) => return None,
        };
        if prob <= 0.0 {
            return None;
        }
        if reflect {
            return Some(BsdfSample {
                wi: Vec3::new(-wo.x, -wo.y, wo.z),
                weight: Vec3::splat(r / prob),
                pdf: prob,
                flags: LobeFlags::REFLECTION | LobeFlags::SPECULAR,
                eta: 1.0,
            });
        }
        if r >= 1.0 {
            return None;
        }
        let t = if self.refraction_only { 1.0 } else { 1.0 - r };
        let wi = Vec3::new(-eta_ti * wo.x, -eta_ti * wo.y, cos_t).normalize_or_zero();
        if wi.z * wo.z >= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.tint * (t / prob),
            pdf: prob,
            flags: LobeFlags::TRANSMISSION | LobeFlags::SPECULAR,
            eta: eta_it,
        })
    }

    /// Exact: R for reflection, (1 - R) x tint for transmission (refraction only: none, and
    /// tint unless the light is totally reflected).
    pub fn albedo(&self, wo: Vec3, mask: u8) -> Spectrum {
        let r = fresnel_dielectric(wo.z, self.eta).0;
        if self.refraction_only {
            let through = mask & LobeFlags::TRANSMISSION != 0 && r < 1.0;
            return if through { self.tint } else { Vec3::ZERO };
        }
        let mut a = Vec3::ZERO;
        if mask & LobeFlags::REFLECTION != 0 {
            a += Vec3::splat(r);
        }
        if mask & LobeFlags::TRANSMISSION != 0 {
            a += self.tint * (1.0 - r);
        }
        a
    }
}
