//! Rendering to a time budget (`--time-budget SECONDS`).
//!
//! **Plan.** A calibration photon pass (a fixed fraction of the preset's stored-photon
//! targets, so it is itself deterministic) measures the seconds per stored photon on this
//! machine, and a calibration fill of the irradiance cache with those maps and
//! `CALIBRATION_GATHER_RAYS` rays per record measures the cost of a gather ray and the number
//! of records. The photon counts and the final-gathering rays are then scaled by one factor,
//! keeping the preset's ratios, so that calibration, photon pass and cache take `MAPS_SHARE`
//! of the budget.
//!
//! **Enforce.** The camera pass is progressive in whole passes over the image, one sample
//! per pixel per pass. Sample `k` of a pixel takes its film position from the Sobol
//! (0,2)-sequence of one of the pixel's independently shifted replicates (`render::error_aov`),
//! so every power-of-two prefix of each replicate is stratified, and the pixel's random
//! stream continues from pass to pass. The image
//! after `K` passes therefore depends only on `K` (and the photon counts and seed), never on
//! how long a pass took. Passes are added while the next one, at the measured time per
//! pass, still fits in the budget less a margin.
//!
//! The deadline and its margin for writing the film are the driver's (`driver::deadline`).
//!
//! The plan depends on timing; it is recorded in the stats (`time_budget`) and a render with
//! the same photon counts and `final_gather_rays`, `spp = passes`, `progressive = true` and the same
//! `gather_rays_per_sample` is bit-identical to it.

use super::cache_fill;
use super::eye::EyeSettings;
use super::photons;
use super::renderer::Renderer;
use super::settings::{RenderSettings, BYTES_PER_TRIANGLE};
use crate::error::{Error, Result};
use serde::Serialize;
use std::time::Instant;

/// The wall clock of a whole command or call under a time budget: reading the scene, building
/// it, rendering and writing the result all count. Started when the front end starts; the
/// render is given what is left ([`WallClock::render_budget`]).
#[derive(Clone, Copy, Debug)]
pub struct WallClock {
    start: Instant,
    budget: f64,
}

impl WallClock {
    pub fn start(budget: f64) -> Self {
        WallClock {
            start: Instant::now(),
            budget,
        }
    }

    pub fn budget(&self) -> f64 {
        self.budget
    }

    pub fn elapsed(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    /// The budget left for rendering one of `frames_left` frames (the remaining time shared
    /// evenly) when writing its output will take `output_seconds`; at least a millisecond,
    /// so that a render that cannot fit still renders one pass and says so.
    pub fn render_budget(&self, frames_left: usize, output_seconds: f64) -> f64 {
        let left = (self.budget - self.elapsed()) / frames_left.max(1) as f64;
        (left - output_seconds).max(1e-3)
    }
}

/// Fraction of the budget the calibration, the photon pass and the irradiance cache are
/// planned to take together; the camera passes fill the rest.
pub const MAPS_SHARE: f64 = 0.6;

/// Final-gathering rays per record in the calibration fill of the irradiance cache.
pub const CALIBRATION_GATHER_RAYS: u32 = 8;

/// Fewest final-gathering rays per cache record in a budgeted plan.
pub const MIN_GATHER_RAYS: u32 = 16;

/// Fraction of the preset's stored-photon targets traced for calibration.
pub const CALIBRATION_FRACTION: f64 = 0.02;

/// Fewest photons stored per map in the calibration pass and in a budgeted plan.
pub const MIN_PHOTONS: usize = 1_000;

/// What a budgeted render planned and what it did. `photons`, `spp` and
/// `gather_rays_per_sample` reproduce the image with `progressive = true`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct BudgetStats {
    /// The budget, in seconds.
    pub budget_seconds: f64,
    /// The time the plan predicted for the whole render (calibration, photons, cache and
    /// the camera passes it ran).
    pub planned_seconds: f64,
    /// The wall time of the whole render.
    pub actual_seconds: f64,
    /// Time spent measuring before the real photon pass.
    pub calibration_seconds: f64,
    /// Measured seconds per stored photon (calibration pass).
    pub seconds_per_photon: f64,
    /// Measured seconds per camera pass (one sample per pixel), mean over the passes run.
    pub seconds_per_pass: f64,
    /// Stored-photon targets chosen: global, caustic, volume.
    pub photons_global: usize,
    pub photons_caustic: usize,
    pub photons_volume: usize,
    /// Irradiance-cache records of the calibration fill.
    pub calibration_cache_records: u64,
    /// Final-gathering rays per irradiance-cache record chosen (the preset's, scaled).
    pub final_gather_rays: u32,
    /// Camera passes run; equal to the samples per pixel.
    pub passes: u32,
    pub spp: u32,
    pub gather_rays_per_sample: u32,
    /// True when the budget could not hold even the smallest render (minimum photons and
    /// one pass); the render then still completes that smallest render.
    pub too_small: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

impl BudgetStats {
    /// The stats of a render to `budget_seconds`, before planning.
    pub fn for_budget(budget_seconds: f64) -> Self {
        BudgetStats {
            budget_seconds,
            ..BudgetStats::default()
        }
    }

