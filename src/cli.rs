//! The one definition of the `render` command's arguments, shared by the development binary and
//! the `photonmap` command of the Python package, so the two never drift apart.

use crate::error::{Error, Result};
use crate::io;
use crate::io::container;
use crate::render::map_file::{self, MapSet};
use crate::render::{RenderOptions, RenderOutput, RenderSettings, Renderer};
use crate::scene::{Scene, SceneDesc};
use clap::{Args, Parser, Subcommand};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
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
    /// Merge the partial sums of blocks of pppm passes (`render --pass-range`) into the
    /// frame's image: the same bits as the frame rendered in one piece.
    Merge(MergeArgs),
}

/// What frames of one command do with the first frame's photon maps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum FrameMaps {
    /// Reuse: a frame whose scene matches the first frame's (the camera aside) renders
    /// with the first frame's photon maps and irradiance cache (extended for its view).
    #[default]
    Reuse,
    /// Rebuild: every frame builds its own.
    Rebuild,
}

#[derive(Args, Debug, Clone)]
pub struct MergeArgs {
    /// Partial-sum files (`.ppart`) of one frame, every block of its passes.
    #[arg(required = true, value_name = "PARTIAL")]
    pub partials: Vec<PathBuf>,
    /// Output multilayer EXR.
    #[arg(short = 'o', long = "output", value_name = "OUT.exr")]
    pub output: PathBuf,
    /// Write an sRGB PNG preview of the beauty.
    #[arg(long, value_name = "preview.png")]
    pub png: Option<PathBuf>,
    /// Write the merged render's statistics as JSON.
    #[arg(long, value_name = "stats.json")]
    pub stats: Option<PathBuf>,
    /// No summary line.
    #[arg(long)]
    pub quiet: bool,
}

#[derive(Args, Debug, Clone)]
pub struct RenderArgs {
    /// Scene file: .json scene IR, or a USD stage (.usd/.usda/.usdc/.usdz, read by the Python
    /// package's `photonmap` command); none renders the embedded default scene.
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
    /// The render settings (`render::options`, one schema with Python and Blender).
    #[command(flatten)]
    pub options: RenderOptions,
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
    /// pppm: render passes A..B (0-based, B excluded) of the `--spp` passes and write their
    /// partial sums (a `.ppart` file) to `-o` instead of an image; `photonmap merge` makes
    /// the image of all the blocks.
    #[arg(long, value_name = "A:B", value_parser = parse_pass_range)]
    pub pass_range: Option<(u32, u32)>,
    /// Jensen: build the photon maps and the irradiance cache for the (first) frame's view
    /// and write them to `-o` (a photon-map file, for `--load-photon-maps`), rendering no
    /// image: the photon-map step of a farm job.
    #[arg(long)]
    pub photon_maps_only: bool,
    /// Frames whose scene matches the first frame's, the camera aside: reuse its photon
    /// maps and irradiance cache (extended for each view), or rebuild them every frame.
    #[arg(long, value_enum, default_value_t = FrameMaps::Reuse)]
    pub frame_photon_maps: FrameMaps,
    /// Render on a Dask cluster (the Python package with `photonmap[distributed]`): a
    /// scheduler's address (`tcp://host:8786`), or `local:N` for N local worker processes.
    /// Frames are distributed; one frame is split into tiles (jensen) or blocks of passes
    /// (pppm). The output is the same as without it.
    #[arg(long, value_name = "ADDRESS|local:N")]
    pub cluster: Option<String>,
    /// With --cluster, one jensen frame: its tiles, as COLUMNSxROWS (default: 2x2 per
    /// worker).
    #[arg(long, value_name = "COLSxROWS", value_parser = parse_tiles)]
    pub tiles: Option<(u32, u32)>,
    /// With --cluster, one pppm frame: passes per block (default: spp over twice the
    /// workers).
    #[arg(long, value_name = "PASSES")]
    pub block_passes: Option<u32>,
}

