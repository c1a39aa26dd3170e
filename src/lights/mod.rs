//! Lights. One enum for the closed set; each kind lives in its own file with its parameter table.
//!
//! Radiometric conventions (Blender/Cycles units, see `scene::desc`): point-like lights carry an
//! intensity or a sphere radiance, area lights a radiance, distant lights an irradiance, the
//! environment a radiance per direction.

mod area;
mod distant;
mod emit;
mod environment;
mod light_sampler;
mod point;
mod triangle;

pub use area::{AreaLight, AreaShape};
pub use distant::DistantLight;
pub use emit::{LeSample, Target};
pub use environment::EnvironmentLight;
pub use light_sampler::{LightSampler, EVERY_LIGHT_UP_TO};
pub use point::{PointLight, SpotShape};
pub use triangle::TriangleLight;

use crate::materials::{texture::Texture, Material};
use crate::math::Spectrum;
use glam::{Vec2, Vec3};

/// What light sampling needs from the scene besides the light itself.
pub struct LightCtx<'a> {
    pub materials: &'a [Material],
    pub textures: &'a [Texture],
    /// Per instance, what shading graphs read of its object (empty when none reads it).
    pub objects: &'a [crate::materials::graph::point::ObjectCoords],
    /// Centre and radius of a sphere bounding the scene (for lights at infinity).
    pub scene_center: Vec3,
    pub scene_radius: f32,
}

/// A sample of incident light at a reference point.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Unit direction from the reference point towards the light.
    pub wi: Vec3,
    /// Radiance arriving along `wi` (for delta lights: intensity / dist^2 or irradiance).
    pub li: Spectrum,
    /// Solid-angle density; for delta lights the value 1 and `delta` is set.
    pub pdf: f32,
    /// Distance to the light point; infinite for lights at infinity.
    pub dist: f32,
    /// Point on the light and its normal (zero for point lights and lights at infinity).
    pub p: Vec3,
    pub n: Vec3,
    pub delta: bool,
}

#[derive(Clone, Debug)]
pub enum Light {
    Point(PointLight),
    Area(AreaLight),
    Distant(DistantLight),
    Environment(EnvironmentLight),
    Triangle(TriangleLight),
}

impl Light {
    /// Samples incident light at `p`. `n` is the side a reflecting surface at `p` faces, or
    /// zero for a point in a medium or a surface that transmits; only the constant
    /// environment uses it (cosine-weighted about `n`, see `EnvironmentLight::sample_li_about`).
    pub fn sample_li(&self, p: Vec3, n: Vec3, u: Vec2, ctx: &LightCtx) -> Option<LightSample> {
        let s = match self {
            Light::Point(l) => l.sample_li(p, u),
            Light::Area(l) => l.sample_li(p, u),
            Light::Distant(l) => l.sample_li(u),
            Light::Environment(l) => l.sample_li_about(n, u),
            Light::Triangle(l) => l.sample_li(p, u, ctx),
        }?;
        (s.pdf > 0.0 && s.pdf.is_finite() && s.li.max_element() > 0.0).then_some(s)
    }

    /// Solid-angle density with which `sample_li` at `p` about `n` would pick direction `wi`,
    /// reaching the light at point `p_light` with normal `n_light` (ignored for lights at
    /// infinity).
    pub fn pdf_li(&self, p: Vec3, n: Vec3, wi: Vec3, p_light: Vec3, n_light: Vec3) -> f32 {
        match self {
            Light::Point(l) => l.pdf_li(p, p_light),
            Light::Area(l) => l.pdf_li(p, p_light, n_light),
            Light::Distant(l) => l.pdf_li(wi),
            Light::Environment(l) => l.pdf_li_about(n, wi),
            Light::Triangle(l) => l.pdf_li(p, p_light, n_light),
        }
    }

    /// Total emitted power Φ (W per channel), used to pick lights and photon counts.
    pub fn power(&self, ctx: &LightCtx) -> Spectrum {
        match self {
            Light::Point(l) => l.power(),
            Light::Area(l) => l.power(),
            Light::Distant(l) => l.power(ctx.scene_radius),
            Light::Environment(l) => l.power(ctx.scene_radius),
            Light::Triangle(l) => l.power(ctx),
        }
    }

    pub fn is_delta(&self) -> bool {
        match self {
            Light::Point(l) => l.radius == 0.0,
            Light::Distant(l) => l.cos_half_angle >= 1.0,
            _ => false,
        }
    }

    pub fn is_infinite(&self) -> bool {
        matches!(self, Light::Distant(_) | Light::Environment(_))
    }
}
