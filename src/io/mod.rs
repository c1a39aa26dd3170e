//! Reading and writing below the renderer: the JSON scene form and the container of the
//! renderer's own binary files (saved photon maps, partial sums of progressive passes). The
//! images a render writes (EXR, PNG) are the command's (`command::exr`, `command::png`).
pub mod container;
pub mod scene_json;
