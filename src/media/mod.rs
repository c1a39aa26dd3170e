//! Participating media (Jensen 2001, chapter 10; Jensen & Christensen 1998): homogeneous
//! media with a Henyey-Greenstein phase function, the stack that tracks which medium a ray is
//! in, and transmittance.

mod homogeneous;
pub mod phase;
mod stack;

pub use homogeneous::Homogeneous;
pub use phase::HenyeyGreenstein;
pub use stack::MediumStack;

use crate::math::Spectrum;

/// The closed set of media.
#[derive(Clone, Debug)]
pub enum Medium {
    Homogeneous(Homogeneous),
}

impl Medium {
    pub fn sigma_t(&self) -> Spectrum {
        match self {
            Medium::Homogeneous(m) => m.sigma_t,
        }
    }
    pub fn sigma_s(&self) -> Spectrum {
        match self {
            Medium::Homogeneous(m) => m.sigma_s,
        }
    }
    pub fn phase(&self) -> HenyeyGreenstein {
        match self {
            Medium::Homogeneous(m) => m.phase,
        }
    }
    /// Transmittance over a distance `d` (exact for homogeneous media).
    pub fn transmittance(&self, d: f32) -> Spectrum {
        match self {
            Medium::Homogeneous(m) => m.transmittance(d),
        }
    }
}
