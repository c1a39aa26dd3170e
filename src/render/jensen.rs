//! Jensen's two-pass render (the `jensen` mode): the photon maps are built once, the
//! irradiance cache is filled from them, and the camera pass estimates every term at the
//! eye (`eye::trace`) through the camera-pass driver, in one stratified pass or, progressive
//! or under a time budget, in whole passes.

use super::adaptive::Adaptive;
use super::budget::BudgetStats;
use super::cache_fill;
use super::compositing::SampleAovs;
use super::driver::{Integrator, Schedule};
use super::eye::{self, EyeCtx, EyeSettings};
use super::film::TermRadiance;
use super::memory::MemoryEstimate;
use super::photons;
use super::renderer::{RenderOutput, Renderer};
use super::settings::{RenderMode, RenderSettings};
use super::stats::StatsParts;
use super::terms::volume::MarchSettings;
use crate::error::{Error, Result};
use crate::geometry::Ray;
use crate::math::Spectrum;
use crate::photon::KnnScratch;
use crate::sampling::Rng;
use std::collections::BTreeMap;
use std::time::Instant;

/// Jensen's camera pass: every term at the eye, from the maps and the cache built before.
struct Jensen<'a> {
    ctx: EyeCtx<'a>,
}

impl Integrator for Jensen<'_> {
    type Extra = ();
    type Scratch = KnnScratch;
    type Pass = ();

    fn scratch(&self) -> KnnScratch {
        KnnScratch::new()
    }

    fn begin_pass(&mut self, _k: u32) -> Result<()> {
        Ok(())
    }

    fn sample(
        &self,
        _pass: &(),
        ray: Ray,
        rng: &mut Rng,
        _extra: &mut (),
        _k: u32,
        scratch: &mut KnnScratch,
        aovs: &mut SampleAovs,
    ) -> (TermRadiance, Spectrum) {
        (eye::trace(&self.ctx, ray, rng, scratch, aovs), Spectrum::ZERO)
    }
}

/// The eye pass's settings in Jensen's mode: gather rays per sample where the cache does not
/// answer are the record's rays spread over the pixel's samples (at least 4).
fn eye_settings(s: &RenderSettings) -> EyeSettings {
    EyeSettings {
        terms: s.terms,
        max_specular_depth: s.max_specular_depth,
        final_gather_rays: s.photons.final_gather_rays,
        gather_rays_per_sample: s.gather_rays_per_sample.unwrap_or(
            match s.photons.final_gather_rays {
                0 => 0,
                n => n.div_ceil(s.spp).max(4),
            },
        ),
    }
}

impl Renderer<'_> {
    /// Jensen's render: planning under a budget, the photon maps, the irradiance cache and
    /// the camera pass.
    pub(super) fn render_jensen(
        &self,
        threads: usize,
        estimate: MemoryEstimate,
        start: Instant,
    ) -> Result<RenderOutput> {
        let mut seconds = BTreeMap::new();
        let need = self.needed_maps();
        let budget_seconds = self.settings.time_budget.filter(|b| *b > 0.0);
        let mut budget_stats = budget_seconds.map(BudgetStats::for_budget);
        let planned;
        let s = match (budget_seconds, budget_stats.as_mut()) {
            (Some(b), Some(bs)) => {
                self.report(0.0, "planning");
                planned = self.plan_budget(b, need, bs)?;
                seconds.insert("calibration".to_string(), bs.calibration_seconds);
                &planned
            }
            _ => &self.settings,
        };

        // First pass: photons.
        self.report(0.0, "photons");
        let t0 = Instant::now();
        let (mut maps, mut map_stats) =
            photons::build(self.scene, &s.photons, s.seed, need, self.cancel());
        if self.is_cancelled() {
            return Err(Error::Cancelled);
        }
        photons::build_volume_points(
            self.scene,
            &s.photons,
            &mut maps,
            &mut map_stats,
            s.seed,
            self.cancel(),
        );
        if self.is_cancelled() {
            return Err(Error::Cancelled);
        }
        let photon_seconds = t0.elapsed().as_secs_f64();
        seconds.insert("photons".to_string(), photon_seconds);

        // The irradiance cache, filled in deterministic rounds.
        let t1 = Instant::now();
        let mut ctx = EyeCtx {
            scene: self.scene,
            work: &self.work,
            maps: &maps,
            cache: None,
            settings: eye_settings(s),
            march: MarchSettings::for_render(s, self.scene, maps.global_r2),
        };
        let cache = if s.photons.irradiance_cache && need[0] && maps.global.is_some() {
            Some(cache_fill::fill(
                &ctx,
                s,
                &|f| self.report(f, "irradiance cache"),
                &|| self.is_cancelled(),
            )?)
        } else {
            None
        };
        let cache_seconds = t1.elapsed().as_secs_f64();
        seconds.insert("irradiance_cache".to_string(), cache_seconds);
        ctx.cache = cache.as_ref();

        // Second pass: camera rays.
        let t2 = Instant::now();
        let driver = self.camera_pass(s, "render");
        let mut jensen = Jensen { ctx };
        let mut adaptive_stats = None;
        let (film, spp) = if s.progressive || budget_seconds.is_some() {
            let schedule = Schedule::of(budget_seconds, s.spp, start);
            let out = driver.progressive(&mut jensen, schedule)?;
            if let Some(bs) = budget_stats.as_mut() {
                bs.passes = out.passes;
                bs.spp = out.passes;
                bs.seconds_per_pass = out.seconds_per_pass;
                bs.planned_seconds = bs.calibration_seconds
                    + photon_seconds
                    + cache_seconds
                    + out.passes as f64 * out.seconds_per_pass;
            }
            (out.film, out.passes)
        } else {
            let (film, a) = driver.stratified(&mut jensen, s.spp, Adaptive::of(s))?;
            adaptive_stats = a;
            (film, s.spp)
        };
        seconds.insert("render".to_string(), t2.elapsed().as_secs_f64());
        let mut stats = self.stats(StatsParts {
            width: self.scene.width,
            height: self.scene.height,
            spp,
            threads,
            seconds,
            maps: map_stats,
            irradiance_cache_records: cache.as_ref().map_or(0, |c| c.len() as u64),
            skipped: self.skipped_terms(Some(&maps)),
            non_finite_samples: driver.non_finite_samples(),
            estimate,
            time_budget: None,
            mode: RenderMode::Jensen,
            sppm: None,
            adaptive: adaptive_stats,
        });
        stats.time_budget = budget_stats.map(|bs| bs.finish(start.elapsed().as_secs_f64()));
        Ok(RenderOutput { film, stats })
    }
}
