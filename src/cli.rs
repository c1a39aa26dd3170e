//! The one definition of the `render` command's arguments, shared by the development binary and
//! the `photonmap` command of the Python package, so the two never drift apart.

use crate::error::{Error, Result};
use crate::io;
use crate::render::{film::Filter, Quality, RenderOutput, RenderSettings, Renderer};
use crate::scene::{Scene, SceneDesc};
use clap::{Args, Parser, Subcommand};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;

#[derive(Parser, Debug)]
#[command(
    name = "photonmap",
    version,
    about = "Photon-mapping renderer: caustics, glass, mirrors and fog"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene to a multilayer EXR (beauty plus one layer per term).
    Render(RenderArgs),
}

#[derive(Args, Debug, Clone)]
pub struct RenderArgs {
    /// Scene file (.json scene IR); none renders the embedded default scene.
    pub scene: Option<PathBuf>,
    /// Output multilayer EXR.
    #[arg(short = 'o', long = "output", value_name = "OUT.exr")]
    pub output: PathBuf,
    /// Image width in pixels (overrides the scene's film).
    #[arg(long, visible_alias = "imageWidth")]
    pub width: Option<u32>,
    /// Image height in pixels (default: keeps the scene's aspect ratio when only --width is given).
    #[arg(long)]
    pub height: Option<u32>,
    /// Quality preset: draft, medium, high, final.
    #[arg(long, default_value = "medium", value_parser = parse_quality)]
    pub quality: Quality,
    /// Camera samples per pixel (overrides the preset).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Random seed; the same seed gives the same image for any thread count.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads (0 = all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Maximum number of perfectly specular bounces followed from the eye.
    #[arg(long, default_value_t = 8)]
    pub max_specular_depth: u32,
    /// Pixel filter: box, tent, gaussian.
    #[arg(long, default_value = "gaussian", value_parser = parse_filter)]
    pub filter: Filter,
    /// Photons to store in the global map (overrides the preset).
    #[arg(long)]
    pub photons: Option<usize>,
    /// Photons to store in the caustic map (overrides the preset).
    #[arg(long)]
    pub caustic_photons: Option<usize>,
    /// Photons per radiance estimate (k nearest).
    #[arg(long)]
    pub gather: Option<usize>,
    /// Largest photon search radius, in scene units (default: from the scene size).
    #[arg(long)]
    pub radius: Option<f32>,
    /// Final-gathering rays per irradiance-cache record, and per pixel elsewhere (overrides the preset).
    #[arg(long)]
    pub final_gather_rays: Option<u32>,
    /// Irradiance caching for final gathering: on or off.
    #[arg(long, value_parser = parse_on_off)]
    pub irradiance_cache: Option<bool>,
    /// Irradiance-cache error tolerance (Ward's a; smaller is more accurate and slower).
    #[arg(long)]
    pub cache_tolerance: Option<f32>,
    /// USD: camera prim path to render through (default: the first camera found).
    #[arg(long, value_name = "PRIM")]
    pub camera: Option<String>,
    /// USD: frames to render, as usdrecord: `1:10x2`, `1,5,9` or `7`. With several frames,
    /// `#` characters in the output name are replaced by the zero-padded frame number.
    #[arg(long)]
    pub frames: Option<String>,
    /// USD: geometry purposes to include besides `default` (usdrecord's --purposes).
    #[arg(long, default_value = "render")]
    pub purposes: String,
    /// USD: refinement complexity (accepted for usdrecord compatibility).
    #[arg(long)]
    pub complexity: Option<String>,
    /// USD: treat importer warnings as errors.
    #[arg(long)]
    pub strict: bool,
    /// Write render statistics as JSON.
    #[arg(long, value_name = "stats.json")]
    pub stats: Option<PathBuf>,
    /// Write an sRGB PNG preview of the beauty.
    #[arg(long, value_name = "preview.png")]
    pub png: Option<PathBuf>,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
}

fn parse_quality(s: &str) -> std::result::Result<Quality, String> {
    Quality::parse(s)
        .ok_or_else(|| format!("unknown quality `{s}` (expected draft, medium, high or final)"))
}

fn parse_on_off(s: &str) -> std::result::Result<bool, String> {
    match s {
        "on" | "true" | "1" => Ok(true),
        "off" | "false" | "0" => Ok(false),
        _ => Err(format!("expected on or off, got `{s}`")),
    }
}

fn parse_filter(s: &str) -> std::result::Result<Filter, String> {
    Filter::parse(s).ok_or_else(|| format!("unknown filter `{s}` (expected box, tent or gaussian)"))
}

