//! The second pass: camera rays, the terms, and the film.
pub mod aov;
pub mod eye;
pub mod film;
mod renderer;
pub mod settings;
pub mod terms;

pub use renderer::{ProgressFn, RenderOutput, RenderStats, Renderer, SkippedTerm};
pub use settings::{PhotonSettings, Quality, RenderSettings};