/// Parses `A:B` (0 <= A < B), the passes of `--pass-range`.
pub fn parse_pass_range(s: &str) -> std::result::Result<(u32, u32), String> {
    let bad = || format!("`{s}` is not a range of passes A:B with A < B (e.g. 0:16)");
    let (a, b) = s.split_once(':').ok_or_else(bad)?;
    let a: u32 = a.trim().parse().map_err(|_| bad())?;
    let b: u32 = b.trim().parse().map_err(|_| bad())?;
    if a >= b {
        return Err(bad());
    }
    Ok((a, b))
}

/// Parses `CxR` (both at least 1), the tiles of `--tiles`.
pub fn parse_tiles(s: &str) -> std::result::Result<(u32, u32), String> {
    let bad = || format!("`{s}` is not COLUMNSxROWS (e.g. 2x2)");
    let (a, b) = s.split_once('x').ok_or_else(bad)?;
    let a: u32 = a.trim().parse().map_err(|_| bad())?;
    let b: u32 = b.trim().parse().map_err(|_| bad())?;
    if a == 0 || b == 0 {
        return Err(bad());
    }
    Ok((a, b))
}

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

/// Parses a usdrecord frame list: `7`, `1,5,9`, `1:10` or `1:10x2` (and lists of those).
pub fn parse_frames(spec: &str) -> Result<Vec<f64>> {
    let bad = |m: String| Error::InvalidSetting {
        setting: "frames".into(),
        message: m,
    };
    let num = |t: &str| -> Result<f64> {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| bad(format!("`{t}` is not a frame number")))
    };
    let mut out = Vec::new();
    for part in spec.split(',') {
        if let Some((a, rest)) = part.split_once(':') {
            let (b, step) = match rest.split_once('x') {
                Some((b, st)) => (num(b)?, num(st)?),
                None => (num(rest)?, 1.0),
            };
            let a = num(a)?;
            if step <= 0.0 || b < a {
                return Err(bad(format!(
                    "`{part}`: expected start:end with end >= start and a positive step"
                )));
            }
            let n = ((b - a) / step + 1e-9).floor() as usize;
            if n > 100_000 {
                return Err(bad(format!("`{part}` has more than 100000 frames")));
            }
            out.extend((0..=n).map(|i| a + i as f64 * step));
        } else {
            out.push(num(part)?);
        }
    }
    if out.is_empty() {
        return Err(bad("no frames given".into()));
    }
    Ok(out)
}

/// Replaces each run of `#` in a file name by the frame number, zero-padded to the run's
/// length (a single `#` pads to 4 digits). Fractional frames keep their fraction (`0001.5`).
pub fn frame_path(path: &Path, frame: f64) -> PathBuf {
    let text = path.to_string_lossy();
    if !text.contains('#') {
        return path.to_path_buf();
    }
    let whole = frame.trunc();
    let frac = frame - whole;
    let mut out = String::new();
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '#' {
            out.push(c);
            continue;
        }
        let mut n = 1;
        while chars.peek() == Some(&'#') {
            chars.next();
            n += 1;
        }
        let width = if n == 1 { 4 } else { n };
        let sign = if frame < 0.0 { "-" } else { "" };
        out.push_str(&format!("{sign}{:0width$}", whole.abs() as i64));
        if frac != 0.0 {
            let f = format!("{:.3}", frac.abs());
            out.push_str(f.trim_start_matches('0').trim_end_matches('0'));
        }
    }
    PathBuf::from(out)
}

impl RenderArgs {
    /// The arguments with every default, as `render -o OUT` would give them (for the Python API).
    pub fn defaults() -> RenderArgs {
        match Cli::try_parse_from(["photonmap", "render", "-o", "out.exr"]) {
            Ok(Cli {
                command: Command::Render(a),
            }) => a,
            Ok(_) => unreachable!("`render` parses as the render command"),
            Err(e) => unreachable!("the default arguments parse: {e}"),
        }
    }

    /// The frames to render: the parsed `--frames`, or one render at the default time.
    pub fn frame_list(&self) -> Result<Vec<Option<f64>>> {
        match &self.frames {
            None => Ok(vec![None]),
            Some(spec) => Ok(parse_frames(spec)?.into_iter().map(Some).collect()),
        }
    }

