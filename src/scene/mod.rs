//! Scene IR, its validation, and the build from IR to the render scene.
pub mod build;
pub mod camera;
pub mod desc;
pub mod graph_desc;
pub mod lightgroups;
mod objects;
pub mod shading;
pub mod subsurface;
pub mod subsurface_walk;
mod transmit;
mod validate;

pub use build::{LightHit, Scene, SceneHit};
pub use desc::SceneDesc;
pub use validate::validate;

/// The scene drawn when none is given: a Cornell box with a glass sphere, a mirror sphere and a
/// rectangular area light.
pub const DEFAULT_SCENE_JSON: &str = include_str!("default_scene.json");

/// Parses the embedded default scene.
pub fn default_scene() -> SceneDesc {
    crate::io::scene_json::from_str(DEFAULT_SCENE_JSON)
        .expect("the embedded default scene is valid")
}
