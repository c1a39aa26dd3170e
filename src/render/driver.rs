//! The camera-pass driver: the pixel loop that every render mode (`jensen`, `sppm`, `pppm`)
//! runs. It owns what is the same in all: each pixel's random stream and film positions, the
//! replicates of the `error` AOV, the finite-sample firewall, the schedule of passes (a count
//! or a deadline), previews, progress and cancellation. An [`Integrator`] supplies what
//! differs: what a pass prepares, what one camera sample adds, how a pixel resolves into the
//! film, and what a pixel accumulates (`accumulate`: f32 sums, or the fixed-point sums that
//! pppm merges).
//!
//! Deterministic: pixel `i` draws from its own stream `Rng::new(seed, i)`, which continues
//! across passes, and pixels are independent, so the film is bit-identical for any thread
//! count, and after `k` passes it is the same however many follow.

use super::accumulate::{Accumulator, Sums};
use super::compositing::{AovLayout, PixelAovs, SampleAovs};
use super::error_aov::Shifts;
use super::eye;
use super::film::{Film, Filter, TermRadiance};
use crate::error::{Error, Result};
use crate::geometry::Ray;
use crate::math::Spectrum;
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::Vec2;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

/// Called with (fraction done in [0,1], phase name). May be called from worker threads.
pub type ProgressFn = dyn Fn(f32, &str) + Send + Sync;

/// Called during a progressive render (`progressive`, a time budget, or `RenderMode::Sppm`)
/// with the image so far and the passes it holds: after passes 1, 2, 4, 8, ... and at most
/// every [`PREVIEW_SECONDS`] between them. The Blender viewport refines through it.
pub type PreviewFn = dyn Fn(&Film, u32) + Send + Sync;

/// Seconds that writing out a film like this one will take (called once, with the film after
/// the first camera pass of a budgeted render, whose last passes leave that much time free).
pub type OutputTimeFn = dyn Fn(&Film) -> f64 + Send + Sync;

/// Shortest interval between two previews, in seconds (powers of two aside).
pub const PREVIEW_SECONDS: f64 = 0.25;

/// Whether a progressive loop that last previewed at `last` should preview after `passes`.
pub fn preview_due(passes: u32, last: &mut Instant) -> bool {
    if passes.is_power_of_two() || last.elapsed().as_secs_f64() >= PREVIEW_SECONDS {
        *last = Instant::now();
        return true;
    }
    false
}

/// The state the driver keeps per pixel; `extra` is the integrator's own.
pub struct Pixel<X, A = Sums> {
    pub rng: Rng,
    /// Sums over samples of the terms the integrator estimated at the eye (finite ones only)
    /// and of the combined image per replicate (the `error` AOV).
    pub sums: A,
    /// Sums of the compositing AOVs (`render::compositing`), when asked for.
    pub aovs: PixelAovs,
    pub extra: X,
}

impl<X: Default, A: Default> Pixel<X, A> {
    pub fn new(rng: Rng) -> Self {
        Pixel {
            rng,
            sums: A::default(),
            aovs: PixelAovs::default(),
            extra: X::default(),
        }
    }
}

/// What a render mode supplies to the driver.
pub trait Integrator: Sync {
    /// Per-pixel state beyond the driver's.
    type Extra: Send + Sync + Default;
    /// What a pixel sums over its samples.
    type Acc: Accumulator;
    /// Per-worker scratch space.
    type Scratch: Send;
    /// What the camera samples of one pass read.
    type Pass: Sync;

    fn scratch(&self) -> Self::Scratch;

    /// Prepares pass `k`, before its camera samples.
    fn begin_pass(&mut self, k: u32) -> Result<Self::Pass>;

    /// After pass `k`'s camera samples, which took `camera_seconds`.
    fn end_pass(&mut self, _pass: Self::Pass, _camera_seconds: f64) {}

    /// A random stream of its own for pixel `pixel` in a progressive pass; `None` continues
    /// the pixel's stream from pass to pass.
    fn pass_rng(&self, _pass: &Self::Pass, _pixel: usize) -> Option<Rng> {
        None
    }

    /// Sample `k` of a pixel along `ray`: the terms estimated at the eye, which the driver
    /// adds to the pixel where finite, and this sample's further share of the combined image
    /// (which the integrator keeps in `extra`; zero if none). What the sample gives the
    /// compositing AOVs goes into `aovs` (those it asks for).
    #[allow(clippy::too_many_arguments)]
    fn sample(
        &self,
        pass: &Self::Pass,
        ray: Ray,
        rng: &mut Rng,
        extra: &mut Self::Extra,
        k: u32,
        scratch: &mut Self::Scratch,
        aovs: &mut SampleAovs,
    ) -> (TermRadiance, Spectrum);

