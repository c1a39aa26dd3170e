//! The renderer builder: seed, threads, samples, progress callback and cancel flag.
//!
//! Each pixel draws its random numbers from its own stream, derived from (seed, pixel index),
//! and pixels are independent (see `film`), so the output is bit-identical for any thread count.

use super::aov::Term;
use super::budget::{self, BudgetStats};
use super::cache_fill;
use super::error_aov::{replicate_of, Replicates, Shifts, REPLICATES};
use super::eye::{self, EyeCtx, EyeSettings};
use super::film::{Film, TermRadiance};
use super::memory::MemoryEstimate;
use super::photons;
use super::settings::RenderMode;
use super::settings::{RenderSettings, BYTES_PER_TRIANGLE};
use super::sppm::SppmJob;
use super::stats::{RenderStats, StatsParts};
use super::terms::volume::MarchSettings;
use crate::error::{Error, Result};
use crate::math::Spectrum;
use crate::photon::KnnScratch;
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::Vec2;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// Called with (fraction done in [0,1], phase name). May be called from worker threads.
pub type ProgressFn = dyn Fn(f32, &str) + Send + Sync;

/// Called during a progressive render (`progressive`, a time budget, or `RenderMode::Sppm`)
/// with the image so far and the passes it holds: after passes 1, 2, 4, 8, ... and at most
/// every `PREVIEW_SECONDS` between them. The Blender viewport refines through it.
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

pub struct RenderOutput {
    pub film: Film,
    pub stats: RenderStats,
}

pub struct Renderer<'a> {
    pub(super) scene: &'a Scene,
    pub(super) settings: RenderSettings,
    progress: Option<Arc<ProgressFn>>,
    pub(super) cancel: Option<Arc<AtomicBool>>,
    pub(super) preview: Option<Arc<PreviewFn>>,
    output_time: Option<Arc<OutputTimeFn>>,
    pub(super) work: crate::render::work::WorkCounts,
}

impl<'a> Renderer<'a> {
    pub fn new(scene: &'a Scene) -> Self {
        Renderer {
            scene,
            settings: RenderSettings::default(),
            progress: None,
            cancel: None,
            preview: None,
            output_time: None,
            work: Default::default(),
        }
    }
    pub fn settings(mut self, s: RenderSettings) -> Self {
        self.settings = s;
        self
    }
    pub fn seed(mut self, seed: u64) -> Self {
        self.settings.seed = seed;
        self
    }
    pub fn threads(mut self, n: usize) -> Self {
        self.settings.threads = n;
        self
    }
    pub fn spp(mut self, n: u32) -> Self {
        self.settings.spp = n;
        self
    }
    pub fn progress(mut self, f: Arc<ProgressFn>) -> Self {
        self.progress = Some(f);
        self
    }
    pub fn cancel_flag(mut self, flag: Arc<AtomicBool>) -> Self {
        self.cancel = Some(flag);
        self
    }
    /// Previews of a progressive render (see [`PreviewFn`]).
    pub fn preview(mut self, f: Arc<PreviewFn>) -> Self {
        self.preview = Some(f);
        self
    }
    /// Under a time budget, leave time at the end for writing the result out (see
    /// [`OutputTimeFn`]).
    pub fn output_time(mut self, f: Arc<OutputTimeFn>) -> Self {
        self.output_time = Some(f);
        self
    }

    pub(super) fn is_cancelled(&self) -> bool {
        self.cancel
            .as_ref()
            .is_some_and(|c| c.load(Ordering::Relaxed))
    }

    pub(super) fn report(&self, fraction: f32, phase: &str) {
        if let Some(p) = &self.progress {
            p(fraction, phase);
        }
    }

    /// Which maps the render reads: global, caustic, volume.
    pub(super) fn needed_maps(&self) -> [bool; 3] {
        let s = &self.settings;
        let need_volume = s.terms.contains(Term::Volume) && self.scene.has_media();
        if s.mode == RenderMode::Sppm {
            // One global map per pass serves both photon terms.
            let terms = s.terms.contains(Term::Caustic) || s.terms.contains(Term::Indirect);
            return [terms, false, need_volume];
        }
        let need_global = s.terms.contains(Term::Indirect) && s.photons.final_gather_rays > 0;
        let need_caustic = s.terms.contains(Term::Caustic);
        [need_global, need_caustic, need_volume]
    }

