//! The scene a render command names: the embedded default, a JSON scene IR, or a USD stage
//! read by a front end's reader (the Python package's importer); then the command's image
//! size over the scene's film.

use crate::cli::RenderArgs;
use crate::error::{Error, Result};
use crate::io;
use crate::scene::SceneDesc;
use std::path::Path;

/// What a front end's scene reader (the Python package's USD importer) is asked to read.
#[derive(Debug, Clone)]
pub struct SceneRequest<'a> {
    pub path: &'a Path,
    /// USD time code; `None` = the stage's default time.
    pub frame: Option<f64>,
    pub camera: Option<&'a str>,
    /// Geometry purposes to include besides `default`.
    pub purposes: Vec<String>,
    pub strict: bool,
}

/// A scene read by a front end: the IR, plus its import statistics for the stats JSON.
pub struct LoadedScene {
    pub desc: SceneDesc,
    pub import_stats: Option<serde_json::Value>,
}

/// Reads scene formats the core does not read itself (USD stages).
pub type SceneLoader<'a> = dyn FnMut(&SceneRequest) -> Result<LoadedScene> + 'a;

/// True for the extensions of USD stages.
pub fn is_usd(path: &Path) -> bool {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    matches!(ext.as_str(), "usd" | "usda" | "usdc" | "usdz")
}

/// The scene of `frame`: a USD stage through `loader` (when one is given), anything else as
/// [`read`] reads it; with the command's size over its film.
pub fn load(
    args: &RenderArgs,
    frame: Option<f64>,
    loader: Option<&mut SceneLoader>,
) -> Result<LoadedScene> {
    match (&args.scene, loader) {
        (Some(p), Some(load)) if is_usd(p) => {
            if !p.exists() {
                return Err(Error::io(p, "no such file"));
            }
            let req = SceneRequest {
                path: p,
                frame,
                camera: args.camera.as_deref(),
                purposes: args
                    .purposes
                    .split(',')
                    .map(|s| s.trim().to_string())
                    .filter(|s| !s.is_empty())
                    .collect(),
                strict: args.strict,
            };
            let mut loaded = load(&req)?;
            apply_size(args, &mut loaded.desc)?;
            Ok(loaded)
        }
        _ => Ok(LoadedScene {
            desc: read(args)?,
            import_stats: None,
        }),
    }
}

/// The scene the core reads itself (the default, or a `.json` IR), with the command's size.
pub fn read(args: &RenderArgs) -> Result<SceneDesc> {
    let mut desc = match &args.scene {
        None => crate::scene::default_scene(),
        Some(p) => {
            let ext = p
                .extension()
                .and_then(|e| e.to_str())
                .unwrap_or("")
                .to_ascii_lowercase();
            if is_usd(p) {
                return Err(Error::io(
                    p,
                    "USD stages are read by the `photonmap` command of the Python package (pip install .)",
                ));
            }
            if ext != "json" {
                return Err(Error::io(p, format!("unsupported scene format `.{ext}`: expected .json, .usd, .usda, .usdc or .usdz")));
            }
            io::scene_json::load(p)?
        }
    };
    apply_size(args, &mut desc)?;
    Ok(desc)
}

/// `--width`/`--height` over the scene's film (one of them keeps its aspect ratio); then
/// validates the scene.
pub fn apply_size(args: &RenderArgs, desc: &mut SceneDesc) -> Result<()> {
    let (w0, h0) = (desc.film.width, desc.film.height);
    match (args.width, args.height) {
        (Some(w), Some(h)) => (desc.film.width, desc.film.height) = (w, h),
        (Some(w), None) => {
            desc.film.width = w;
            desc.film.height = ((w as u64 * h0 as u64) / w0.max(1) as u64).max(1) as u32;
        }
        (None, Some(h)) => {
            desc.film.height = h;
            desc.film.width = ((h as u64 * w0 as u64) / h0.max(1) as u64).max(1) as u32;
        }
        (None, None) => {}
    }
    crate::scene::validate(desc)
}
