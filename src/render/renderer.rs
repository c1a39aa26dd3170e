//! The renderer builder: seed, threads, samples, progress callback and cancel flag.
//!
//! Each pixel draws its random numbers from its own stream, derived from (seed, pixel index),
//! and pixels are independent (see `film`), so the output is bit-identical for any thread count.

use super::aov::Term;
use super::budget::{self, BudgetStats};
use super::cache_fill;
use super::error::{replicate_of, Replicates, Shifts, REPLICATES};
use super::eye::{self, EyeCtx, EyeSettings};
use super::film::{Film, TermRadiance};
use super::photons::{self, MapStats, PhotonMaps};
use super::settings::RenderMode;
use super::settings::{RenderSettings, BYTES_PER_TRIANGLE};
use super::sppm::{SppmJob, SppmStats};
use super::terms::volume::MarchSettings;
use crate::error::{Error, Result};
use crate::math::Spectrum;
use crate::photon::KnnScratch;
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::Vec2;
use serde::Serialize;
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

/// Bytes per photon held, besides the finished record, while a map is built: the traced
/// photon (`RAW_PHOTON_BYTES`) until it is converted, or the kd-tree's scratch copy of the
/// record during balancing, whichever is more (measured at 10^8 photons: 40 B/photon peak).
fn build_extra(record: u64) -> u64 {
    crate::photon::trace::RAW_PHOTON_BYTES
        .saturating_sub(record)
        .max(record)
}

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

/// Why a term is zero in this render.
#[derive(Clone, Debug, Serialize)]
pub struct SkippedTerm {
    pub term: &'static str,
    pub reason: String,
}

#[derive(Clone, Debug, Default, Serialize)]
pub struct RenderStats {
    pub version: &'static str,
    pub seed: u64,
    pub width: usize,
    pub height: usize,
    pub spp: u32,
    pub threads: usize,
    pub triangles: usize,
    pub lights: usize,
    /// Wall-clock seconds per pass.
    pub seconds: std::collections::BTreeMap<String, f64>,
    pub camera_rays: u64,
    /// Photons stored per map that was built.
    pub photons_stored: std::collections::BTreeMap<String, u64>,
    /// Every map: built (photons stored and emitted, memory, time) or skipped, and why.
    pub photon_maps: Vec<MapStats>,
    pub irradiance_cache_records: u64,
    pub skipped: Vec<SkippedTerm>,
    /// Estimates that came out NaN or infinite and were dropped.
    pub non_finite_samples: u64,
    /// Approximate bytes held by the render (film and scene geometry).
    pub memory_bytes: u64,
    /// The estimate checked against the memory limit before the photon pass.
    pub memory_estimate: MemoryEstimate,
    /// Bytes per stored photon in the estimate.
    pub bytes_per_photon: u64,
    /// Bytes per triangle of the BVH in the estimate.
    pub bytes_per_triangle: u64,
    /// The plan of a render to a time budget, and how it went; absent without a budget.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_budget: Option<BudgetStats>,
    /// Jensen's two passes or progressive photon mapping.
    pub mode: RenderMode,
    /// What a progressive render did; absent in Jensen's mode.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sppm: Option<SppmStats>,
    /// Work done per kind (march steps, volume and caustic map lookups).
    pub work: crate::render::work::WorkStats,
    /// The settings the render was given (a budgeted render's plan is under `time_budget`).
    pub settings: RenderSettings,
}

/// What a render measured, for [`RenderStats`].
struct StatsParts {
    width: usize,
    height: usize,
    spp: u32,
    threads: usize,
    seconds: std::collections::BTreeMap<String, f64>,
    maps: Vec<MapStats>,
    irradiance_cache_records: u64,
    skipped: Vec<SkippedTerm>,
    non_finite_samples: u64,
    estimate: MemoryEstimate,
    time_budget: Option<BudgetStats>,
    mode: RenderMode,
    sppm: Option<SppmStats>,
}