    /// These arguments with `#` in the output names replaced by `frame`.
    pub fn for_frame(&self, frame: Option<f64>) -> RenderArgs {
        let mut a = self.clone();
        if let Some(f) = frame {
            a.output = frame_path(&a.output, f);
            a.png = a.png.map(|p| frame_path(&p, f));
            a.stats = a.stats.map(|p| frame_path(&p, f));
        }
        a
    }

    /// Loads the scene through `loader` when the file is a USD stage (and a loader is given),
    /// otherwise as `load_scene` does; then applies the size overrides.
    pub fn load_scene_with(
        &self,
        frame: Option<f64>,
        loader: Option<&mut SceneLoader>,
    ) -> Result<LoadedScene> {
        match (&self.scene, loader) {
            (Some(p), Some(load)) if is_usd(p) => {
                if !p.exists() {
                    return Err(Error::io(p, "no such file"));
                }
                let req = SceneRequest {
                    path: p,
                    frame,
                    camera: self.camera.as_deref(),
                    purposes: self
                        .purposes
                        .split(',')
                        .map(|s| s.trim().to_string())
                        .filter(|s| !s.is_empty())
                        .collect(),
                    strict: self.strict,
                };
                let mut loaded = load(&req)?;
                self.apply_size(&mut loaded.desc)?;
                Ok(loaded)
            }
            _ => Ok(LoadedScene {
                desc: self.load_scene()?,
                import_stats: None,
            }),
        }
    }

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
        let mut s = self.options.settings();
        s.pass_range = self.pass_range;
        s
    }

    /// Checks the values clap cannot: the ranges of the schema, and the image size.
    pub fn check(&self) -> Result<()> {
        self.options.validate()?;
        if let Some((_, b)) = self.pass_range {
            if self.options.mode != crate::render::settings::RenderMode::Pppm {
                return Err(Error::InvalidSetting {
                    setting: "pass_range".into(),
                    message: "renders blocks of passes of the pppm mode: add --mode pppm".into(),
                });
            }
            let spp = self.settings().spp;
            if b > spp {
                return Err(Error::InvalidSetting {
                    setting: "pass_range".into(),
                    message: format!("ends at pass {b}, after the render's {spp} passes (--spp)"),
                });
            }
            if self.options.time_budget.is_some() {
                return Err(Error::InvalidSetting {
                    setting: "pass_range".into(),
                    message: "cannot be combined with --time-budget".into(),
                });
            }
        }
        if self.photon_maps_only {
            let s = self.settings();
            if s.mode != crate::render::settings::RenderMode::Jensen {
                return Err(Error::InvalidSetting {
                    setting: "photon_maps_only".into(),
                    message: "builds the maps of the jensen mode; the progressive modes trace \
                              a fresh map every pass"
                        .into(),
                });
            }
            if s.time_budget.is_some() || self.pass_range.is_some() {
                return Err(Error::InvalidSetting {
                    setting: "photon_maps_only".into(),
                    message: "cannot be combined with --time-budget or --pass-range".into(),
                });
            }
        }
        if self.cluster.is_some() {
            return Err(Error::InvalidSetting {
                setting: "cluster".into(),
                message: "renders on a Dask cluster through the Python package's photonmap \
                          command: pip install 'photonmap[distributed]'"
                    .into(),
            });
        }
        crate::render::map_file::check_settings(&self.settings())?;
        if self.width == Some(0) || self.height == Some(0) {
            return Err(Error::InvalidSetting {
                setting: "width/height".into(),
                message: "must be at least 1".into(),
            });
        }
        Ok(())
    }
}

/// Renders and writes every requested output. `progress` receives (fraction, phase). Errors
/// name settings by their flags ([`Error::for_cli`]).
pub fn run_render(
    args: &RenderArgs,
    progress: Option<Arc<crate::render::ProgressFn>>,
) -> Result<RenderOutput> {
    render_and_write(args, progress).map_err(Error::for_cli)
}

