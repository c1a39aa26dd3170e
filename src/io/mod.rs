//! Reading and writing: the JSON scene form, EXR and PNG images.
pub mod scene_json;
