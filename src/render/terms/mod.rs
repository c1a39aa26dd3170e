//! One file per term of the rendering equation (Jensen 2001, §9.1). `volume` is in the AOV
//! list and written as zeros until participating media exist.
pub mod caustic;
pub mod direct;
pub mod emission;
pub mod indirect;
pub mod specular;