    /// The pixel's terms and `error` after `samples` samples.
    fn resolve(
        &self,
        px: &Pixel<Self::Extra, Self::Acc>,
        samples: u32,
    ) -> (TermRadiance, Spectrum) {
        px.sums.resolve(samples)
    }

    /// Adds to the pixel's light groups (the means of its samples' shares, one entry per
    /// group) what the integrator keeps apart from its samples.
    fn resolve_groups(
        &self,
        _px: &Pixel<Self::Extra, Self::Acc>,
        _samples: u32,
        _groups: &mut [Spectrum],
    ) {
    }
}

/// Seconds kept free at the end of the budget for writing out the film, as a fraction of
/// the budget, plus a fixed part.
pub const MARGIN_FRACTION: f64 = 0.01;
pub const MARGIN_SECONDS: f64 = 0.005;

/// Seconds since the render's start by which the last camera pass under `budget_seconds`
/// must end: the budget less the margin for writing the film out.
pub fn deadline(budget_seconds: f64) -> f64 {
    budget_seconds - MARGIN_FRACTION * budget_seconds - MARGIN_SECONDS
}

/// When a progressive camera pass stops.
#[derive(Clone, Copy, Debug)]
pub enum Schedule {
    /// After this many passes.
    Passes(u32),
    /// When the next pass, at the mean time per pass so far, would end after `deadline`
    /// seconds since `start` (at least one pass).
    Deadline { start: Instant, deadline: f64 },
}

impl Schedule {
    /// `spp` passes, or under a time budget (seconds since `start`) as many as fit.
    pub fn of(time_budget: Option<f64>, spp: u32, start: Instant) -> Schedule {
        match time_budget {
            Some(b) => Schedule::Deadline {
                start,
                deadline: deadline(b),
            },
            None => Schedule::Passes(spp),
        }
    }
}

/// The outcome of a progressive camera pass.
pub struct Passes<X, A = Sums> {
    pub film: Film,
    pub pixels: Vec<Pixel<X, A>>,
    pub passes: u32,
    pub seconds_per_pass: f64,
}

/// The driver: what it reads from the render.
pub struct CameraPass<'a> {
    pub scene: &'a Scene,
    pub filter: Filter,
    pub seed: u64,
    /// The phase name in progress reports.
    pub phase: &'static str,
    pub progress: Option<&'a ProgressFn>,
    pub cancel: Option<&'a AtomicBool>,
    pub preview: Option<&'a PreviewFn>,
    /// Under a deadline, the time to leave for writing the result (measured after pass 1).
    pub output_time: Option<&'a OutputTimeFn>,
    /// Non-finite term estimates dropped by the firewall.
    pub non_finite: AtomicUsize,
    /// The compositing AOVs of the render.
    pub aovs: &'a AovLayout,
}

impl<'a> CameraPass<'a> {
    pub fn new(scene: &'a Scene, filter: Filter, seed: u64, phase: &'static str) -> Self {
        CameraPass {
            scene,
            filter,
            seed,
            phase,
            progress: None,
            cancel: None,
            preview: None,
            output_time: None,
            non_finite: AtomicUsize::new(0),
            aovs: &super::compositing::NO_AOVS,
        }
    }

    pub(super) fn report(&self, fraction: f32, phase: &str) {
        if let Some(p) = self.progress {
            p(fraction, phase);
        }
    }

