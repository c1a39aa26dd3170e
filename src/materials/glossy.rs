//! Rough reflection: the GGX microfacet BRDF.

use super::bsdf::{BsdfSample, LobeFlags};
use super::fresnel::Fresnel;
use super::layer::{CoatAlbedoTable, SchlickAlbedoTable};
use super::microfacet::{reflect, Ggx};
use crate::math::Spectrum;
use glam::{Vec2, Vec3};

/// GGX microfacet reflection (Walter et al. 2007 eq. 20):
/// f = F(wo.h) D(h) G2(wo, wi) / (4 |wo.n| |wi.n|), h = normalize(wo + wi),
/// sampled through the visible normals (Heitz 2018) with pdf D_wo(h) / (4 wo.h)
/// (Walter eq. 14 for the Jacobian).
///
/// | parameter | meaning |
/// |---|---|
/// | `ggx` | distribution; alpha = roughness^2 |
/// | `fresnel` | conductor (complex IOR), Schlick (F0 tint) or dielectric (coat IOR) |
/// | `coat` | for a dielectric Fresnel, the coat's albedo table (its exact albedo) |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MicrofacetReflection {
    pub ggx: Ggx,
    pub fresnel: Fresnel,
    pub coat: Option<&'static CoatAlbedoTable>,
}

impl MicrofacetReflection {
    pub fn flags(&self) -> u8 {
        LobeFlags::REFLECTION | LobeFlags::GLOSSY
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3, mask: u8) -> Spectrum {
        if mask & LobeFlags::REFLECTION == 0 || wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let h = (wo + wi).normalize_or_zero();
        if h.z <= 0.0 {
            return Vec3::ZERO;
        }
        let d = self.ggx.d(h);
        let g = self.ggx.g2(wo, wi, h);
        self.fresnel.eval(wo.dot(h)) * (d * g / (4.0 * wo.z * wi.z))
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3, mask: u8) -> f32 {
        if mask & LobeFlags::REFLECTION == 0 || wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let h = (wo + wi).normalize_or_zero();
        let dot = wo.dot(h);
        if h.z <= 0.0 || dot <= 0.0 {
            return 0.0;
        }
        self.ggx.pdf_visible(wo, h) / (4.0 * dot)
    }

    pub fn sample(&self, wo: Vec3, _uc: f32, u: Vec2, mask: u8) -> Option<BsdfSample> {
        if mask & LobeFlags::REFLECTION == 0 || wo.z <= 0.0 {
            return None;
        }
        let m = self.ggx.sample_visible(wo, u);
        let wi = reflect(wo, m).normalize_or_zero();
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(wo, wi, mask);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        // f cos / pdf = F G2 / G1(wo) (Heitz 2018 eq. 19).
        let lo = self.ggx.lambda(wo);
        let li = self.ggx.lambda(wi);
        let weight = self.fresnel.eval(wo.dot(m)) * ((1.0 + lo) / (1.0 + lo + li));
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            flags: self.flags(),
            eta: 1.0,
        })
    }

    /// The single-scattering directional albedo from tables: exact (to the tables) for
    /// Schlick and constant reflectance and, with its `coat` table, for a dielectric; a
    /// conductor is read as Schlick with its normal-incidence reflectance.
    pub fn albedo(&self, wo: Vec3, mask: u8) -> Spectrum {
        if mask & LobeFlags::REFLECTION == 0 || wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        let r = self.ggx.alpha.sqrt();
        let t = SchlickAlbedoTable::get();
        match (self.fresnel, self.coat) {
            (Fresnel::Dielectric { .. }, Some(c)) => Spectrum::splat(c.albedo(wo.z, r)),
            (Fresnel::Schlick { f0 }, _) => t.albedo(wo.z, r, f0),
            (Fresnel::Constant(c), _) => {
                let (a, b) = t.ab(wo.z, r);
                c * (a + b)
            }
            (f, _) => t.albedo(wo.z, r, f.eval(1.0)),
        }
    }
}
