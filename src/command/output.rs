//! Writing what a command made: the multilayer EXR (with the render's figures in its
//! metadata), the PNG preview and the stats JSON; or, for a block of pppm passes, its partial
//! sums, and for the photon-map step of a farm job, the photon maps. Every file is written to
//! a temporary name and renamed over its own, so no partial file ever has the final name.

use super::report;
use super::{exr, png};
use crate::cli::RenderArgs;
use crate::error::{Error, Result};
use crate::io::container;
use crate::render::film::Film;
use crate::render::RenderOutput;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

/// Where an image goes: the EXR, and optionally a PNG preview and the stats JSON.
#[derive(Clone, Copy, Debug)]
pub struct ImageFiles<'a> {
    pub exr: &'a Path,
    pub png: Option<&'a Path>,
    pub stats: Option<&'a Path>,
}

impl<'a> ImageFiles<'a> {
    /// The files a render command names.
    pub fn of(args: &'a RenderArgs) -> ImageFiles<'a> {
        ImageFiles {
            exr: &args.output,
            png: args.png.as_deref(),
            stats: args.stats.as_deref(),
        }
    }
}

/// Writes a render's outputs as `args` asks: the partial sums of a block of passes
/// (`--pass-range`), the photon maps (`--photon-maps-only`) or the EXR; then the PNG and the
/// stats JSON (with a front end's import statistics under `import`).
pub fn write_outputs(args: &RenderArgs, out: &RenderOutput, import: Option<&Value>) -> Result<()> {
    let stats = report::stats_json(&out.stats, import)?;
    let files = ImageFiles::of(args);
    match (&out.partial, &out.photon_maps) {
        (Some(partial), _) if args.pass_range.is_some() => partial.save(&args.output)?,
        (_, Some(set)) if args.photon_maps_only => set.save(&args.output)?,
        _ => write_exr(files.exr, &out.film, &stats)?,
    }
    if let Some(p) = files.png.filter(|_| !args.photon_maps_only) {
        write_png(p, &out.film)?;
    }
    if let Some(p) = files.stats {
        write_stats(p, &stats)?;
    }
    Ok(())
}

/// Writes an image made elsewhere (merged partial sums, assembled tiles) with its stats JSON.
pub fn write_image(files: ImageFiles, film: &Film, stats: &Value) -> Result<()> {
    write_exr(files.exr, film, stats)?;
    if let Some(p) = files.png {
        write_png(p, film)?;
    }
    if let Some(p) = files.stats {
        write_stats(p, stats)?;
    }
    Ok(())
}

/// The EXR metadata of an image with stats JSON `stats`: the version, seed, spp, photons
/// stored, seconds per pass and, when a denoiser ran, what denoised it (`denoise/<key>`).
pub fn exr_metadata(stats: &Value) -> BTreeMap<String, String> {
    let text = |v: &Value| match v {
        Value::String(s) => s.clone(),
        other => other.to_string(),
    };
    let mut meta = BTreeMap::new();
    meta.insert("version".into(), text(&stats["version"]));
    meta.insert("seed".into(), text(&stats["seed"]));
    meta.insert("spp".into(), text(&stats["spp"]));
    meta.insert("photons".into(), text(&stats["photons_stored"]));
    meta.insert("seconds".into(), text(&stats["seconds"]));
    if let Value::Object(d) = &stats["denoise"] {
        for (k, v) in d {
            meta.insert(format!("denoise/{k}"), text(v));
        }
    }
    meta
}

/// Writes `film` as a multilayer EXR with the metadata of `stats`, atomically.
pub fn write_exr(path: &Path, film: &Film, stats: &Value) -> Result<()> {
    let meta = exr_metadata(stats);
    container::with_temp_path(path, |tmp| {
        exr::write_multilayer(tmp, film, &meta).map_err(|e| match e {
            Error::Io { message, .. } => Error::io(path, message),
            other => other,
        })
    })
}

/// Writes the sRGB PNG preview of `film`'s beauty, atomically.
/// The sRGB preview of the beauty: RGBA where some pixel is not opaque (Film > Transparent,
/// a Holdout), else RGB.
pub fn write_png(path: &Path, film: &Film) -> Result<()> {
    let alpha = film
        .alpha
        .iter()
        .any(|&a| a < 1.0)
        .then_some(film.alpha.as_slice());
    container::with_temp_path(path, |tmp| {
        png::write_png(tmp, &film.combined(), 1.0, alpha)
    })
}

/// Writes stats JSON, pretty-printed, atomically.
pub fn write_stats(path: &Path, stats: &Value) -> Result<()> {
    let text = serde_json::to_string_pretty(stats).map_err(|e| Error::Internal(e.to_string()))?;
    container::write_atomic(path, text.as_bytes())
}
