//! One file per term of the rendering equation (Jensen 2001, §9.1). `indirect`, `caustic` and
//! `volume` are in the AOV list and written as zeros until their estimators exist.
pub mod direct;
pub mod emission;
pub mod specular;
