//! A Lambertian base under a dielectric specular coat, energy-conserving through the coat's
//! tabulated directional albedo (Kelemen & Szirmay-Kalos 2001; Kulla & Conty 2017).

use super::bsdf::{BsdfSample, LobeFlags};
use super::fresnel::{fresnel_dielectric, ior_from_f0};
use super::microfacet::{alpha_from_roughness, reflect, Ggx};
use crate::math::{Spectrum, INV_PI};
use crate::sampling::warp::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use glam::{Vec2, Vec3};
use std::sync::OnceLock;

const N_MU: usize = 32;
const N_ROUGH: usize = 16;
const N_F0: usize = 16;
/// Largest tabulated sqrt(F0); coats are clamped to F0 <= 0.9 (relative IOR ~ 37).
const MAX_SQRT_F0: f32 = 0.948_683_3;
const STRATA: usize = 24;

/// Directional albedo E(mu) = integral of f_coat |cos| of the coat's reflection (GGX with
/// dielectric Fresnel, or the smooth Fresnel R(mu) at roughness 0), tabulated over
/// (mu = cos theta, perceptual roughness, sqrt(F0)), with its cosine-weighted average
/// E_avg = 2 integral E(mu) mu dmu computed exactly for the piecewise-linear interpolant.
pub struct CoatAlbedoTable {
    e: Vec<f32>,
    e_avg: Vec<f32>,
}

fn coat_albedo(mu: f32, roughness: f32, eta: f32) -> f32 {
    let mu = mu.clamp(2e-3, 1.0);
    if roughness <= 0.0 {
        return fresnel_dielectric(mu, eta).0;
    }
    let ggx = Ggx::new(alpha_from_roughness(roughness));
    let wo = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let lo = ggx.lambda(wo);
    let mut sum = 0.0f64;
    for j in 0..STRATA {
        for i in 0..STRATA {
            let u = Vec2::new(
                (i as f32 + 0.5) / STRATA as f32,
                (j as f32 + 0.5) / STRATA as f32,
            );
            let m = ggx.sample_visible(wo, u);
            let wi = reflect(wo, m);
            if wi.z > 0.0 {
                let f = fresnel_dielectric(wo.dot(m), eta).0;
                sum += (f * (1.0 + lo) / (1.0 + lo + ggx.lambda(wi))) as f64;
            }
        }
    }
    (sum / (STRATA * STRATA) as f64) as f32
}

impl CoatAlbedoTable {
    fn build() -> Self {
        let mut e = vec![0.0f32; N_MU * N_ROUGH * N_F0];
        let mut e_avg = vec![0.0f32; N_ROUGH * N_F0];
        for k in 0..N_F0 {
            let s = MAX_SQRT_F0 * k as f32 / (N_F0 - 1) as f32;
            let eta = ior_from_f0(s * s);
            for j in 0..N_ROUGH {
                let r = j as f32 / (N_ROUGH - 1) as f32;
                for i in 0..N_MU {
                    let mu = i as f32 / (N_MU - 1) as f32;
                    e[(k * N_ROUGH + j) * N_MU + i] = coat_albedo(mu, r, eta);
                }
                // Exact 2 * integral mu E(mu) dmu of the linear interpolant (Simpson is
                // exact for the quadratic integrand on each segment).
                let row = &e[(k * N_ROUGH + j) * N_MU..(k * N_ROUGH + j + 1) * N_MU];
                let h = 1.0 / (N_MU - 1) as f64;
                let mut acc = 0.0f64;
                for i in 0..N_MU - 1 {
                    let (a, b) = (i as f64 * h, (i + 1) as f64 * h);
                    let (ea, eb) = (row[i] as f64, row[i + 1] as f64);
                    acc += h / 6.0 * (a * ea + 4.0 * 0.5 * (a + b) * 0.5 * (ea + eb) + b * eb);
                }
                e_avg[k * N_ROUGH + j] = (2.0 * acc) as f32;
            }
        }
        CoatAlbedoTable { e, e_avg }
    }

