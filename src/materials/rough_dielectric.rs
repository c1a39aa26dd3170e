//! Rough dielectric interface: GGX reflection and refraction (Walter et al. 2007).

use super::bsdf::{BsdfSample, LobeFlags};
use super::fresnel::fresnel_dielectric;
use super::glass_albedo;
use super::microfacet::{reflect, refract, Ggx};
use crate::math::Spectrum;
use glam::{Vec2, Vec3};

/// Rough dielectric boundary (frosted glass), Walter et al. 2007:
///
/// - reflection, eq. 20: f_r = F(wo.m) D(m) G2 / (4 |wo.n| |wi.n|), m = h_r (eq. 13);
/// - refraction, eq. 21 as Cycles evaluates it (no 1/eta^2 radiance scaling, see
///   [`crate::materials::bsdf`]): f_t = eta^2 |wo.m| |wi.m| (1 - F) D(m) G2 / (|wo.n| |wi.n|
///   (wo.m + eta wi.m)^2), m = h_t = normalize(wo + eta wi) (eq. 16), eta = IOR of wi's side /
///   IOR of wo's side.
///
/// Sampling draws a visible normal for wo (Heitz 2018), then reflects with probability
/// F(wo.m) and refracts otherwise; the pdf uses the Jacobians of eqs. 14 and 17.
/// G2 is the height-correlated Smith term.
///
/// | parameter | meaning |
/// |---|---|
/// | `ggx` | distribution; alpha = roughness^2 |
/// | `eta` | relative IOR, inside / outside (the normal points outside) |
/// | `tint` | transmittance multiplier |
/// | `multiscatter` | Cycles' Multiscatter GGX: f / E(mu_o) ([`glass_albedo`](super::glass_albedo)) |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughDielectric {
    pub ggx: Ggx,
    pub eta: f32,
    pub tint: Spectrum,
    pub multiscatter: bool,
    /// Cycles' Refraction BSDF: no reflection, refraction not scaled by 1 - F (none where a
    /// facet reflects totally).
    pub refraction_only: bool,
}

/// Half vector of (wo, wi) oriented to the upper hemisphere, the relative IOR eta of wi's
/// side over wo's side, and whether the pair is a reflection.
struct Geometry {
    m: Vec3,
    eta: f32,
    reflect: bool,
}

impl RoughDielectric {
    pub fn flags(&self) -> u8 {
        LobeFlags::REFLECTION | LobeFlags::TRANSMISSION | LobeFlags::GLOSSY
    }

