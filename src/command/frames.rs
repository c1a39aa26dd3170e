//! The render command: every frame it names, each read, rendered (with the first frame's
//! photon maps where they fit), denoised when asked and written, under one wall clock when
//! the command has a time budget. The development binary and the Python package's
//! `photonmap` command both run it; a front end brings what the core lacks ([`Frontend`]).

use super::output;
use super::progress::progress_bar;
use super::render::{render_request, RenderRequest};
use super::report;
use super::scene::{self, SceneLoader};
use crate::cli::{FrameMaps, RenderArgs};
use crate::error::{Error, Result};
use crate::render::budget::WallClock;
use crate::render::map_file::MapSet;
use crate::render::settings::RenderMode;
use crate::render::{OutputTimeFn, RenderOutput, RenderSettings};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Runs one frame's render request.
pub type Runner<'a> = dyn FnMut(RenderRequest) -> Result<RenderOutput> + 'a;

/// Denoises rendered frames (`--denoise`): Open Image Denoise, which the Python package runs.
pub trait Denoiser {
    /// Why the denoiser cannot run, if it cannot; asked before any frame renders.
    fn check(&mut self) -> std::result::Result<(), String>;
    /// Replaces the denoised terms of `out`'s film, and records what denoised them in its
    /// stats (`denoise`).
    fn denoise(&mut self, out: &mut RenderOutput) -> std::result::Result<(), String>;
}

/// What a front end brings to [`run_render`]. The default is the core alone: the scenes it
/// reads itself, renders on the calling thread, no denoiser.
#[derive(Default)]
pub struct Frontend<'a> {
    /// Reads the scenes the core does not read (USD stages).
    pub scene_loader: Option<Box<SceneLoader<'a>>>,
    /// Runs each frame's render (the Python package: on another thread, while the calling
    /// one watches for Ctrl-C); by default `render_request` on the calling thread.
    pub runner: Option<Box<Runner<'a>>>,
    /// Denoises the frames of `--denoise`; without one, `--denoise` is an error.
    pub denoiser: Option<Box<dyn Denoiser + 'a>>,
    /// Every frame's cancel flag: set, it stops the render under way.
    pub cancel: Option<Arc<AtomicBool>>,
}

/// Why a command stopped: what follows `photonmap: error: `, and the exit status (2: the
/// command line's settings are wrong; 1: anything else).
#[derive(Debug)]
pub struct Failure {
    pub message: String,
    pub status: i32,
}

impl Failure {
    /// An error of the command outside its renders: the settings' are the command line's.
    fn command(e: Error) -> Failure {
        let e = e.for_cli();
        let status = if matches!(e, Error::InvalidSetting { .. }) {
            2
        } else {
            1
        };
        Failure {
            message: e.to_string(),
            status,
        }
    }

    /// An error of a render.
    fn render(e: Error) -> Failure {
        Failure {
            message: e.for_cli().to_string(),
            status: 1,
        }
    }

    fn denoise(message: String, status: i32) -> Failure {
        Failure {
            message: format!("--denoise: {message}"),
            status,
        }
    }
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

/// `photonmap render`: renders every frame of `args` and writes its outputs, printing the
/// progress and a summary of each frame on stderr (unless `--quiet`).
pub fn run_render(args: &RenderArgs, mut fe: Frontend) -> std::result::Result<(), Failure> {
    // Under --time-budget the command's wall clock runs from here: reading each scene,
    // building it, rendering and writing every frame all count.
    let clock = wall_clock(args);
    args.check().map_err(Failure::command)?;
    if args.options.denoise {
        match fe.denoiser.as_mut() {
            Some(d) => d.check().map_err(|m| Failure::denoise(m, 2))?,
            None => {
                return Err(Failure::command(Error::InvalidSetting {
                    setting: "denoise".into(),
                    message: "denoising runs Open Image Denoise in the Python package's \
                              `photonmap` command (pip install 'photonmap[denoise]'), not in \
                              this binary"
                        .into(),
                }))
            }
        }
    }
    let frames = args.frame_list().map_err(Failure::command)?;
    let mut reuse = FrameReuse::new(args, frames.len());
    for (i, &frame) in frames.iter().enumerate() {
        let a = args.for_frame(frame);
        let loaded =
            scene::load(&a, frame, fe.scene_loader.as_deref_mut()).map_err(Failure::command)?;
        let (bar, progress) = progress_bar(a.quiet);
        let settings = settings_within(&a, clock.as_ref(), frames.len() - i);
        let request = reuse.request(
            i,
            RenderRequest {
                progress: Some(progress),
                cancel: fe.cancel.clone(),
                output_time: clock.map(|_| output_time(&a)),
                maps_only: a.photon_maps_only,
                ..RenderRequest::new(&loaded.desc, settings)
            },
        );
        let rendered = match fe.runner.as_mut() {
            Some(run) => run(request),
            None => render_request(request),
        };
        let mut out = rendered.map_err(|e| {
            bar.abandon();
            Failure::render(e)
        })?;
        bar.finish_and_clear();
        if let (true, Some(d)) = (
            a.options.denoise && !a.photon_maps_only,
            fe.denoiser.as_mut(),
        ) {
            d.denoise(&mut out).map_err(|m| Failure::denoise(m, 1))?;
        }
        output::write_outputs(&a, &out, loaded.import_stats.as_ref()).map_err(Failure::command)?;
        reuse.rendered(i, &mut out);
        if !a.quiet {
            eprintln!("{}", report::summary(&a, &out));
        }
        if a.photon_maps_only {
            // The maps of the first frame's view; later frames load them.
            break;
        }
    }
    Ok(())
}

/// The command's wall clock when `--time-budget` is given: it covers reading the scene,
/// rendering and writing every output.
fn wall_clock(args: &RenderArgs) -> Option<WallClock> {
    args.options
        .time_budget
        .filter(|b| *b > 0.0)
        .map(WallClock::start)
}

/// The settings of one of `frames_left` frames: with a wall clock, the time budget is what
/// is left of it (the render then leaves time for [`output_time`]).
fn settings_within(
    args: &RenderArgs,
    clock: Option<&WallClock>,
    frames_left: usize,
) -> RenderSettings {
    let mut s = args.settings();
    if let Some(c) = clock {
        s.time_budget = Some(c.render_budget(frames_left, 0.0));
    }
    s
}

/// Seconds that writing the outputs of `args` for a film like the one given will take: the
/// EXR (measured on a strip of the film), and a fifth more with a PNG preview.
fn output_time(args: &RenderArgs) -> Arc<OutputTimeFn> {
    let png = args.png.is_some();
    Arc::new(move |film: &crate::render::film::Film| {
        super::exr::estimate_write_seconds(film) * if png { 1.2 } else { 1.0 }
    })
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
                && s.mode == RenderMode::Jensen
                && s.budget_seconds().is_none()
                && s.photon_map_files().load.is_none(),
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
