//! Reading and writing: the JSON scene form, EXR and PNG images, and the container of the
//! renderer's own binary files (saved photon maps, partial sums of progressive passes).
pub mod container;
pub mod exr;
pub mod png;
pub mod scene_json;