fn render_and_write(
    args: &RenderArgs,
    progress: Option<Arc<crate::render::ProgressFn>>,
) -> Result<RenderOutput> {
    let clock = args.wall_clock();
    args.check()?;
    if args.options.denoise {
        return Err(Error::InvalidSetting {
            setting: "denoise".into(),
            message: "denoising runs Open Image Denoise in the Python package's `photonmap` \
                      command (pip install 'photonmap[denoise]'), not in this binary"
                .into(),
        });
    }
    let desc = args.load_scene()?;
    let settings = args.settings_within(clock.as_ref(), 1);
    let output = clock.map(|_| args.output_time());
    let out = render_request(RenderRequest {
        progress,
        output_time: output,
        maps_only: args.photon_maps_only,
        ..RenderRequest::new(&desc, settings)
    })?;
    write_outputs(args, &out)?;
    Ok(out)
}

/// `photonmap merge`: the image of the partial sums of every block of a pppm frame.
pub fn run_merge(args: &MergeArgs) -> Result<crate::render::partial::Partial> {
    use crate::render::partial::Partial;
    let parts: Vec<Partial> = args
        .partials
        .iter()
        .map(|p| Partial::load(p))
        .collect::<Result<_>>()?;
    let merged = Partial::merge_all(&parts)?;
    merged.check_complete()?;
    write_merged(
        &merged,
        &args.output,
        args.png.as_deref(),
        args.stats.as_deref(),
    )?;
    Ok(merged)
}

/// Writes the image of a complete partial sum (EXR, optional PNG and stats), atomically.
pub fn write_merged(
    merged: &crate::render::partial::Partial,
    output: &Path,
    png: Option<&Path>,
    stats: Option<&Path>,
) -> Result<()> {
    write_merged_with(merged, output, png, stats, &merged_stats(merged))
}

/// As [`write_merged`], with the stats JSON `st`.
pub fn write_merged_with(
    merged: &crate::render::partial::Partial,
    output: &Path,
    png: Option<&Path>,
    stats: Option<&Path>,
    st: &serde_json::Value,
) -> Result<()> {
    let film = merged.film();
    let mut meta = BTreeMap::new();
    meta.insert("version".into(), env!("CARGO_PKG_VERSION").to_string());
    meta.insert("seed".into(), merged.header.seed.to_string());
    meta.insert("spp".into(), merged.passes().to_string());
    meta.insert("photons".into(), st["photons_stored"].to_string());
    meta.insert("seconds".into(), st["seconds"].to_string());
    write_exr_atomic(output, &film, &meta)?;
    if let Some(p) = png {
        container::with_temp_path(p, |tmp| io::png::write_png(tmp, &film.combined(), 1.0))?;
    }
    if let Some(p) = stats {
        let text = serde_json::to_string_pretty(&st).map_err(|e| Error::Internal(e.to_string()))?;
        container::write_atomic(p, text.as_bytes())?;
    }
    Ok(())
}

/// The stats JSON of a merged pppm image: what the partial sums hold (the scene's own
/// figures are in each block's stats).
pub fn merged_stats(p: &crate::render::partial::Partial) -> serde_json::Value {
    let t = &p.tally;
    let last = p.ranges.last().map_or(0, |r| r.1.saturating_sub(1));
    let options: serde_json::Value =
        serde_json::from_str(&p.options).unwrap_or(serde_json::Value::Null);
    serde_json::json!({
        "version": env!("CARGO_PKG_VERSION"),
        "mode": "pppm",
        "seed": p.header.seed,
        "width": p.header.width,
        "height": p.header.height,
        "spp": p.passes(),
        "seconds": {"photons": t.photon_seconds, "render": t.camera_seconds},
        "photons_stored": p.maps.iter().filter(|m| m.built)
            .map(|m| (m.map, m.stored)).collect::<BTreeMap<_, _>>(),
        "photon_maps": p.maps,
        "non_finite_samples": t.non_finite,
        "pppm": {
            "passes": p.passes(),
            "pass_ranges": p.ranges,
            "alpha": shortest(p.header.alpha),
            "initial_radius": shortest(p.header.initial_radius),
            "final_radius": shortest(crate::render::pppm::pass_radius2(
                p.header.initial_radius, p.header.alpha, last).sqrt()),
            "photons_per_pass": p.header.photons_per_pass,
            "photons_emitted": t.photons_emitted,
            "photon_seconds": t.photon_seconds,
            "camera_seconds": t.camera_seconds,
            "partials": t.partials,
        },
        "options": options,
    })
}

