//! The one definition of the `render` and `merge` commands' arguments, shared by the
//! development binary and the `photonmap` command of the Python package, so the two never
//! drift apart: the clap structs, the parsers of their values and the checks clap cannot make.
//! What the commands do is `command`.

use crate::error::{Error, Result};
use crate::render::RenderSettings;
use clap::{Args, Parser, Subcommand};
use std::path::{Path, PathBuf};

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

impl Cli {
    /// Parses a command line (the program name first), as clap does; the render command's
    /// preset settings that are not given take the `--quality` preset's values.
    pub fn parse_args<I, T>(args: I) -> std::result::Result<Cli, clap::Error>
    where
        I: IntoIterator<Item = T>,
        T: Into<std::ffi::OsString> + Clone,
    {
        use clap::parser::ValueSource;
        let m = <Cli as clap::CommandFactory>::command().try_get_matches_from(args)?;
        let mut cli = <Cli as clap::FromArgMatches>::from_arg_matches(&m)?;
        if let (Command::Render(a), Some(("render", sub))) = (&mut cli.command, m.subcommand()) {
            a.options
                .apply_preset(|name| sub.value_source(name) == Some(ValueSource::CommandLine));
        }
        Ok(cli)
    }
}

// Parsed once per command: boxing the render arguments would only complicate every match.
#[allow(clippy::large_enum_variant)]
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
    /// The render settings (`render::settings`, one schema with Python and Blender).
    #[command(flatten)]
    pub options: RenderSettings,
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
        match Cli::parse_args(["photonmap", "render", "-o", "out.exr"]) {
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

    /// The preset, with every explicit flag applied over it.
    pub fn settings(&self) -> RenderSettings {
        let mut s = self.options.clone();
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
            if s.budget_seconds().is_some() || self.pass_range.is_some() {
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
        assert_eq!(a.settings(), crate::render::RenderSettings::default());
    }
}
