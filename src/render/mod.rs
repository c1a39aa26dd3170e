//! The second pass: camera rays, the terms, and the film.
pub mod adaptive;
pub mod aov;
pub mod budget;
mod cache_fill;
pub mod driver;
pub mod error_aov;
pub mod eye;
pub mod film;
pub mod irradiance_cache;
mod jensen;
pub mod map_file;
mod memory;
pub mod options;
pub mod photons;
pub mod pppm;
mod renderer;
pub mod settings;
pub mod sppm;
mod stats;
pub mod terms;
pub mod tile;
pub mod work;

pub use memory::MemoryEstimate;
pub use options::RenderOptions;
pub use renderer::{OutputTimeFn, PreviewFn, ProgressFn, RenderKeys, RenderOutput, Renderer};
pub use settings::{PhotonSettings, Quality, RenderSettings};
pub use stats::{RenderStats, SkippedTerm};