    /// The stats once the render took `actual_seconds`: a render more than 5% over the
    /// budget had a budget too small for its smallest form, and the note says so.
    pub fn finish(mut self, actual_seconds: f64) -> Self {
        self.actual_seconds = actual_seconds;
        if actual_seconds > 1.05 * self.budget_seconds {
            self.too_small = true;
            self.note = Some(format!(
                "the budget of {} s is too small for this scene and machine: the smallest \
                 render ({} stored photons and one camera pass, with the calibration and the \
                 irradiance cache where the mode uses them) took {:.3} s",
                self.budget_seconds,
                self.photons_global + self.photons_caustic + self.photons_volume,
                actual_seconds
            ));
        }
        self
    }
}

/// Scales photon targets by `scale`, keeping their ratios; a map with a zero target stays
/// at zero, others store at least `MIN_PHOTONS`.
pub fn scale_count(n: usize, scale: f64) -> usize {
    if n == 0 {
        return 0;
    }
    ((n as f64 * scale).round() as usize).max(MIN_PHOTONS)
}

impl Renderer<'_> {
    /// Plans a budgeted render: a calibration photon pass measures the seconds per stored
    /// photon, then the photon targets are scaled (keeping their ratios) so that the photon
    /// pass takes `PHOTON_SHARE` of the budget. Returns the settings to render with.
    pub(super) fn plan_budget(
        &self,
        budget_seconds: f64,
        need: [bool; 3],
        stats: &mut BudgetStats,
    ) -> Result<RenderSettings> {
        let mut s = self.settings.clone();
        let t = Instant::now();
        let targets = [
            (need[0], s.photons),
            (need[1], s.caustic_photons),
            (need[2], s.volume_photons),
        ];
        let preset_total: usize = targets.iter().filter(|(n, _)| *n).map(|(_, c)| *c).sum();
        let mut scale = 1.0;
        if preset_total > 0 && !self.scene.lights.is_empty() {
            let mut cal = s.clone();
            cal.photons = scale_count(s.photons, CALIBRATION_FRACTION);
            cal.caustic_photons = scale_count(s.caustic_photons, CALIBRATION_FRACTION);
            cal.volume_photons = scale_count(s.volume_photons, CALIBRATION_FRACTION);
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
            let fg = s.final_gather_rays;
            if need[0] && s.irradiance_cache && cal_maps.global.is_some() && fg > 0 {
                let tc = Instant::now();
                let mut cal_settings = s.clone();
                cal_settings.final_gather_rays = CALIBRATION_GATHER_RAYS;
                let settings = EyeSettings {
                    terms: s.terms,
                    max_specular_depth: s.max_specular_depth,
                    final_gather_rays: CALIBRATION_GATHER_RAYS,
                    gather_rays_per_sample: CALIBRATION_GATHER_RAYS,
                };
                let ctx = self.eye_ctx(&s, &cal_maps, None, settings);
                let cache =
                    cache_fill::fill(&ctx, &cal_settings, &|_| {}, &|| self.is_cancelled())?;
                let secs = tc.elapsed().as_secs_f64();
                stats.calibration_cache_records = cache.len() as u64;
                cache_preset =
                    secs * fg as f64 / CALIBRATION_GATHER_RAYS as f64 * log_ratio(s.photons as f64);
            }
            let photon_preset =
                stats.seconds_per_photon * preset_photons * log_ratio(preset_photons);
            let room = (budget_seconds * MAPS_SHARE - t.elapsed().as_secs_f64()).max(0.0);
            if photon_preset + cache_preset > 0.0 {
                scale = room / (photon_preset + cache_preset);
            }
            // Final-gathering rays grow with the plan only up to the preset's.
            if scale > 1.0 && photon_preset > 0.0 {
                scale = ((room - cache_preset) / photon_preset).max(1.0);
            }
            if let Some(limit) = s.memory_limit_bytes() {
                let bvh = self.scene.triangle_count as u64 * BYTES_PER_TRIANGLE;
                let record = s.bytes_per_photon();
                let fit = limit.saturating_sub(bvh) / record;
                scale = scale.min(fit as f64 / preset_photons);
            }
        }
        let spp_equivalent = (s.spp as f64 * scale).max(1.0);
        s.photons = scale_count(s.photons, scale);
        s.caustic_photons = scale_count(s.caustic_photons, scale);
        s.volume_photons = scale_count(s.volume_photons, scale);
        if s.final_gather_rays > 0 {
            s.final_gather_rays =
                ((s.final_gather_rays as f64 * scale.min(1.0)).round() as u32).max(MIN_GATHER_RAYS);
        }
        s.progressive = true;
        let gather = s
            .gather_rays_per_sample
            .unwrap_or(match s.final_gather_rays {
                0 => 0,
                n => ((n as f64 / spp_equivalent).ceil() as u32).max(4),
            });
        s.gather_rays_per_sample = Some(gather);
        stats.calibration_seconds = t.elapsed().as_secs_f64();
        stats.photons_global = s.photons;
        stats.photons_caustic = s.caustic_photons;
        stats.photons_volume = s.volume_photons;
        stats.gather_rays_per_sample = gather;
        stats.final_gather_rays = s.final_gather_rays;
        Ok(s)
    }
}
