//! The closed set of BSDF lobes and the one dispatch over it.
//!
//! Every lobe works in the local shading frame and offers the same five operations;
//! `mask` restricts scattering to `LobeFlags::REFLECTION`, `TRANSMISSION` or both (photon
//! Russian roulette samples one side at a time). Opaque lobes are two-sided: when `wo` is
//! below the surface both directions are mirrored through the tangent plane, as Cycles does
//! by facing the normal towards the viewer.

use super::bsdf::{BsdfSample, LobeFlags};
use super::conductor::SpecularReflection;
use super::dielectric::SmoothDielectric;
use super::diffuse::Lambert;
use super::glossy::MicrofacetReflection;
use super::layer::CoatedDiffuse;
use super::rough_dielectric::RoughDielectric;
use super::translucent::Translucent;
use crate::math::Spectrum;
use glam::{Vec2, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Lobe {
    Lambert(Lambert),
    SpecularReflection(SpecularReflection),
    MicrofacetReflection(MicrofacetReflection),
    SmoothDielectric(SmoothDielectric),
    RoughDielectric(RoughDielectric),
    CoatedDiffuse(CoatedDiffuse),
    Translucent(Translucent),
}

/// Applies `$body` to the lobe inside whichever variant `$self` is.
macro_rules! dispatch {
    ($self:expr, $l:ident => $body:expr) => {
        match $self {
            Lobe::Lambert($l) => $body,
            Lobe::SpecularReflection($l) => $body,
            Lobe::MicrofacetReflection($l) => $body,
            Lobe::SmoothDielectric($l) => $body,
            Lobe::RoughDielectric($l) => $body,
            Lobe::CoatedDiffuse($l) => $body,
            Lobe::Translucent($l) => $body,
        }
    };
}

#[inline]
fn flip(v: Vec3) -> Vec3 {
    Vec3::new(v.x, v.y, -v.z)
}

impl Lobe {
    /// Placeholder for unused slots (a black Lambertian).
    pub const NONE: Lobe = Lobe::Lambert(Lambert { albedo: Vec3::ZERO });

    /// [`LobeFlags`] of the lobe.
    pub fn flags(&self) -> u8 {
        dispatch!(self, l => l.flags())
    }

    fn two_sided(&self) -> bool {
        self.flags() & LobeFlags::TRANSMISSION == 0
    }

    /// f(wo, wi) without the cosine; zero for delta lobes.
    pub fn eval(&self, wo: Vec3, wi: Vec3, mask: u8) -> Spectrum {
        if self.two_sided() && wo.z < 0.0 {
            return dispatch!(self, l => l.eval(flip(wo), flip(wi), mask));
        }
        dispatch!(self, l => l.eval(wo, wi, mask))
    }

    /// Solid-angle pdf of `sample` producing `wi` (zero for delta lobes).
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mask: u8) -> f32 {
        if self.two_sided() && wo.z < 0.0 {
            return dispatch!(self, l => l.pdf(flip(wo), flip(wi), mask));
        }
        dispatch!(self, l => l.pdf(wo, wi, mask))
    }

    /// Samples `wi` with `uc` (choices inside the lobe) and `u` (the direction).
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2, mask: u8) -> Option<BsdfSample> {
        if self.two_sided() && wo.z < 0.0 {
            let s = dispatch!(self, l => l.sample(flip(wo), uc, u, mask))?;
            return Some(BsdfSample {
                wi: flip(s.wi),
                ..s
            });
        }
        dispatch!(self, l => l.sample(wo, uc, u, mask))
    }

    /// For a diffuse lobe whose f does not depend on the incident direction: the radiance
    /// towards `wo` per unit irradiance; None for other lobes.
    pub fn irradiance_response(&self, wo: Vec3) -> Option<Spectrum> {
        let wo = if self.two_sided() && wo.z < 0.0 {
            flip(wo)
        } else {
            wo
        };
        match self {
            Lobe::Lambert(l) => Some(l.irradiance_response(wo)),
            Lobe::CoatedDiffuse(l) => Some(l.irradiance_response(wo)),
            _ => None,
        }
    }

    /// Fixes what depends on the view direction alone for `wo` (local), for many evaluations
    /// with it.
    pub fn fix_view(&mut self, wo: Vec3) {
        let mu = wo.z.abs();
        match self {
            Lobe::MicrofacetReflection(l) => l.fix_view(mu),
            Lobe::CoatedDiffuse(l) => l.fix_view(mu),
            _ => {}
        }
    }

    /// Estimate of the directional albedo of the masked part (used to pick lobes and for
    /// photon Russian roulette; exact where the lobe documents it).
    pub fn albedo(&self, wo: Vec3, mask: u8) -> Spectrum {
        let wo = if self.two_sided() && wo.z < 0.0 {
            flip(wo)
        } else {
            wo
        };
        dispatch!(self, l => l.albedo(wo, mask))
    }
}