    pub(super) fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }

    pub fn non_finite_samples(&self) -> u64 {
        self.non_finite.load(Ordering::Relaxed) as u64
    }

    /// A worker's scratch space: the integrator's, and a sample's record of the compositing
    /// AOVs.
    pub(super) fn scratch<I: Integrator>(&self, it: &I) -> (I::Scratch, SampleAovs) {
        (it.scratch(), self.aovs.sample())
    }

    /// One camera sample of pixel (x, y) at film position `u`, through the firewall; its
    /// random numbers from `own` if the integrator gives the pass a stream of its own, else
    /// from the pixel's.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn sample<I: Integrator>(
        &self,
        it: &I,
        pass: &I::Pass,
        px: &mut Pixel<I::Extra, I::Acc>,
        own: Option<Rng>,
        (x, y): (usize, usize),
        u: Vec2,
        k: u32,
        (scratch, aovs): &mut (I::Scratch, SampleAovs),
    ) {
        let mut own = own;
        let rng = own.as_mut().unwrap_or(&mut px.rng);
        let ray = eye::camera_ray(self.scene, &self.filter, x, y, u, rng);
        let (l, further) = it.sample(pass, ray, rng, &mut px.extra, k, scratch, aovs);
        let transparent = std::mem::take(&mut aovs.transparent);
        self.aovs.add(&mut px.aovs, aovs);
        let dropped = px.sums.add(k, &l, further, transparent);
        if dropped > 0 {
            self.non_finite.fetch_add(dropped, Ordering::Relaxed);
        }
    }

    fn film_of<I: Integrator>(
        &self,
        it: &I,
        pixels: &[Pixel<I::Extra, I::Acc>],
        samples: u32,
    ) -> Film {
        let mut film = self.new_film(self.scene.width, self.scene.height);
        for (i, px) in pixels.iter().enumerate() {
            self.resolve(it, &mut film, px, samples, i);
        }
        film
    }

    /// An empty film of `w` x `h` pixels (the image, or a tile of it) with this render's
    /// compositing AOVs.
    pub(super) fn new_film(&self, w: usize, h: usize) -> Film {
        let mut film = Film::new(w, h);
        film.aovs = self.aovs.images(w, h);
        film.cryptomatte = self.aovs.manifests();
        film
    }

    /// Pixel `i` after `samples` samples, into the film.
    pub(super) fn resolve<I: Integrator>(
        &self,
        it: &I,
        film: &mut Film,
        px: &Pixel<I::Extra, I::Acc>,
        samples: u32,
        i: usize,
    ) {
        let w = film.width;
        let (v, err) = it.resolve(px, samples);
        film.set_pixel(i % w, i / w, &v);
        film.error.data[i] = err.to_array();
        film.alpha[i] = px.sums.alpha(samples);
        self.aovs
            .resolve(&px.aovs, samples, &v, &mut film.aovs, i, |g| {
                it.resolve_groups(px, samples, g)
            });
    }

    /// Whole passes over the image, passes `first`, `first + 1`, ..., one sample per pixel
    /// each: sample `k` of a pixel comes from its replicated Sobol (0,2)-sequence
    /// (`error_aov::Shifts`). Previews after passes 1, 2, 4, ... and at most every
    /// [`PREVIEW_SECONDS`] between them.
    pub fn progressive<I: Integrator>(
        &self,
        it: &mut I,
        schedule: Schedule,
        first: u32,
    ) -> Result<Passes<I::Extra, I::Acc>> {
        use rayon::prelude::*;
        let (w, h) = (self.scene.width, self.scene.height);
        let (shifts, mut pixels): (Vec<Shifts>, Vec<Pixel<I::Extra, I::Acc>>) = (0..w * h)
            .into_par_iter()
            .map(|i| {
                let mut rng = Rng::new(self.seed, i as u64);
                (Shifts::draw(&mut rng), Pixel::new(rng))
            })
            .unzip();
        let t = Instant::now();
        let mut last_preview = Instant::now();
        let mut passes: u32 = 0;
        let mut schedule = schedule;
        loop {
            if passes == 1 {
                if let (Schedule::Deadline { deadline, .. }, Some(f)) =
                    (&mut schedule, self.output_time)
                {
                    *deadline -= f(&self.film_of(it, &pixels, 1));
                }
            }
            match schedule {
                Schedule::Deadline { start, deadline } if passes > 0 => {
                    let per_pass = t.elapsed().as_secs_f64() / passes as f64;
                    if start.elapsed().as_secs_f64() + per_pass > deadline
                        || u64::from(first) + u64::from(passes) >= u64::from(u32::MAX)
                    {
                        break;
                    }
                    let f = (start.elapsed().as_secs_f64() / deadline).min(1.0) as f32;
                    self.report(f, self.phase);
                }
                Schedule::Passes(n) if passes >= n => break,
                Schedule::Passes(n) => self.report(passes as f32 / n as f32, self.phase),
                Schedule::Deadline { .. } => {}
            }
            let k = first + passes;
            let pass = it.begin_pass(k)?;
            if self.cancelled() {
                return Err(Error::Cancelled);
            }
            let tc = Instant::now();
            let it_ref: &I = it;
            pixels
                .par_chunks_mut(w.max(1))
                .zip(shifts.par_chunks(w.max(1)))
                .enumerate()
                .for_each_init(
                    || self.scratch(it_ref),
                    |scratch, (y, (row, row_shifts))| {
                        for (x, (px, sh)) in row.iter_mut().zip(row_shifts.iter()).enumerate() {
                            if self.cancelled() {
                                return;
                            }
                            let own = it_ref.pass_rng(&pass, y * w + x);
                            self.sample(it_ref, &pass, px, own, (x, y), sh.point(k), k, scratch);
                        }
                    },
                );
            it.end_pass(pass, tc.elapsed().as_secs_f64());
            if self.cancelled() {
                return Err(Error::Cancelled);
            }
            passes += 1;
            if let Some(p) = self.preview {
                if preview_due(passes, &mut last_preview) {
                    p(&self.film_of(it, &pixels, passes), passes);
                }
            }
        }
        self.report(1.0, self.phase);
        let seconds_per_pass = t.elapsed().as_secs_f64() / passes.max(1) as f64;
        Ok(Passes {
            film: self.film_of(it, &pixels, passes),
            pixels,
            passes,
            seconds_per_pass,
        })
    }
}

#[cfg(test)]
#[path = "driver_tests.rs"]
mod tests;
