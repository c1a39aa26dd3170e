//! Rough reflection: the GGX microfacet BRDF.

use super::bsdf::{BsdfSample, LobeFlags};
use super::fresnel::Fresnel;
use super::layer::{CoatAlbedoTable, MultiScatter, SchlickAlbedoTable};
use super::microfacet::alpha_from_roughness;
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
/// | `ms` | Cycles' multiple-scattering compensation ([`MultiScatter`]), if any |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MicrofacetReflection {
    pub ggx: Ggx,
    pub fresnel: Fresnel,
    pub coat: Option<&'static CoatAlbedoTable>,
    pub ms: Option<MultiScatter>,
    /// The compensation factor for one view cosine, fixed by [`MicrofacetReflection::fix_view`].
    view: Option<(f32, Spectrum)>,
}

impl MicrofacetReflection {
    pub fn new(
        roughness: f32,
        fresnel: Fresnel,
        coat: Option<&'static CoatAlbedoTable>,
        multiscatter: bool,
    ) -> Self {
        let ggx = Ggx::new(alpha_from_roughness(roughness));
        let ms = multiscatter
            .then(|| MultiScatter::new(ggx.alpha.sqrt(), average_fresnel(fresnel, coat)));
        MicrofacetReflection {
            ggx,
            fresnel,
            coat,
            ms,
            view: None,
        }
    }

    /// The compensation factor at the view cosine `mu_o` (1 without it).
    #[inline]
    /// Fixes the view-dependent factor for the view cosine `mu_o`: many evaluations with the
    /// same `wo` (a photon-map radiance estimate) then skip its table lookup.
    pub fn fix_view(&mut self, mu_o: f32) {
        self.view = Some((mu_o, self.ms_factor(mu_o)));
    }

    fn ms_factor(&self, mu_o: f32) -> Spectrum {
        if let Some((m, f)) = self.view {
            if m == mu_o {
                return f;
            }
        }
        self.ms.map_or(Spectrum::ONE, |m| m.factor(mu_o))
    }

    pub fn flags(&self) -> u8 {
        let near = if self.ggx.alpha <= super::microfacet::NEAR_SPECULAR_ALPHA {
            LobeFlags::NEAR_SPECULAR
        } else {
            0
        };
        LobeFlags::REFLECTION | LobeFlags::GLOSSY | near
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
        self.fresnel.eval(wo.dot(h)) * self.ms_factor(wo.z) * (d * g / (4.0 * wo.z * wi.z))
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
        let weight =
            self.fresnel.eval(wo.dot(m)) * self.ms_factor(wo.z) * ((1.0 + lo) / (1.0 + lo + li));
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
        let single = match (self.fresnel, self.coat) {
            (Fresnel::Dielectric { .. }, Some(c)) => Spectrum::splat(c.albedo(wo.z, r)),
            (Fresnel::Schlick { f0 }, _) => t.albedo(wo.z, r, f0),
            (Fresnel::Constant(c), _) => c * t.e1(wo.z, r),
            (f, _) => t.albedo(wo.z, r, f.eval(1.0)),
        };
        single * self.ms_factor(wo.z)
    }
}

/// The hemispherical average F_ss of a Fresnel model, as Cycles takes it for the compensation:
/// exact for Schlick (F0 + (1 - F0)/21) and constant reflectance, the coat table's average for
/// a dielectric, and Cycles' F82 fit for a conductor.
fn average_fresnel(f: Fresnel, coat: Option<&'static CoatAlbedoTable>) -> Spectrum {
    match f {
        Fresnel::Constant(c) => c,
        Fresnel::Schlick { f0 } => f0 + (Spectrum::ONE - f0) / 21.0,
        Fresnel::Dielectric { eta } => match coat {
            Some(t) => Spectrum::splat(t.fresnel_avg()),
            None => {
                let f0 = super::fresnel::f0_from_ior(eta);
                Spectrum::splat(f0 + (1.0 - f0) / 21.0)
            }
        },
        Fresnel::Conductor { .. } => {
            let f0 = f.eval(1.0);
            let f82 = f.eval(1.0 / 7.0);
            let b = (f0.lerp(Spectrum::ONE, 0.462_664_36) - f82) * 17.651_384;
            (f0.lerp(Spectrum::ONE, 1.0 / 21.0) - b / 126.0).clamp(Spectrum::ZERO, Spectrum::ONE)
        }
    }
}
