//! Reading and writing: the JSON scene form, EXR and PNG images.
pub mod exr;
pub mod png;
pub mod scene_json;