/// An `f32` as the JSON number of its shortest decimal (0.7, not 0.699999988).
fn shortest(v: f32) -> serde_json::Value {
    v.to_string()
        .parse::<f64>()
        .ok()
        .and_then(serde_json::Number::from_f64)
        .map_or(serde_json::Value::Null, serde_json::Value::Number)
}

/// Writes a multilayer EXR atomically (a temporary file renamed over `path`).
pub fn write_exr_atomic(
    path: &Path,
    film: &crate::render::film::Film,
    meta: &BTreeMap<String, String>,
) -> Result<()> {
    container::with_temp_path(path, |tmp| {
        io::exr::write_multilayer(tmp, film, meta).map_err(|e| match e {
            Error::Io { message, .. } => Error::io(path, message),
            other => other,
        })
    })
}

impl RenderArgs {
    /// The command's wall clock when `--time-budget` is given: it covers reading the scene,
    /// rendering and writing every output.
    pub fn wall_clock(&self) -> Option<crate::render::budget::WallClock> {
        self.options
            .time_budget
            .filter(|b| *b > 0.0)
            .map(crate::render::budget::WallClock::start)
    }

    /// The settings for one of `frames_left` frames: with a wall clock, the time budget is
    /// what is left of it (the render then leaves time for [`RenderArgs::output_time`]).
    pub fn settings_within(
        &self,
        clock: Option<&crate::render::budget::WallClock>,
        frames_left: usize,
    ) -> RenderSettings {
        let mut s = self.settings();
        if let Some(c) = clock {
            s.time_budget = Some(c.render_budget(frames_left, 0.0));
        }
        s
    }

    /// Seconds that writing this command's outputs for a film like `film` will take: the EXR
    /// (measured on a strip of the film), and a fifth more with a PNG preview.
    pub fn output_time(&self) -> Arc<crate::render::OutputTimeFn> {
        let png = self.png.is_some();
        Arc::new(move |film: &crate::render::film::Film| {
            crate::io::exr::estimate_write_seconds(film) * if png { 1.2 } else { 1.0 }
        })
    }
}

/// Builds the render scene from the IR and renders it; the build time goes into the stats and,
/// under a time budget, comes out of it.
pub fn render_desc(
    desc: &SceneDesc,
    settings: RenderSettings,
    progress: Option<Arc<crate::render::ProgressFn>>,
    cancel: Option<Arc<AtomicBool>>,
) -> Result<RenderOutput> {
    render_desc_with_preview(desc, settings, progress, cancel, None, None)
}

/// As `render_desc`, with previews of a progressive render (see `render::PreviewFn`).
pub fn render_desc_with_preview(
    desc: &SceneDesc,
    settings: RenderSettings,
    progress: Option<Arc<crate::render::ProgressFn>>,
    cancel: Option<Arc<AtomicBool>>,
    preview: Option<Arc<crate::render::PreviewFn>>,
    output_time: Option<Arc<crate::render::OutputTimeFn>>,
) -> Result<RenderOutput> {
    render_request(RenderRequest {
        progress,
        cancel,
        preview,
        output_time,
        ..RenderRequest::new(desc, settings)
    })
}

