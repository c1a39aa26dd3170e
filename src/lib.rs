//! photonmap: a two-pass photon-mapping renderer after Jensen
//! ("Realistic Image Synthesis Using Photon Mapping", 2001).

pub mod error;
pub mod materials;
pub mod math;
pub mod sampling;
pub mod scene;

pub use error::{Error, Result};
pub mod io;