/// Memory that the photon maps and the BVH of a render take, estimated before the photon
/// pass from the stored-photon targets of the maps that will be built.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct MemoryEstimate {
    /// Photons stored over every map that will be built.
    pub photons: u64,
    /// `photons * PhotonSettings::bytes_per_photon()` (20 B RGBE, 28 B `f32` power).
    pub photon_bytes: u64,
    pub triangles: u64,
    /// `triangles * BYTES_PER_TRIANGLE`.
    pub bvh_bytes: u64,
    /// The global map's precomputed irradiance points: one per `irradiance::STRIDE` photons,
    /// `size_of::<IrradiancePoint>()` (20) bytes each.
    pub irradiance_bytes: u64,
    /// `photon_bytes + bvh_bytes + irradiance_bytes`.
    pub total_bytes: u64,
    /// The most the render holds at once, which the memory limit is checked against: the
    /// BVH, the maps, and, while the largest map is built, its photons a second time (as
    /// traced, `RAW_PHOTON_BYTES` each, or as the kd-tree's scratch copy, whichever is more).
    pub peak_bytes: u64,
}

pub struct RenderOutput {
    pub film: Film,
    pub stats: RenderStats,
}

pub struct Renderer<'a> {
    scene: &'a Scene,
    settings: RenderSettings,
    progress: Option<Arc<ProgressFn>>,
    cancel: Option<Arc<AtomicBool>>,
    pub(super) preview: Option<Arc<PreviewFn>>,
    output_time: Option<Arc<OutputTimeFn>>,
    work: crate::render::work::WorkCounts,
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

    fn skipped_terms(&self, maps: &PhotonMaps) -> Vec<SkippedTerm> {
        let mut out = Vec::new();
        for t in Term::ALL {
            let reason = if !self.settings.terms.contains(t) {
                "disabled in the render settings".to_string()
            } else {
                match t {
                    Term::Indirect if maps.global.is_none() => {
                        "no global photon map (see photon_maps)".into()
                    }
                    Term::Indirect if self.settings.photons.final_gather_rays == 0 => {
                        "final gathering disabled (0 rays)".into()
                    }
                    Term::Caustic if maps.caustic.is_none() => {
                        "no caustic photon map (see photon_maps)".into()
                    }
                    Term::Volume if !self.scene.has_media() => {
                        "the scene has no participating media".into()
                    }
                    _ => continue,
                }
            };
            out.push(SkippedTerm {
                term: t.name(),
                reason,
            });
        }
        out
    }

    fn is_cancelled(&self) -> bool {
        self.cancel
            .as_ref()
            .is_some_and(|c| c.load(Ordering::Relaxed))
    }

    fn report(&self, fraction: f32, phase: &str) {
        if let Some(p) = &self.progress {
            p(fraction, phase);
        }
    }

    /// Which maps the render reads: global, caustic, volume.
    fn needed_maps(&self) -> [bool; 3] {
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

    /// The memory the photon maps (stored targets of every map that will be built, at
    /// `PhotonSettings::bytes_per_photon`) and the BVH (`BYTES_PER_TRIANGLE`) take.
    pub fn memory_estimate(&self) -> MemoryEstimate {
        let p = &self.settings.photons;
        let [need_global, need_caustic, need_volume] = self.needed_maps();
        let built: Vec<u64> = if self.scene.lights.is_empty() {
            Vec::new()
        } else {
            let caustic =
                need_caustic && p.caustic > 0 && !photons::specular_targets(self.scene).is_empty();
            [
                (need_global, p.global),
                (caustic, p.caustic),
                (need_volume, p.volume),
            ]
            .iter()
            .filter(|(b, _)| *b)
            .map(|(_, n)| *n as u64)
            .collect()
        };
        let photons = built.iter().fold(0u64, |acc, n| acc.saturating_add(*n));
        let global = if need_global && !self.scene.lights.is_empty() {
            p.global as u64
        } else {
            0
        };
        let irradiance_bytes = global
            .div_ceil(crate::photon::irradiance::STRIDE as u64)
            .saturating_mul(
                std::mem::size_of::<crate::photon::irradiance::IrradiancePoint>() as u64,
            );
        let largest = built.iter().copied().max().unwrap_or(0);
        let triangles = self.scene.triangle_count as u64;
        let record = p.bytes_per_photon();
        let photon_bytes = photons.saturating_mul(record);
        let bvh_bytes = triangles.saturating_mul(BYTES_PER_TRIANGLE);
        let total_bytes = photon_bytes
            .saturating_add(bvh_bytes)
            .saturating_add(irradiance_bytes);
        MemoryEstimate {
            photons,
            photon_bytes,
            triangles,
            bvh_bytes,
            irradiance_bytes,
            total_bytes,
            peak_bytes: total_bytes.saturating_add(largest.saturating_mul(build_extra(record))),
        }
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

    /// Plans a budgeted render: a calibration photon pass measures the seconds per stored
    /// photon, then the photon targets are scaled (keeping their ratios) so that the photon
    /// pass takes `budget::PHOTON_SHARE` of the budget. Returns the settings to render with.
    fn plan_budget(
        &self,
        budget_seconds: f64,
        need: [bool; 3],
        stats: &mut BudgetStats,
    ) -> Result<RenderSettings> {
        let mut s = self.settings.clone();
        let t = Instant::now();
        let p = &s.photons;
        let targets = [
            (need[0], p.global),
            (need[1], p.caustic),
            (need[2], p.volume),
        ];
        let preset_total: usize = targets.iter().filter(|(n, _)| *n).map(|(_, c)| *c).sum();
        let mut scale = 1.0;
        if preset_total > 0 && !self.scene.lights.is_empty() {
            let mut cal = p.clone();
            cal.global = budget::scale_count(p.global, budget::CALIBRATION_FRACTION);
            cal.caustic = budget::scale_count(p.caustic, budget::CALIBRATION_FRACTION);
            cal.volume = budget::scale_count(p.volume, budget::CALIBRATION_FRACTION);
            let (cal_maps, cal_stats) = photons::build(
                self.scene,
                &cal,
                s.seed ^ 0xCA1B_4A7E,
                need,
                self.cancel.as_deref(),
            );
            if self.is_cancelled() {
                return Err(Error::Cancelled);
            }
            let stored: u64 = cal_stats.iter().filter(|m| m.built).map(|m| m.stored).sum();
            let photon_secs = t.elapsed().as_secs_f64();
            let preset_photons = preset_total as f64;
            // A bigger map costs more per photon (kd-tree balancing, cache misses): about in
            // proportion to log n.
            let log_ratio = |n: f64| (n.max(2.0).ln() / (stored.max(2) as f64).ln()).max(1.0);
            if stored > 0 {
                stats.seconds_per_photon = photon_secs / stored as f64;
            }
            // Irradiance cache: fill it with the calibration maps and a few gather rays to
            // count the records and time a gather ray.
            let mut cache_preset = 0.0;
            let fg = s.photons.final_gather_rays;
            if need[0] && s.photons.irradiance_cache && cal_maps.global.is_some() && fg > 0 {
                let tc = Instant::now();
                let mut cal_settings = s.clone();
                cal_settings.photons.final_gather_rays = budget::CALIBRATION_GATHER_RAYS;
                let ctx = EyeCtx {
                    scene: self.scene,
                    work: &self.work,
                    maps: &cal_maps,
                    cache: None,
                    settings: EyeSettings {
                        terms: s.terms,
                        max_specular_depth: s.max_specular_depth,
                        final_gather_rays: budget::CALIBRATION_GATHER_RAYS,
                        gather_rays_per_sample: budget::CALIBRATION_GATHER_RAYS,
                    },
                    march: MarchSettings::for_render(&s, self.scene, cal_maps.global_r2),
                };
                let cache =
                    cache_fill::fill(&ctx, &cal_settings, &|_| {}, &|| self.is_cancelled())?;
                let secs = tc.elapsed().as_secs_f64();
                stats.calibration_cache_records = cache.len() as u64;
                cache_preset = secs * fg as f64 / budget::CALIBRATION_GATHER_RAYS as f64
                    * log_ratio(p.global as f64);
            }
            let photon_preset =
                stats.seconds_per_photon * preset_photons * log_ratio(preset_photons);
            let room = (budget_seconds * budget::MAPS_SHARE - t.elapsed().as_secs_f64()).max(0.0);
            if photon_preset + cache_preset > 0.0 {
                scale = room / (photon_preset + cache_preset);
            }
            // Final-gathering rays grow with the plan only up to the preset's.
            if scale > 1.0 && photon_preset > 0.0 {
                scale = ((room - cache_preset) / photon_preset).max(1.0);
            }
            if let Some(limit) = s.memory_limit {
                let bvh = self.scene.triangle_count as u64 * BYTES_PER_TRIANGLE;
                let record = s.photons.bytes_per_photon();
                let fit = limit.saturating_sub(bvh) / (record + build_extra(record));
                scale = scale.min(fit as f64 / preset_photons);
            }
        }
        let spp_equivalent = (s.spp as f64 * scale).max(1.0);
        let p = &mut s.photons;
        p.global = budget::scale_count(p.global, scale);
        p.caustic = budget::scale_count(p.caustic, scale);
        p.volume = budget::scale_count(p.volume, scale);
        if p.final_gather_rays > 0 {
            p.final_gather_rays = ((p.final_gather_rays as f64 * scale.min(1.0)).round() as u32)
                .max(budget::MIN_GATHER_RAYS);
        }
        s.progressive = true;
        let gather = s
            .gather_rays_per_sample
            .unwrap_or(match p.final_gather_rays {
                0 => 0,
                n => ((n as f64 / spp_equivalent).ceil() as u32).max(4),
            });
        s.gather_rays_per_sample = Some(gather);
        stats.calibration_seconds = t.elapsed().as_secs_f64();
        stats.photons_global = p.global;
        stats.photons_caustic = p.caustic;
        stats.photons_volume = p.volume;
        stats.gather_rays_per_sample = gather;
        stats.final_gather_rays = p.final_gather_rays;
        Ok(s)
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
            skipped: self.skipped_terms(&maps),
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
        let mut skipped = Vec::new();
        for t in Term::ALL {
            let reason = if !s.terms.contains(t) {
                "disabled in the render settings"
            } else if self.scene.lights.is_empty() && matches!(t, Term::Caustic | Term::Indirect) {
                "the scene has no lights"
            } else if t == Term::Caustic && photons::specular_targets(self.scene).is_empty() {
                "the scene has no specular or transmissive surfaces"
            } else if t == Term::Volume && !self.scene.has_media() {
                "the scene has no participating media"
            } else {
                continue;
            };
            skipped.push(SkippedTerm {
                term: t.name(),
                reason: reason.to_string(),
            });
        }
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

    /// The stats of a render of either mode, from what it measured.
    fn stats(&self, p: StatsParts) -> RenderStats {
        let s = &self.settings;
        let photon_bytes: u64 = p.maps.iter().map(|m| m.memory_bytes).sum();
        RenderStats {
            settings: s.clone(),
            work: self.work.stats(),
            version: env!("CARGO_PKG_VERSION"),
            seed: s.seed,
            width: p.width,
            height: p.height,
            spp: p.spp,
            threads: p.threads,
            triangles: self.scene.triangle_count,
            lights: self.scene.lights.len(),
            seconds: p.seconds,
            camera_rays: (p.width * p.height) as u64 * p.spp as u64,
            photons_stored: p
                .maps
                .iter()
                .filter(|m| m.built)
                .map(|m| (m.map.to_string(), m.stored))
                .collect(),
            photon_maps: p.maps,
            irradiance_cache_records: p.irradiance_cache_records,
            skipped: p.skipped,
            non_finite_samples: p.non_finite_samples,
            // The film: one image per term and the error AOV, RGB f32.
            memory_bytes: (p.width * p.height * (Term::COUNT + 1) * 12) as u64
                + self.scene.triangle_count as u64 * 64
                + photon_bytes,
            memory_estimate: p.estimate,
            bytes_per_photon: s.photons.bytes_per_photon(),
            bytes_per_triangle: BYTES_PER_TRIANGLE,
            time_budget: p.time_budget,
            mode: p.mode,
            sppm: p.sppm,
        }
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
    /// of a pixel comes from its replicated Sobol (0,2)-sequence (`error::Shifts`), and
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