    pub fn render(self) -> Result<RenderOutput> {
        let start = Instant::now();
        let s = &self.settings;
        if let Some(b) = s.time_budget {
            budget::check_budget(b).map_err(|message| Error::InvalidSetting {
                setting: "time_budget".into(),
                message,
            })?;
        }
        if s.spp == 0 {
            return Err(Error::InvalidSetting {
                setting: "spp".into(),
                message: "must be at least 1".into(),
            });
        }
        let estimate = self.memory_estimate();
        if let Some(limit) = s.memory_limit {
            if estimate.peak_bytes > limit {
                return Err(Error::InvalidSetting {
                    setting: "memory_limit".into(),
                    message: format!(
                        "the render needs an estimated {} bytes at its peak ({} photons x {} B \
                         = {} B for the photon maps, {} B of precomputed irradiance, {} \
                         triangles x {} B = {} B for the BVH, {} B in all, plus the largest \
                         map's photons once more while it is built), over the limit of \
                         {limit} bytes; store fewer photons or raise the limit",
                        estimate.peak_bytes,
                        estimate.photons,
                        s.photons.bytes_per_photon(),
                        estimate.photon_bytes,
                        estimate.irradiance_bytes,
                        estimate.triangles,
                        BYTES_PER_TRIANGLE,
                        estimate.bvh_bytes,
                        estimate.total_bytes
                    ),
                });
            }
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(s.threads)
            .build()
            .map_err(|e| Error::Internal(format!("thread pool: {e}")))?;
        pool.install(|| self.render_in_pool(pool.current_num_threads(), estimate, start))
    }

    fn render_in_pool(
        &self,
        threads: usize,
        estimate: MemoryEstimate,
        start: Instant,
    ) -> Result<RenderOutput> {
        if self.settings.mode == RenderMode::Sppm {
            return self.render_sppm(threads, estimate, start);
        }
        let (w, h) = (self.scene.width, self.scene.height);
        let mut seconds = std::collections::BTreeMap::new();
        let [need_global, need_caustic, need_volume] = self.needed_maps();
        let cancel = self.cancel.as_deref();

        let budget_seconds = self.settings.time_budget.filter(|b| *b > 0.0);
        let mut budget_stats = budget_seconds.map(|b| BudgetStats {
            budget_seconds: b,
            ..BudgetStats::default()
        });
        let planned;
        let s = match (budget_seconds, budget_stats.as_mut()) {
            (Some(b), Some(bs)) => {
                self.report(0.0, "planning");
                planned = self.plan_budget(b, [need_global, need_caustic, need_volume], bs)?;
                seconds.insert("calibration".to_string(), bs.calibration_seconds);
                &planned
            }
            _ => &self.settings,
        };

        // First pass: photons.
        self.report(0.0, "photons");
        let t0 = Instant::now();
        let (maps, map_stats) = photons::build(
            self.scene,
            &s.photons,
            s.seed,
            [need_global, need_caustic, need_volume],
            cancel,
        );
        if self.is_cancelled() {
            return Err(Error::Cancelled);
        }
        seconds.insert("photons".to_string(), t0.elapsed().as_secs_f64());

        let eye_settings = EyeSettings {
            terms: s.terms,
            max_specular_depth: s.max_specular_depth,
            final_gather_rays: s.photons.final_gather_rays,
            gather_rays_per_sample: s.gather_rays_per_sample.unwrap_or(
                match s.photons.final_gather_rays {
                    0 => 0,
                    n => n.div_ceil(s.spp).max(4),
                },
            ),
        };
        let march = MarchSettings::for_render(s, self.scene, maps.global_r2);
        // Irradiance cache, filled in deterministic rounds.
        let t1 = Instant::now();
        let photon_planned_seconds = t0.elapsed().as_secs_f64();
        let cache = if s.photons.irradiance_cache && need_global && maps.global.is_some() {
            let pre = EyeCtx {
                scene: self.scene,
                work: &self.work,
                maps: &maps,
                cache: None,
                settings: eye_settings,
                march,
            };
            Some(cache_fill::fill(
                &pre,
                s,
                &|f| self.report(f, "irradiance cache"),
                &|| self.is_cancelled(),
            )?)
        } else {
            None
        };
        seconds.insert("irradiance_cache".to_string(), t1.elapsed().as_secs_f64());

        // Second pass: camera rays.
        let t2 = Instant::now();
        let ctx = EyeCtx {
            scene: self.scene,
            work: &self.work,
            maps: &maps,
            cache: cache.as_ref(),
            settings: eye_settings,
            march,
        };
        let non_finite = AtomicUsize::new(0);
        let cache_seconds = t1.elapsed().as_secs_f64();
        let (film, spp) = if s.progressive || budget_seconds.is_some() {
            let deadline =
                budget_seconds.map(|b| b - budget::MARGIN_FRACTION * b - budget::MARGIN_SECONDS);
            let (film, passes, per_pass) =
                self.progressive_passes(&ctx, s, start, deadline, &non_finite)?;
            if let Some(bs) = budget_stats.as_mut() {
                bs.passes = passes;
                bs.spp = passes;
                bs.seconds_per_pass = per_pass;
                bs.planned_seconds = bs.calibration_seconds
                    + photon_planned_seconds.max(0.0)
                    + cache_seconds
                    + passes as f64 * per_pass;
            }
            (film, passes)
        } else {
            (self.single_pass(&ctx, s, &non_finite)?, s.spp)
        };
        seconds.insert("render".to_string(), t2.elapsed().as_secs_f64());
        let stats = self.stats(StatsParts {
            width: w,
            height: h,
            spp,
            threads,
            seconds,
            maps: map_stats,
            irradiance_cache_records: cache.as_ref().map_or(0, |c| c.len() as u64),
            skipped: self.skipped_terms(Some(&maps)),
            non_finite_samples: non_finite.load(Ordering::Relaxed) as u64,
            estimate,
            time_budget: None,
            mode: RenderMode::Jensen,
            sppm: None,
        });
        let mut stats = stats;
        if let Some(mut bs) = budget_stats {
            bs.actual_seconds = start.elapsed().as_secs_f64();
            if bs.actual_seconds > 1.05 * bs.budget_seconds {
                bs.too_small = true;
                bs.note = Some(format!(
                    "the budget of {} s is too small for this scene and machine: the smallest \
                     render (calibration, {} stored photons, the irradiance cache and one \
                     camera pass) took {:.3} s",
                    bs.budget_seconds,
                    bs.photons_global + bs.photons_caustic + bs.photons_volume,
                    bs.actual_seconds
                ));
            }
            stats.time_budget = Some(bs);
        }
        Ok(RenderOutput { film, stats })
    }

    /// A progressive photon-mapping render (`RenderMode::Sppm`, see `sppm`): `spp` passes,
    /// or as many as fit in the time budget.
    fn render_sppm(
        &self,
        threads: usize,
        estimate: MemoryEstimate,
        start: Instant,
    ) -> Result<RenderOutput> {
        let s = &self.settings;
        let (w, h) = (self.scene.width, self.scene.height);
        let [need_global, _, need_volume] = self.needed_maps();
        let budget_seconds = s.time_budget.filter(|b| *b > 0.0);
        let deadline =
            budget_seconds.map(|b| b - budget::MARGIN_FRACTION * b - budget::MARGIN_SECONDS);
        let non_finite = AtomicUsize::new(0);
        let report = |f: f32, phase: &str| self.report(f, phase);
        let job = SppmJob {
            scene: self.scene,
            settings: s,
            need_global,
            need_volume,
            cancel: self.cancel.as_deref(),
            report: &report,
            deadline,
            start,
            non_finite: &non_finite,
            preview: self.preview.as_deref(),
            work: &self.work,
        };
        let out = job.run()?;
        let mut seconds = std::collections::BTreeMap::new();
        seconds.insert("photons".to_string(), out.stats.photon_seconds);
        seconds.insert("render".to_string(), out.stats.camera_seconds);
        let skipped = self.skipped_terms(None);
        let mut maps = out.maps;
        for m in maps.iter_mut().filter(|m| m.map == "caustic") {
            m.skipped_because =
                Some("progressive mode: each pass's global map holds the caustic photons".into());
        }
        let time_budget = budget_seconds.map(|b| {
            let actual = start.elapsed().as_secs_f64();
            BudgetStats {
                budget_seconds: b,
                planned_seconds: out.passes as f64 * out.seconds_per_pass,
                actual_seconds: actual,
                passes: out.passes,
                spp: out.passes,
                seconds_per_pass: out.seconds_per_pass,
                photons_global: s.photons.global,
                photons_volume: s.photons.volume,
                too_small: actual > 1.05 * b,
                ..BudgetStats::default()
            }
        });
        let stats = self.stats(StatsParts {
            width: w,
            height: h,
            spp: out.passes,
            threads,
            seconds,
            maps,
            irradiance_cache_records: 0,
            skipped,
            non_finite_samples: non_finite.load(Ordering::Relaxed) as u64,
            estimate,
            time_budget,
            mode: RenderMode::Sppm,
            sppm: Some(out.stats),
        });
        Ok(RenderOutput {
            film: out.film,
            stats,
        })
    }

    /// Traces sample `u` (in [0,1)^2, warped by the filter) of pixel (x, y) into `acc`, and
    /// returns the sample's value of the combined image (for the `error` AOV).
    #[allow(clippy::too_many_arguments)]
    fn sample_pixel(
        &self,
        ctx: &EyeCtx,
        s: &RenderSettings,
        x: usize,
        y: usize,
        u: Vec2,
        rng: &mut Rng,
        scratch: &mut KnnScratch,
        acc: &mut TermRadiance,
        non_finite: &AtomicUsize,
    ) -> Spectrum {
        let ray = eye::camera_ray(self.scene, &s.filter, x, y, u, rng);
        let l = eye::trace(ctx, ray, rng, scratch);
        let mut total = Spectrum::ZERO;
        for t in Term::ALL {
            let v = l.0[t.index()];
            if v.is_finite() {
                acc.0[t.index()] += v;
                total += v;
            } else {
                non_finite.fetch_add(1, Ordering::Relaxed);
            }
        }
        total
    }

    /// The camera pass in one go: `spp` samples per pixel, stratified over an nx-by-ny grid.
    fn single_pass(
        &self,
        ctx: &EyeCtx,
        s: &RenderSettings,
        non_finite: &AtomicUsize,
    ) -> Result<Film> {
        let (w, h) = (self.scene.width, self.scene.height);
        self.report(0.0, "render");
        let rows_done = AtomicUsize::new(0);
        // Sample i belongs to replicate i mod R (see `error`); each replicate is stratified
        // over its own nx-by-ny grid.
        let grids: Vec<(u32, u32)> = (0..REPLICATES as u32)
            .map(|r| {
                let n = s.spp.saturating_sub(r).div_ceil(REPLICATES as u32).max(1);
                let nx = (n as f32).sqrt().floor().max(1.0) as u32;
                (nx, n.div_ceil(nx))
            })
            .collect();
        let rows: Vec<Option<Vec<(TermRadiance, Spectrum)>>> = {
            use rayon::prelude::*;
            (0..h)
                .into_par_iter()
                .map_init(KnnScratch::new, |scratch, y| {
                    if self.is_cancelled() {
                        return None;
                    }
                    let mut row = Vec::with_capacity(w);
                    for x in 0..w {
                        if self.is_cancelled() {
                            return None;
                        }
                        let mut rng = Rng::new(s.seed, (y * w + x) as u64);
                        let mut acc = TermRadiance::default();
                        let mut batches = Replicates::default();
                        for i in 0..s.spp {
                            // Stratified over the replicate's grid, then warped by the filter.
                            let (r, j) = replicate_of(i);
                            let (nx, ny) = grids[r];
                            let (cx, cy) = (j % nx, (j / nx) % ny);
                            let j = rng.vec2();
                            let u = Vec2::new(
                                (cx as f32 + j.x) / nx as f32,
                                (cy as f32 + j.y) / ny as f32,
                            );
                            let v = self.sample_pixel(
                                ctx, s, x, y, u, &mut rng, scratch, &mut acc, non_finite,
                            );
                            batches.add(i, v);
                        }
                        let inv = 1.0 / s.spp as f32;
                        for v in acc.0.iter_mut() {
                            *v *= inv;
                        }
                        row.push((acc, batches.standard_error()));
                    }
                    let done = rows_done.fetch_add(1, Ordering::Relaxed) + 1;
                    self.report(done as f32 / h as f32, "render");
                    Some(row)
                })
                .collect()
        };
        if self.is_cancelled() {
            return Err(Error::Cancelled);
        }
        let mut film = Film::new(w, h);
        for (y, row) in rows.into_iter().enumerate() {
            let row = row.ok_or(Error::Cancelled)?;
            for (x, (px, err)) in row.iter().enumerate() {
                film.set_pixel(x, y, px);
                film.error.data[y * w + x] = err.to_array();
            }
        }
        Ok(film)
    }

    /// The camera pass in whole passes over the image, one sample per pixel each: sample `k`
    /// of a pixel comes from its replicated Sobol (0,2)-sequence (`error_aov::Shifts`), and
    /// the pixel's random stream continues across passes, so the image after `k` passes is
    /// the same however many follow. Without a deadline it runs `spp` passes; with one (seconds
    /// since `start`) it adds passes while the next, at the mean time per pass so far, ends
    /// before it (at least one pass). Returns the film, the passes run and the mean seconds
    /// per pass.
    fn progressive_passes(
        &self,
        ctx: &EyeCtx,
        s: &RenderSettings,
        start: Instant,
        deadline: Option<f64>,
        non_finite: &AtomicUsize,
    ) -> Result<(Film, u32, f64)> {
        use rayon::prelude::*;
        struct PixelState {
            rng: Rng,
            shifts: Shifts,
            acc: TermRadiance,
            batches: Replicates,
        }
        let (w, h) = (self.scene.width, self.scene.height);
        let mut pixels: Vec<PixelState> = (0..w * h)
            .into_par_iter()
            .map(|i| {
                let mut rng = Rng::new(s.seed, i as u64);
                let shifts = Shifts::draw(&mut rng);
                PixelState {
                    rng,
                    shifts,
                    acc: TermRadiance::default(),
                    batches: Replicates::default(),
                }
            })
            .collect();
        let film_of = |pixels: &[PixelState], passes: u32| {
            let mut film = Film::new(w, h);
            let inv = 1.0 / passes.max(1) as f32;
            for (i, px) in pixels.iter().enumerate() {
                let mut v = px.acc;
                for c in v.0.iter_mut() {
                    *c *= inv;
                }
                film.set_pixel(i % w, i / w, &v);
                film.error.data[i] = px.batches.standard_error().to_array();
            }
            film
        };
        let t = Instant::now();
        let mut last_preview = Instant::now();
        let mut passes: u32 = 0;
        let mut deadline = deadline;
        loop {
            if passes == 1 {
                if let (Some(d), Some(f)) = (deadline.as_mut(), &self.output_time) {
                    *d -= f(&film_of(&pixels, 1));
                }
            }
            match deadline {
                Some(d) if passes > 0 => {
                    let per_pass = t.elapsed().as_secs_f64() / passes as f64;
                    if start.elapsed().as_secs_f64() + per_pass > d || passes == u32::MAX {
                        break;
                    }
                    self.report(
                        (start.elapsed().as_secs_f64() / d).min(1.0) as f32,
                        "render",
                    );
                }
                None if passes >= s.spp => break,
                None => self.report(passes as f32 / s.spp as f32, "render"),
                _ => {}
            }
            let k = passes;
            pixels.par_chunks_mut(w.max(1)).enumerate().for_each_init(
                KnnScratch::new,
                |scratch, (y, row)| {
                    if self.is_cancelled() {
                        return;
                    }
                    for (x, px) in row.iter_mut().enumerate() {
                        if self.is_cancelled() {
                            return;
                        }
                        let u = px.shifts.point(k);
                        let v = self.sample_pixel(
                            ctx,
                            s,
                            x,
                            y,
                            u,
                            &mut px.rng,
                            scratch,
                            &mut px.acc,
                            non_finite,
                        );
                        px.batches.add(k, v);
                    }
                },
            );
            if self.is_cancelled() {
                return Err(Error::Cancelled);
            }
            passes += 1;
            if let Some(p) = &self.preview {
                if preview_due(passes, &mut last_preview) {
                    p(&film_of(&pixels, passes), passes);
                }
            }
        }
        self.report(1.0, "render");
        let per_pass = t.elapsed().as_secs_f64() / passes.max(1) as f64;
        Ok((film_of(&pixels, passes), passes, per_pass))
    }
}
