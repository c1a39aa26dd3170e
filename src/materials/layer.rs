//! Directional-albedo tables of GGX reflection, the compensation for multiple scattering
//! between microfacets that Cycles applies (Kulla & Conty 2017), and the diffuse base under a
//! dielectric specular layer as Cycles layers it.

mod albedo;

pub(super) use albedo::{cell, decode_f32, visible_normal_integral};
pub use albedo::{tables, CoatAlbedoTable, MultiScatter, SchlickAlbedoTable, N_F0};

use super::bsdf::{BsdfSample, LobeFlags};
use crate::math::{Spectrum, INV_PI};
use crate::sampling::warp::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use glam::{Vec2, Vec3};

/// A clear coat over a BSDF, as Cycles layers the Principled BSDF's Coat: the lobes under it
/// are weighted by what the coat does not reflect towards the viewer, 1 - weight E_coat(wo),
/// and tinted by the coat's absorption, mix(1, tint^(1 / cos t), weight) with t the angle of
/// the view refracted into the coat (Beer's law through a unit thickness). The coat's own
/// reflection is a lobe of the BSDF ([`super::coat_lobe`]).
///
/// | parameter | meaning |
/// |---|---|
/// | `weight` | Coat Weight, in [0, 1] |
/// | `roughness` | Coat Roughness |
/// | `ior` | Coat IOR (its F0 fixes `table`) |
/// | `tint` | Coat Tint |
/// | `multiscatter` | the coat's reflection compensated for multiple scattering |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoatLayer {
    pub weight: f32,
    pub roughness: f32,
    pub ior: f32,
    pub tint: Spectrum,
    pub table: &'static CoatAlbedoTable,
    pub multiscatter: bool,
}

impl CoatLayer {
    /// What reaches the lobes under the coat and back towards a viewer at cosine `mu`.
    pub fn under(&self, mu: f32) -> Spectrum {
        let e = self.table.albedo_ms(mu, self.roughness, self.multiscatter);
        let through = Spectrum::splat((1.0 - self.weight * e).max(0.0));
        if self.tint == Spectrum::ONE {
            return through;
        }
        let sin2_t = (1.0 - mu * mu).max(0.0) / (self.ior * self.ior);
        let cos_t = (1.0 - sin2_t).max(1e-4).sqrt();
        let absorbed = self.tint.max(Spectrum::ZERO).powf(1.0 / cos_t);
        through * Spectrum::ONE.lerp(absorbed, self.weight)
    }
}

/// The diffuse base of a coated (plastic-like) surface, layered as Cycles layers the
/// Principled BSDF's base under its specular layer: the base's weight is what the specular
/// layer does not reflect towards the viewer,
/// f = albedo (1 - E_spec(wo)) / pi,
/// with E_spec the specular layer's directional albedo (tabulated, with the multiple-scattering
/// compensation when the layer has it). It depends on the view direction only, so it is not
/// reciprocal: the photon pass evaluates it with the directions swapped. Coat + base never
/// exceed one. The coat's own reflection is a separate lobe.
///
/// | parameter | meaning |
/// |---|---|
/// | `albedo` | base colour |
/// | `roughness` | the specular layer's perceptual roughness (0 = smooth) |
/// | `table` | the specular layer's albedo table, which fixes its F0 = ((eta - 1) / (eta + 1))^2 |
/// | `multiscatter` | whether the specular layer is compensated for multiple scattering |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoatedDiffuse {
    pub albedo: Spectrum,
    pub roughness: f32,
    table: &'static CoatAlbedoTable,
    multiscatter: bool,
    /// `transmitted` for one view cosine, fixed by [`CoatedDiffuse::fix_view`].
    view: Option<(f32, f32)>,
}

impl CoatedDiffuse {
    pub fn new(
        albedo: Spectrum,
        roughness: f32,
        table: &'static CoatAlbedoTable,
        multiscatter: bool,
    ) -> Self {
        CoatedDiffuse {
            albedo,
            roughness,
            table,
            multiscatter,
            view: None,
        }
    }

    /// Fixes the view-dependent weight for the view cosine `mu`: many evaluations with the
    /// same `wo` then skip the table.
    pub fn fix_view(&mut self, mu: f32) {
        self.view = Some((mu, self.transmitted(mu)));
    }

    /// Pins the view-dependent weight for the view cosine `mu` to the specular layer's albedo
    /// at cosine `mu_layer` (a layer whose normal is not the base's).
    pub fn pin_view(&mut self, mu: f32, mu_layer: f32) {
        self.view = None;
        self.view = Some((mu, self.transmitted(mu_layer)));
    }

    fn transmitted(&self, mu: f32) -> f32 {
        if let Some((m, t)) = self.view {
            if m == mu {
                return t;
            }
        }
        (1.0 - self.table.albedo_ms(mu, self.roughness, self.multiscatter)).max(0.0)
    }

    pub fn flags(&self) -> u8 {
        LobeFlags::REFLECTION | LobeFlags::DIFFUSE
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3, mask: u8) -> Spectrum {
        if mask & LobeFlags::REFLECTION == 0 || wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo * (self.transmitted(wo.z) * INV_PI)
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

    /// Radiance towards `wo` per unit irradiance: albedo (1 - E_spec(wo)) / pi.
    pub fn irradiance_response(&self, wo: Vec3) -> Spectrum {
        if wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo * (self.transmitted(wo.z) * INV_PI)
    }

    /// Exact (up to the table): albedo x (1 - E_spec(wo)).
    pub fn albedo(&self, wo: Vec3, mask: u8) -> Spectrum {
        if mask & LobeFlags::REFLECTION == 0 || wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo * self.transmitted(wo.z)
    }
}