impl RenderArgs {
    /// Loads the scene named on the command line (or the default) and applies size overrides.
    pub fn load_scene(&self) -> Result<SceneDesc> {
        let mut desc = match &self.scene {
            None => crate::scene::default_scene(),
            Some(p) => {
                let ext = p
                    .extension()
                    .and_then(|e| e.to_str())
                    .unwrap_or("")
                    .to_ascii_lowercase();
                if matches!(ext.as_str(), "usd" | "usda" | "usdc" | "usdz") {
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
        self.apply_size(&mut desc)?;
        Ok(desc)
    }

    pub fn apply_size(&self, desc: &mut SceneDesc) -> Result<()> {
        let (w0, h0) = (desc.film.width, desc.film.height);
        match (self.width, self.height) {
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

    /// The preset, with every explicit flag applied over it.
    pub fn settings(&self) -> RenderSettings {
        let mut s = self.quality.settings();
        s.spp = self.spp.unwrap_or(s.spp);
        s.seed = self.seed;
        s.threads = self.threads;
        s.max_specular_depth = self.max_specular_depth;
        s.filter = self.filter.clone();
        let p = &mut s.photons;
        p.global = self.photons.unwrap_or(p.global);
        p.caustic = self.caustic_photons.unwrap_or(p.caustic);
        p.gather = self.gather.unwrap_or(p.gather);
        p.max_radius = self.radius.or(p.max_radius);
        p.final_gather_rays = self.final_gather_rays.unwrap_or(p.final_gather_rays);
        p.irradiance_cache = self.irradiance_cache.unwrap_or(p.irradiance_cache);
        p.cache_tolerance = self.cache_tolerance.unwrap_or(p.cache_tolerance);
        s
    }

    /// Checks the values clap cannot: positive counts and radii.
    pub fn check(&self) -> Result<()> {
        let bad = |setting: &str, message: &str| {
            Err(Error::InvalidSetting {
                setting: setting.into(),
                message: message.into(),
            })
        };
        if self.spp == Some(0) {
            return bad("--spp", "must be at least 1");
        }
        if self.gather == Some(0) {
            return bad("--gather", "must be at least 1");
        }
        if let Some(r) = self.radius {
            if !(r.is_finite() && r > 0.0) {
                return bad("--radius", "must be a finite number > 0");
            }
        }
        if let Some(t) = self.cache_tolerance {
            if !(t.is_finite() && t > 0.0) {
                return bad("--cache-tolerance", "must be a finite number > 0");
            }
        }
        if self.width == Some(0) || self.height == Some(0) {
            return bad("--width/--height", "must be at least 1");
        }
        Ok(())
    }
}

/// Renders and writes every requested output. `progress` receives (fraction, phase).
pub fn run_render(
    args: &RenderArgs,
    progress: Option<Arc<crate::render::ProgressFn>>,
) -> Result<RenderOutput> {
    args.check()?;
    let t0 = std::time::Instant::now();
    let desc = args.load_scene()?;
    let scene = Scene::build(&desc)?;
    let build_s = t0.elapsed().as_secs_f64();
    let mut r = Renderer::new(&scene).settings(args.settings());
    if let Some(p) = progress {
        r = r.progress(p);
    }
    let mut out = r.render()?;
    out.stats.seconds.insert("scene_build".into(), build_s);
    write_outputs(args, &out)?;
    Ok(out)
}

/// EXR (with metadata), optional PNG and stats JSON.
pub fn write_outputs(args: &RenderArgs, out: &RenderOutput) -> Result<()> {
    let mut meta = BTreeMap::new();
    meta.insert("version".into(), out.stats.version.to_string());
    meta.insert("seed".into(), out.stats.seed.to_string());
    meta.insert("spp".into(), out.stats.spp.to_string());
    meta.insert(
        "photons".into(),
        serde_json::to_string(&out.stats.photons_stored).unwrap_or_default(),
    );
    meta.insert(
        "seconds".into(),
        serde_json::to_string(&out.stats.seconds).unwrap_or_default(),
    );
    io::exr::write_multilayer(&args.output, &out.film, &meta)?;
    if let Some(p) = &args.png {
        io::png::write_png(p, &out.film.combined(), 1.0)?;
    }
    if let Some(p) = &args.stats {
        let text =
            serde_json::to_string_pretty(&out.stats).map_err(|e| Error::Internal(e.to_string()))?;
        std::fs::write(p, text).map_err(|e| Error::io(p, e))?;
    }
    Ok(())
}