/// A render of a scene IR, with everything a front end may ask of it.
pub struct RenderRequest<'a> {
    pub desc: &'a SceneDesc,
    pub settings: RenderSettings,
    pub progress: Option<Arc<crate::render::ProgressFn>>,
    pub cancel: Option<Arc<AtomicBool>>,
    pub preview: Option<Arc<crate::render::PreviewFn>>,
    pub output_time: Option<Arc<crate::render::OutputTimeFn>>,
    /// Jensen: photon maps to use (an earlier frame's, or a set built for this frame); used
    /// only when their key is this render's.
    pub reuse: Option<Arc<MapSet>>,
    /// Jensen: keep the maps in the output (`RenderOutput::photon_maps`).
    pub keep_maps: bool,
    /// Jensen: build the maps and the cache only.
    pub maps_only: bool,
}

impl<'a> RenderRequest<'a> {
    pub fn new(desc: &'a SceneDesc, settings: RenderSettings) -> Self {
        RenderRequest {
            desc,
            settings,
            progress: None,
            cancel: None,
            preview: None,
            output_time: None,
            reuse: None,
            keep_maps: false,
            maps_only: false,
        }
    }
}

/// Renders a request: builds the scene, loads the photon maps it names (checking their key),
/// renders, and saves the maps where it says.
pub fn render_request(req: RenderRequest) -> Result<RenderOutput> {
    let t0 = std::time::Instant::now();
    let RenderRequest {
        desc,
        mut settings,
        progress,
        cancel,
        preview,
        output_time,
        mut reuse,
        keep_maps,
        maps_only,
    } = req;
    map_file::check_settings(&settings)?;
    let files = settings.photon_map_files.clone();
    use crate::render::settings::RenderMode;
    // Keys hash the whole scene: computed only where they are used.
    let keyed = match settings.mode {
        RenderMode::Pppm => true,
        RenderMode::Sppm => false,
        RenderMode::Jensen => {
            reuse.is_some() || keep_maps || maps_only || files != Default::default()
        }
    };
    let (keys, parts) = if keyed {
        (
            Some(map_file::keys(desc, &settings)),
            Some(map_file::key_parts(desc, &settings)),
        )
    } else {
        (None, None)
    };
    if let (Some(set), Some(k)) = (&reuse, keys) {
        if set.key != k.maps {
            reuse = None;
        }
    }
    let mut rebuilt_because = None;
    let mut loaded_from = None;
    if let (Some(path), Some(parts)) = (&files.load, &parts) {
        match MapSet::load(path, parts) {
            Ok(set) => {
                reuse = Some(Arc::new(set));
                loaded_from = Some(path.display().to_string());
            }
            Err(e) if files.on_mismatch == map_file::OnMismatch::Rebuild => {
                rebuilt_because = Some(e.to_string());
            }
            Err(e) => return Err(e),
        }
    }
    let scene = Scene::build_cancellable(desc, cancel.as_deref())?;
    let build_s = t0.elapsed().as_secs_f64();
    if let Some(b) = settings.time_budget.filter(|b| *b > 0.0) {
        settings.time_budget = Some((b - build_s).max(1e-3));
    }
    let save = files
        .save
        .clone()
        .filter(|p| Some(p) != files.load.as_ref() || reuse.is_none());
    let mut r = Renderer::new(&scene)
        .settings(settings)
        .keep_photon_maps(keep_maps || save.is_some())
        .maps_only(maps_only);
    if let (Some(k), Some(p)) = (keys, parts) {
        r = r.keys(k).key_parts(p);
    }
    if let Some(set) = reuse {
        r = r.reuse_photon_maps(set);
    }
    if let Some(p) = progress {
        r = r.progress(p);
    }
    if let Some(c) = cancel {
        r = r.cancel_flag(c);
    }
    if let Some(p) = preview {
        r = r.preview(p);
    }
    if let Some(o) = output_time {
        r = r.output_time(o);
    }
    let mut out = r.render()?;
    out.stats.seconds.insert("scene_build".into(), build_s);
    if let Some(st) = out.stats.photon_map_reuse.as_mut() {
        if loaded_from.is_some() {
            st.maps = "loaded".into();
        }
        st.loaded_from = loaded_from;
        st.rebuilt_because = rebuilt_because;
    }
    if let (Some(path), Some(set)) = (&save, &out.photon_maps) {
        set.save(path)?;
        if let Some(st) = out.stats.photon_map_reuse.as_mut() {
            st.saved_to = Some(path.display().to_string());
        }
    }
    Ok(out)
}

