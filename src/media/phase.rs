//! Henyey-Greenstein phase function (Henyey & Greenstein 1941; pbrt-v4 §11.3.1).
//! p(cos) = (1 - g^2) / (4 pi (1 + g^2 + 2 g cos)^(3/2)), with `cos` the cosine between the
//! two directions pointing away from the scattering point (`wo` towards the viewer, `wi`
//! towards the light): g > 0 scatters forward, i.e. wi close to -wo.

use crate::math::{Frame, INV_4PI, PI};
use glam::{Vec2, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenyeyGreenstein {
    pub g: f32,
}

impl HenyeyGreenstein {
    pub fn new(g: f32) -> Self {
        HenyeyGreenstein {
            g: g.clamp(-0.999, 0.999),
        }
    }

    /// Density for `wo`, `wi` both pointing away from the point.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        hg(-wo.dot(wi), self.g)
    }

    /// Samples `wi` with density `eval(wo, wi)`; returns (wi, pdf).
    pub fn sample(&self, wo: Vec3, u: Vec2) -> (Vec3, f32) {
        let g = self.g;
        // Cosine between wi and wo (pbrt-v4 SampleHenyeyGreenstein): forward scattering
        // (g > 0) puts wi near -wo.
        let cos_wo = if g.abs() < 1e-3 {
            1.0 - 2.0 * u.x
        } else {
            let sq = (1.0 - g * g) / (1.0 + g - 2.0 * g * u.x);
            -(1.0 + g * g - sq * sq) / (2.0 * g)
        }
        .clamp(-1.0, 1.0);
        let sin = (1.0 - cos_wo * cos_wo).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let wi =
            Frame::from_normal(wo).to_world(Vec3::new(sin * phi.cos(), sin * phi.sin(), cos_wo));
        (wi, hg(-cos_wo, g))
    }
}

fn hg(cos: f32, g: f32) -> f32 {
    let denom = 1.0 + g * g + 2.0 * g * -cos;
    // Written with the forward cosine: p = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos_fwd)^1.5).
    INV_4PI * (1.0 - g * g) / (denom.max(1e-12) * denom.max(1e-12).sqrt())
}
