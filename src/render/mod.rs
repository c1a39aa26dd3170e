//! The second pass: camera rays, the terms, and the film.
pub mod aov;
pub mod budget;
mod cache_fill;
pub mod error;
pub mod eye;
pub mod film;
pub mod irradiance_cache;
pub mod photons;
mod renderer;
pub mod settings;
pub mod sppm;
pub mod terms;
pub mod work;

pub use renderer::{
    MemoryEstimate, OutputTimeFn, PreviewFn, ProgressFn, RenderOutput, RenderStats, Renderer,
    SkippedTerm,
};
pub use settings::{PhotonSettings, Quality, RenderSettings};
