//! What the `render` and `merge` commands do, for the development binary and the Python
//! package's `photonmap` command alike (their arguments are `cli`'s):
//!
//! - `scene`: the scene a command names (the core's readers, or a front end's for USD);
//! - `render`: a render request (photon maps reused, kept, loaded or saved) and its render;
//! - `frames`: the render command, every frame of it, with what a front end brings to it;
//! - `merge`: merging the partial sums of blocks of pppm passes;
//! - `output`: writing the EXR, the PNG preview, the stats JSON, partial sums, photon maps;
//! - `exr`, `png`: the image files (multilayer EXR, written and read; the sRGB PNG preview);
//! - `report`: the stats JSON (of a render, a merge, or a frame's tiles) and summary lines;
//! - `progress`: the progress bar.

pub mod exr;
pub mod frames;
pub mod merge;
pub mod output;
pub mod png;
pub mod progress;
pub mod render;
pub mod report;
pub mod scene;

pub use frames::{run_render, Denoiser, Failure, FrameReuse, Frontend};
pub use merge::run_merge;
pub use render::{render_request, RenderRequest};
pub use scene::{LoadedScene, SceneLoader, SceneRequest};
