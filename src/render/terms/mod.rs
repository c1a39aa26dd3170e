//! One file per term of the rendering equation (Jensen 2001, §9.1; media, chapter 10).
pub mod caustic;
pub mod direct;
pub mod emission;
pub mod indirect;
pub mod specular;
pub mod volume;
