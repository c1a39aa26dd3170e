//! photonmap: a two-pass photon-mapping renderer after Jensen
//! ("Realistic Image Synthesis Using Photon Mapping", 2001).
//!
//! Modules follow the renderer's data flow: the scene IR (`scene::desc`) is validated and built
//! into a render scene (`scene::build`) with its acceleration structure (`geometry`),
//! materials and lights; the renderer (`render`) splits radiance into the terms of
//! `render::aov` and writes them (`io`).

pub mod cli;
pub mod command;
pub mod error;
pub mod geometry;
pub mod io;
pub mod lights;
pub mod materials;
pub mod math;
pub mod media;
pub mod photon;
pub mod render;
pub mod sampling;
pub mod scene;

pub use error::{Error, Result};
#[cfg(feature = "python")]
mod python;
#[cfg(test)]
#[path = "python/pointer.rs"]
mod python_pointer;