/// The photon maps kept across the frames of one command: the first frame's, reused by
/// every later frame whose key matches (the scene but its camera, the settings, the seed).
/// Frames depend on the first frame's maps only, so they render to the same bits in any
/// order and on any machine.
pub struct FrameReuse {
    enabled: bool,
    first: Option<Arc<MapSet>>,
}

impl FrameReuse {
    pub fn new(args: &RenderArgs, frames: usize) -> FrameReuse {
        let s = args.settings();
        FrameReuse {
            enabled: frames > 1
                && args.frame_photon_maps == FrameMaps::Reuse
                && s.mode == crate::render::settings::RenderMode::Jensen
                && s.time_budget.is_none()
                && s.photon_map_files.load.is_none(),
            first: None,
        }
    }

    /// The request of frame `index` (0 = the first): it keeps its maps when it is the
    /// first, and reuses the first's otherwise.
    pub fn request<'a>(&self, index: usize, mut req: RenderRequest<'a>) -> RenderRequest<'a> {
        if self.enabled {
            if index == 0 {
                req.keep_maps = true;
            } else {
                req.reuse = self.first.clone();
            }
        }
        req
    }

    /// Whether frames reuse the first frame's maps.
    pub fn enabled(&self) -> bool {
        self.enabled
    }

    /// After frame `index`: keeps the first frame's maps.
    pub fn rendered(&mut self, index: usize, out: &mut RenderOutput) {
        if index == 0 && self.enabled {
            self.first = out.photon_maps.take();
        } else {
            out.photon_maps = None;
        }
    }
}

/// The progress bar on stderr (hidden with `--quiet`) and the callback that drives it.
pub fn progress_bar(quiet: bool) -> (indicatif::ProgressBar, Arc<crate::render::ProgressFn>) {
    use indicatif::{ProgressBar, ProgressStyle};
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        let b = ProgressBar::new(1000);
        b.set_style(
            ProgressStyle::with_template(
                "{msg:>8} [{bar:40}] {percent:>3}% {elapsed_precise} eta {eta}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
        );
        b
    };
    let pb = bar.clone();
    let f: Arc<crate::render::ProgressFn> = Arc::new(move |f: f32, phase: &str| {
        pb.set_message(phase.to_string());
        pb.set_position((f * 1000.0) as u64);
    });
    (bar, f)
}

/// The lines printed after a render: what was written, and which terms are zero and why.
pub fn summary(args: &RenderArgs, out: &RenderOutput) -> String {
    let secs: f64 = out.stats.seconds.values().sum();
    if args.photon_maps_only {
        return format!(
            "wrote {} (photon maps: {}; {} irradiance-cache records; {secs:.2} s)",
            args.output.display(),
            out.stats
                .photons_stored
                .iter()
                .map(|(k, v)| format!("{k} {v}"))
                .collect::<Vec<_>>()
                .join(", "),
            out.stats.irradiance_cache_records
        );
    }
    let mut s = format!(
        "wrote {} ({}x{}, {} spp, {:.2} s)",
        args.output.display(),
        out.stats.width,
        out.stats.height,
        out.stats.spp,
        secs
    );
    for t in &out.stats.skipped {
        s.push_str(&format!("\n  {} is zero: {}", t.term, t.reason));
    }
    for w in &out.stats.warnings {
        s.push_str(&format!("\n  warning: {w}"));
    }
    s
}