    /// The multiple-scattering compensation for the view direction `wo` (1 without it).
    fn ms_factor(&self, wo: Vec3) -> f32 {
        if !self.multiscatter {
            return 1.0;
        }
        let eta = if wo.z >= 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        };
        glass_albedo::compensation(wo.z.abs(), self.ggx.alpha.sqrt(), eta)
    }

    fn geometry(&self, wo: Vec3, wi: Vec3) -> Option<Geometry> {
        if wo.z == 0.0 || wi.z == 0.0 {
            return None;
        }
        let reflect = wo.z * wi.z > 0.0;
        let eta = if reflect {
            1.0
        } else if wo.z > 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        };
        let m = (wo + wi * eta).normalize_or_zero();
        let m = if m.z < 0.0 { -m } else { m };
        if m.z <= 0.0 {
            return None;
        }
        // Sidedness (chi+ of Walter eq. 34): both directions see the facet from their side.
        if wo.dot(m) * wo.z <= 0.0 || wi.dot(m) * wi.z <= 0.0 {
            return None;
        }
        Some(Geometry { m, eta, reflect })
    }

    /// The shares of reflection and refraction at a facet of Fresnel reflectance `f`.
    fn split(&self, f: f32) -> (f32, f32) {
        if self.refraction_only {
            (0.0, if f < 1.0 { 1.0 } else { 0.0 })
        } else {
            (f, 1.0 - f)
        }
    }

    /// Probabilities of choosing reflection and refraction for Fresnel reflectance `f`.
    fn choice(&self, f: f32, mask: u8) -> (f32, f32) {
        let (r, t) = self.split(f);
        match (
            mask & LobeFlags::REFLECTION != 0 && r > 0.0,
            mask & LobeFlags::TRANSMISSION != 0,
        ) {
            (true, true) => (r, t),
            (true, false) => (1.0, 0.0),
            (false, true) => (0.0, 1.0),
            (false, false) => (0.0, 0.0),
        }
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3, mask: u8) -> Spectrum {
        let Some(g) = self.geometry(wo, wi) else {
            return Vec3::ZERO;
        };
        let side = if g.reflect {
            LobeFlags::REFLECTION
        } else {
            LobeFlags::TRANSMISSION
        };
        if mask & side == 0 {
            return Vec3::ZERO;
        }
        let d = self.ggx.d(g.m);
        let g2 = self.ggx.g2(wo, wi, g.m);
        let (f, t) = self.split(fresnel_dielectric(wo.dot(g.m), self.eta).0);
        let cos = (wo.z * wi.z).abs();
        let ms = self.ms_factor(wo);
        if g.reflect {
            Vec3::splat(ms * f * d * g2 / (4.0 * cos))
        } else {
            let om = wo.dot(g.m);
            let im = wi.dot(g.m);
            let denom = om + g.eta * im;
            if denom == 0.0 {
                return Vec3::ZERO;
            }
            let eta2 = g.eta * g.eta;
            self.tint * (ms * t * d * g2 * eta2 * (om * im).abs() / (cos * denom * denom))
        }
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3, mask: u8) -> f32 {
        let Some(g) = self.geometry(wo, wi) else {
            return 0.0;
        };
        let om = wo.dot(g.m);
        let f = fresnel_dielectric(om, self.eta).0;
        let (pr, pt) = self.choice(f, mask);
        let dv = self.ggx.pdf_visible(wo, g.m);
        if g.reflect {
            // Walter eq. 14: |dh/dwi| = 1 / (4 |wi.h|).
            pr * dv / (4.0 * om.abs())
        } else {
            // Walter eq. 17: |dh/dwi| = eta^2 |wi.h| / (wo.h + eta wi.h)^2.
            let im = wi.dot(g.m);
            let denom = om + g.eta * im;
            if denom == 0.0 {
                return 0.0;
            }
            pt * dv * g.eta * g.eta * im.abs() / (denom * denom)
        }
    }

    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2, mask: u8) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let m = self.ggx.sample_visible(wo, u);
        let (f, cos_t, eta_it, eta_ti) = fresnel_dielectric(wo.dot(m), self.eta);
        let (pr, pt) = self.choice(f, mask);
        let (fr, ft) = self.split(f);
        if pr + pt <= 0.0 {
            return None;
        }
        let reflect = uc * (pr + pt) < pr;
        let (wi, factor, eta, flags) = if reflect {
            let wi = reflect_dir(wo, m)?;
            (
                wi,
                Vec3::splat(fr / pr),
                1.0,
                LobeFlags::REFLECTION | LobeFlags::GLOSSY,
            )
        } else {
            if ft <= 0.0 || pt <= 0.0 {
                return None;
            }
            let wi = refract(wo, m, cos_t, eta_ti).normalize_or_zero();
            if wi.z * wo.z >= 0.0 {
                return None;
            }
            (
                wi,
                self.tint * (ft / pt),
                eta_it,
                LobeFlags::TRANSMISSION | LobeFlags::GLOSSY,
            )
        };
        let pdf = self.pdf(wo, wi, mask);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        // f cos / pdf = (F or 1 - F) / (choice probability) x G2 / G1(wo) (Heitz 2018 eq. 19).
        let lo = self.ggx.lambda(wo);
        let li = self.ggx.lambda(wi);
        let weight = factor * (self.ms_factor(wo) * (1.0 + lo) / (1.0 + lo + li));
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            flags,
            eta,
        })
    }

    /// Estimate: the smooth interface's R and (1 - R) x tint at the macro normal, with R kept
    /// inside [0.02, 0.98]: rough facets reflect and refract beyond the macro-surface's total
    /// internal reflection, and a component chosen by these estimates must never have zero
    /// probability where it scatters. (With the compensation the lobe's energy is all of it.)
    pub fn albedo(&self, wo: Vec3, mask: u8) -> Spectrum {
        if self.refraction_only {
            let through = mask & LobeFlags::TRANSMISSION != 0;
            return if through { self.tint } else { Vec3::ZERO };
        }
        let r = fresnel_dielectric(wo.z, self.eta).0.clamp(0.02, 0.98);
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

fn reflect_dir(wo: Vec3, m: Vec3) -> Option<Vec3> {
    let wi = reflect(wo, m).normalize_or_zero();
    (wi.z * wo.z > 0.0).then_some(wi)
}
