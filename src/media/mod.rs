//! Participating media (Jensen 2001, chapter 10; Jensen & Christensen 1998): homogeneous
//! media and density grids with a Henyey-Greenstein phase function, the stack that tracks
//! which medium a ray is in, and transmittance.

mod grid;
mod homogeneous;
pub mod phase;
mod stack;

pub use grid::GridMedium;
pub use homogeneous::Homogeneous;
pub use phase::HenyeyGreenstein;
pub use stack::MediumStack;

use crate::math::Spectrum;
use glam::Vec3;

/// The closed set of media.
#[derive(Clone, Debug)]
pub enum Medium {
    Homogeneous(Homogeneous),
    Grid(GridMedium),
}

impl Medium {
    pub fn phase(&self) -> HenyeyGreenstein {
        match self {
            Medium::Homogeneous(m) => m.phase,
            Medium::Grid(m) => m.phase,
        }
    }

    /// Scattering and extinction coefficients at a point.
    pub fn coefficients_at(&self, p: Vec3) -> (Spectrum, Spectrum) {
        match self {
            Medium::Homogeneous(m) => (m.sigma_s, m.sigma_t),
            Medium::Grid(m) => {
                let rho = m.density(p);
                (m.sigma_s * rho, Spectrum::splat(m.sigma_t * rho))
            }
        }
    }

    /// An upper bound of the extinction anywhere in the medium.
    pub fn majorant(&self) -> Spectrum {
        match self {
            Medium::Homogeneous(m) => m.sigma_t,
            Medium::Grid(m) => Spectrum::splat(m.sigma_t * m.max_density),
        }
    }

    /// Transmittance along `[0, dist]` of the ray from `o` along the unit direction `d`
    /// (exact for homogeneous media; the integrated optical depth for grids).
    pub fn transmittance_along(&self, o: Vec3, d: Vec3, dist: f32) -> Spectrum {
        match self {
            Medium::Homogeneous(m) => m.transmittance(dist),
            Medium::Grid(m) => {
                if dist.is_finite() {
                    m.transmittance(o, d, dist)
                } else {
                    m.transmittance(o, d, 1e30)
                }
            }
        }
    }
}
