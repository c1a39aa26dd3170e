//! The second pass: camera rays, the terms, and the film.
pub mod aov;
pub mod eye;
pub mod film;
mod renderer;
pub mod terms;

pub use renderer::{
    ProgressFn, Quality, RenderOutput, RenderSettings, RenderStats, Renderer, SkippedTerm,
};
