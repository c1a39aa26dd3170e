//! Random numbers and the warps from the unit square to the shapes the renderer samples.
pub mod chi2;
mod distribution;
mod rng;
mod sobol;
pub mod warp;

pub use distribution::{Distribution1D, Distribution2D};
pub use rng::{mix64, Rng};
pub use sobol::{sobol02, to_unit};