    /// The table, built on first use (a few million GGX samples, once per process).
    pub fn get() -> &'static CoatAlbedoTable {
        static TABLE: OnceLock<CoatAlbedoTable> = OnceLock::new();
        TABLE.get_or_init(CoatAlbedoTable::build)
    }

    fn cell(x: f32, n: usize) -> (usize, f32) {
        let x = if x.is_finite() {
            x.clamp(0.0, 1.0)
        } else {
            0.0
        } * (n - 1) as f32;
        let i = (x as usize).min(n - 2);
        (i, x - i as f32)
    }

    fn coords(roughness: f32, f0: f32) -> ((usize, f32), (usize, f32)) {
        let s = f0.clamp(0.0, 0.9).sqrt() / MAX_SQRT_F0;
        (Self::cell(roughness, N_ROUGH), Self::cell(s, N_F0))
    }

    /// E(mu) by trilinear interpolation.
    pub fn albedo(&self, mu: f32, roughness: f32, f0: f32) -> f32 {
        let ((j, tj), (k, tk)) = Self::coords(roughness, f0);
        let (i, ti) = Self::cell(mu, N_MU);
        let at = |k: usize, j: usize| {
            let base = (k * N_ROUGH + j) * N_MU + i;
            self.e[base] * (1.0 - ti) + self.e[base + 1] * ti
        };
        let lo = at(k, j) * (1.0 - tj) + at(k, j + 1) * tj;
        let hi = at(k + 1, j) * (1.0 - tj) + at(k + 1, j + 1) * tj;
        lo * (1.0 - tk) + hi * tk
    }

    /// E_avg by bilinear interpolation (consistent with [`CoatAlbedoTable::albedo`]).
    pub fn average(&self, roughness: f32, f0: f32) -> f32 {
        let ((j, tj), (k, tk)) = Self::coords(roughness, f0);
        let at = |k: usize, j: usize| self.e_avg[k * N_ROUGH + j];
        let lo = at(k, j) * (1.0 - tj) + at(k, j + 1) * tj;
        let hi = at(k + 1, j) * (1.0 - tj) + at(k + 1, j + 1) * tj;
        lo * (1.0 - tk) + hi * tk
    }
}

/// The diffuse base of a coated (plastic-like) surface: what the coat does not reflect
/// reaches a Lambertian base,
/// f = albedo (1 - E(wo)) (1 - E(wi)) / (pi (1 - E_avg)),
/// which is reciprocal and has directional albedo exactly albedo x (1 - E(wo)), so that
/// coat + base never exceed one. The coat's own reflection is a separate lobe.
///
/// | parameter | meaning |
/// |---|---|
/// | `albedo` | base colour |
/// | `roughness` | the coat's perceptual roughness (0 = smooth coat) |
/// | `f0` | the coat's normal-incidence reflectance, ((eta - 1) / (eta + 1))^2 |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoatedDiffuse {
    pub albedo: Spectrum,
    pub roughness: f32,
    pub f0: f32,
    e_avg: f32,
}

impl CoatedDiffuse {
    pub fn new(albedo: Spectrum, roughness: f32, f0: f32) -> Self {
        let e_avg = CoatAlbedoTable::get().average(roughness, f0);
        CoatedDiffuse {
            albedo,
            roughness,
            f0,
            e_avg,
        }
    }

    fn transmitted(&self, mu: f32) -> f32 {
        (1.0 - CoatAlbedoTable::get().albedo(mu, self.roughness, self.f0)).max(0.0)
    }

    fn scale(&self) -> f32 {
        let d = 1.0 - self.e_avg;
        if d > 1e-6 {
            INV_PI / d
        } else {
            0.0
        }
    }

    pub fn flags(&self) -> u8 {
        LobeFlags::REFLECTION | LobeFlags::DIFFUSE
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3, mask: u8) -> Spectrum {
        if mask & LobeFlags::REFLECTION == 0 || wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo * (self.transmitted(wo.z) * self.transmitted(wi.z) * self.scale())
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
        let pdf = cosine_hemisphere_pdf(wi);
        Some(BsdfSample {
            wi,
            weight: self.eval(wo, wi, mask) * (wi.z / pdf),
            pdf,
            flags: self.flags(),
            eta: 1.0,
        })
    }

    /// Exact (up to the table): albedo x (1 - E(wo)).
    pub fn albedo(&self, wo: Vec3, mask: u8) -> Spectrum {
        if mask & LobeFlags::REFLECTION == 0 || wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo * self.transmitted(wo.z)
    }
}