/// Writes a film assembled elsewhere (tiles) with its stats JSON: the EXR with the
/// metadata `write_outputs` gives, the PNG and the stats, each atomically.
pub fn write_film_outputs(
    args: &RenderArgs,
    film: &crate::render::film::Film,
    stats: &serde_json::Value,
) -> Result<()> {
    let mut meta = BTreeMap::new();
    meta.insert("version".into(), env!("CARGO_PKG_VERSION").to_string());
    meta.insert("seed".into(), stats["seed"].to_string());
    meta.insert("spp".into(), stats["spp"].to_string());
    meta.insert("photons".into(), stats["photons_stored"].to_string());
    meta.insert("seconds".into(), stats["seconds"].to_string());
    write_exr_atomic(&args.output, film, &meta)?;
    if let Some(p) = &args.png {
        container::with_temp_path(p, |tmp| io::png::write_png(tmp, &film.combined(), 1.0))?;
    }
    if let Some(p) = &args.stats {
        let text =
            serde_json::to_string_pretty(stats).map_err(|e| Error::Internal(e.to_string()))?;
        container::write_atomic(p, text.as_bytes())?;
    }
    Ok(())
}

/// EXR (with metadata), optional PNG and stats JSON.
pub fn write_outputs(args: &RenderArgs, out: &RenderOutput) -> Result<()> {
    write_outputs_with(args, out, None)
}

/// As `write_outputs`, with a front end's import statistics under `import` in the stats JSON.
pub fn write_outputs_with(
    args: &RenderArgs,
    out: &RenderOutput,
    import_stats: Option<&serde_json::Value>,
) -> Result<()> {
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
    // The denoiser that ran, under `photonmap/denoise/...`: filter, version, binding, terms.
    if let Some(serde_json::Value::Object(d)) = &out.stats.denoise {
        for (k, v) in d {
            let v = match v {
                serde_json::Value::String(s) => s.clone(),
                other => other.to_string(),
            };
            meta.insert(format!("denoise/{k}"), v);
        }
    }
    match (&out.partial, &out.photon_maps) {
        (Some(partial), _) if args.pass_range.is_some() => partial.save(&args.output)?,
        (_, Some(set)) if args.photon_maps_only => set.save(&args.output)?,
        _ => write_exr_atomic(&args.output, &out.film, &meta)?,
    }
    if let Some(p) = args.png.as_ref().filter(|_| !args.photon_maps_only) {
        container::with_temp_path(p, |tmp| io::png::write_png(tmp, &out.film.combined(), 1.0))?;
    }
    if let Some(p) = &args.stats {
        // Through text, not `to_value`: that widens each `f32` to `f64` (0.7 -> 0.699999988).
        let mut v: serde_json::Value = serde_json::to_string(&out.stats)
            .and_then(|t| serde_json::from_str(&t))
            .map_err(|e| Error::Internal(e.to_string()))?;
        if let (Some(imp), Some(obj)) = (import_stats, v.as_object_mut()) {
            obj.insert("import".into(), imp.clone());
        }
        let text = serde_json::to_string_pretty(&v).map_err(|e| Error::Internal(e.to_string()))?;
        container::write_atomic(p, text.as_bytes())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_follow_usdrecord() {
        assert_eq!(parse_frames("7").unwrap(), vec![7.0]);
        assert_eq!(parse_frames("1,5,9").unwrap(), vec![1.0, 5.0, 9.0]);
        assert_eq!(
            parse_frames("1:10x2").unwrap(),
            vec![1.0, 3.0, 5.0, 7.0, 9.0]
        );
        assert_eq!(parse_frames("1:3").unwrap(), vec![1.0, 2.0, 3.0]);
        assert!(parse_frames("3:1").is_err() && parse_frames("a").is_err());
        assert_eq!(
            frame_path(Path::new("out.#.exr"), 7.0),
            Path::new("out.0007.exr")
        );
        assert_eq!(
            frame_path(Path::new("o_##.exr"), 3.0),
            Path::new("o_03.exr")
        );
        assert_eq!(frame_path(Path::new("o.exr"), 3.0), Path::new("o.exr"));
    }

    #[test]
    fn defaults_match_the_flags() {
        let a = RenderArgs::defaults();
        assert_eq!(a.options.quality, crate::render::Quality::Medium);
        assert_eq!(a.settings().spp, crate::render::Quality::Medium.spp());
    }
}
