//! Scene IR, its validation, and the build from IR to the render scene.
pub mod desc;
mod validate;

pub use desc::SceneDesc;
pub use validate::validate;
