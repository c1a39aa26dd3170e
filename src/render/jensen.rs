//! Jensen's two-pass render (the `jensen` mode): the photon maps are built once, the
//! irradiance cache is filled from them, and the camera pass estimates every term at the
//! eye (`eye::trace`) through the camera-pass driver, in one stratified pass or, progressive
//! or under a time budget, in whole passes.

use super::accumulate::Sums;
use super::adaptive::{Adaptive, AdaptiveStats};
use super::budget::BudgetStats;
use super::cache_fill;
use super::compositing::SampleAovs;
use super::driver::{Integrator, Schedule};
use super::eye::{self, EyeCtx, EyeSettings};
use super::film::{Film, TermRadiance};
use super::irradiance_cache::IrradianceCache;
use super::map_file::{MapSet, ReuseStats};
use super::memory::MemoryEstimate;
use super::output::RenderOutput;
use super::photons::{self, MapStats, PhotonMaps};
use super::renderer::Renderer;
use super::settings::{RenderMode, RenderSettings};
use super::stats::{RenderStats, StatsParts};
use super::stratified::{first_round_noise, Rect};
use super::tile::{self, TileOutput, TileStage};
use crate::error::{Error, Result};
use crate::geometry::Ray;
use crate::math::Spectrum;
use crate::photon::KnnScratch;
use crate::sampling::Rng;
use std::borrow::Cow;
use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Instant;

/// Jensen's camera pass: every term at the eye, from the maps and the cache built before.
struct Jensen<'a> {
    ctx: EyeCtx<'a>,
}

impl Integrator for Jensen<'_> {
    type Extra = ();
    type Acc = Sums;
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
        (
            eye::trace(&self.ctx, ray, rng, scratch, aovs),
            Spectrum::ZERO,
        )
    }
}

/// The eye pass's settings in Jensen's mode: gather rays per sample where the cache does not
/// answer are the record's rays spread over the pixel's samples (at least 4).
fn eye_settings(s: &RenderSettings) -> EyeSettings {
    EyeSettings {
        terms: s.terms,
        max_specular_depth: s.max_specular_depth,
        final_gather_rays: s.final_gather_rays,
        gather_rays_per_sample: s
            .gather_rays_per_sample
            .unwrap_or(match s.final_gather_rays {
                0 => 0,
                n => n.div_ceil(s.spp).max(4),
            }),
    }
}

/// What the camera pass of a Jensen render reads, prepared: the settings (a budget's
/// plan), the photon maps (built, or given to reuse) and the irradiance cache.
struct Prepared<'r> {
    settings: Cow<'r, RenderSettings>,
    budget_stats: Option<BudgetStats>,
    seconds: BTreeMap<String, f64>,
    /// The maps when this render built them.
    built: Option<PhotonMaps>,
    map_stats: Vec<MapStats>,
    cache: Option<Cow<'r, IrradianceCache>>,
    reuse: ReuseStats,
}

impl Renderer<'_> {
    /// The maps of `p`: those it built, or those given to reuse.
    fn maps_of<'a>(&'a self, p: &'a Prepared) -> &'a PhotonMaps {
        match (&p.built, &self.reuse) {
            (Some(m), _) => m,
            (None, Some(set)) => &set.maps,
            (None, None) => unreachable!("a prepared render has maps"),
        }
    }

    /// Planning under a budget, the photon maps (or the maps given to reuse) and the
    /// irradiance cache (filled, reused as it is when it was filled for this view, or
    /// extended when it was filled for another).
    fn prepare_jensen(&self) -> Result<Prepared<'_>> {
        let mut seconds = BTreeMap::new();
        let need = self.needed_maps();
        let budget_seconds = self.settings.budget_seconds();
        let mut budget_stats = budget_seconds.map(BudgetStats::for_budget);
        let settings = match (budget_seconds, budget_stats.as_mut()) {
            (Some(b), Some(bs)) => {
                self.report(0.0, "planning");
                let planned = self.plan_budget(b, need, bs)?;
                seconds.insert("calibration".to_string(), bs.calibration_seconds);
                Cow::Owned(planned)
            }
            _ => Cow::Borrowed(&self.settings),
        };
        let s: &RenderSettings = &settings;

        // First pass: photons (or the maps given to reuse).
        let t0 = Instant::now();
        let mut reuse = ReuseStats::default();
        let (built, map_stats) = match &self.reuse {
            Some(set) => {
                if let Some(k) = self.keys.filter(|k| k.maps != set.key) {
                    return Err(Error::Internal(format!(
                        "photon maps of key {:016x} given to a render of key {:016x}",
                        set.key, k.maps
                    )));
                }
                reuse.maps = "reused".into();
                reuse.key = format!("{:016x}", set.key);
                reuse.build_seconds = set.stats.iter().map(|m| m.seconds).sum();
                (None, set.stats.clone())
            }
            None => {
                self.report(0.0, "photons");
                let (mut maps, mut stats) =
                    photons::build(self.scene, s, s.seed, need, self.cancel());
                if self.is_cancelled() {
                    return Err(Error::Cancelled);
                }
                photons::build_volume_points(
                    self.scene,
                    s,
                    &mut maps,
                    &mut stats,
                    s.seed,
                    self.cancel(),
                );
                if self.is_cancelled() {
                    return Err(Error::Cancelled);
                }
                reuse.maps = "built".into();
                reuse.key = self
                    .keys
                    .map_or(String::new(), |k| format!("{:016x}", k.maps));
                reuse.build_seconds = stats.iter().map(|m| m.seconds).sum();
                (Some(maps), stats)
            }
        };
        seconds.insert("photons".to_string(), t0.elapsed().as_secs_f64());
        let mut p = Prepared {
            settings,
            budget_stats,
            seconds,
            built,
            map_stats,
            cache: None,
            reuse,
        };

        // The irradiance cache, filled in deterministic rounds.
        let t1 = Instant::now();
        let s: &RenderSettings = &p.settings;
        let maps = self.maps_of(&p);
        let ctx = self.eye_ctx(s, maps, None, eye_settings(s));
        let view = self.keys.map(|k| k.view);
        let given = self
            .reuse
            .as_ref()
            .and_then(|r| r.cache.as_ref().map(|c| (c, r.cache_view)));
        let progress = |f| self.report(f, "irradiance cache");
        let cancelled = || self.is_cancelled();
        let (cache, how) = if s.irradiance_cache && need[0] && maps.global.is_some() {
            match given {
                Some((c, v)) if Some(v) == view => (Some(Cow::Borrowed(c)), "reused"),
                Some((c, _)) => (
                    Some(Cow::Owned(cache_fill::extend(
                        &ctx,
                        s,
                        c.clone(),
                        &progress,
                        &cancelled,
                    )?)),
                    "extended",
                ),
                None => (
                    Some(Cow::Owned(cache_fill::fill(
                        &ctx, s, &progress, &cancelled,
                    )?)),
                    "filled",
                ),
            }
        } else {
            (None, "none")
        };
        let reused = given.map_or(0, |(c, _)| c.len() as u64);
        let total = cache.as_ref().map_or(0, |c| c.len() as u64);
        p.reuse.cache = how.into();
        p.reuse.cache_records_reused = if how == "filled" {
            0
        } else {
            reused.min(total)
        };
        p.reuse.cache_records_added = total - p.reuse.cache_records_reused;
        p.cache = cache;
        p.seconds
            .insert("irradiance_cache".to_string(), t1.elapsed().as_secs_f64());
        Ok(p)
    }

    /// The stats of a Jensen render from what it prepared and its camera pass.
    fn jensen_stats(
        &self,
        p: &Prepared,
        threads: usize,
        estimate: MemoryEstimate,
        spp: u32,
        non_finite: u64,
        adaptive: Option<AdaptiveStats>,
    ) -> RenderStats {
        let mut stats = self.stats(StatsParts {
            width: self.scene.width,
            height: self.scene.height,
            spp,
            threads,
            seconds: p.seconds.clone(),
            maps: p.map_stats.clone(),
            irradiance_cache_records: p.cache.as_ref().map_or(0, |c| c.len() as u64),
            skipped: self.skipped_terms(Some(self.maps_of(p))),
            non_finite_samples: non_finite,
            estimate,
            time_budget: None,
            mode: RenderMode::Jensen,
            sppm: None,
            adaptive,
        });
        stats.photon_map_reuse = Some(p.reuse.clone());
        stats
    }

    /// The maps and the cache of `p` as a set to reuse or save: the set given to reuse when
    /// this render extended nothing, else a new one.
    fn map_set(&self, p: Prepared) -> Arc<MapSet> {
        let keys = self.keys.unwrap_or_default();
        let maps = match (p.built, &self.reuse) {
            (Some(m), _) => m,
            // Reused maps: the set given, as it was (a cache extended for this view is this
            // render's only).
            (None, Some(set)) => return set.clone(),
            (None, None) => unreachable!("a prepared render has maps"),
        };
        Arc::new(MapSet {
            key: keys.maps,
            parts: self.key_parts.unwrap_or_default(),
            maps,
            stats: p.map_stats,
            cache: p.cache.map(Cow::into_owned),
            cache_view: keys.view,
        })
    }

    /// Jensen's render: planning under a budget, the photon maps, the irradiance cache and
    /// the camera pass.
    pub(super) fn render_jensen(
        &self,
        threads: usize,
        estimate: MemoryEstimate,
        start: Instant,
    ) -> Result<RenderOutput> {
        let mut p = self.prepare_jensen()?;
        if self.maps_only {
            let film = Film::new(0, 0);
            let stats = self.jensen_stats(&p, threads, estimate, 0, 0, None);
            let set = self.map_set(p);
            return Ok(RenderOutput {
                film,
                stats,
                partial: None,
                photon_maps: Some(set),
            });
        }
        let mut budget_stats = p.budget_stats.take();
        let s: &RenderSettings = &p.settings;
        let maps = self.maps_of(&p);
        let ctx = self.eye_ctx(s, maps, p.cache.as_deref(), eye_settings(s));
        let budget_seconds = s.budget_seconds();

        // Second pass: camera rays.
        let t2 = Instant::now();
        let driver = self.camera_pass(s, "render");
        let mut jensen = Jensen { ctx };
        let mut adaptive_stats = None;
        let (film, spp) = if s.progressive || budget_seconds.is_some() {
            let schedule = Schedule::of(budget_seconds, s.spp, start);
            let out = driver.progressive(&mut jensen, schedule, 0)?;
            if let Some(bs) = budget_stats.as_mut() {
                bs.passes = out.passes;
                bs.spp = out.passes;
                bs.seconds_per_pass = out.seconds_per_pass;
                bs.planned_seconds = bs.calibration_seconds
                    + p.seconds["photons"]
                    + p.seconds["irradiance_cache"]
                    + out.passes as f64 * out.seconds_per_pass;
            }
            (out.film, out.passes)
        } else {
            let (film, a) = driver.stratified(&mut jensen, s.spp, Adaptive::of(s))?;
            adaptive_stats = a;
            (film, s.spp)
        };
        let render_seconds = t2.elapsed().as_secs_f64();
        let non_finite = driver.non_finite_samples();
        drop(driver);
        drop(jensen);
        p.seconds.insert("render".to_string(), render_seconds);
        let mut stats = self.jensen_stats(&p, threads, estimate, spp, non_finite, adaptive_stats);
        stats.time_budget = budget_stats.map(|bs| bs.finish(start.elapsed().as_secs_f64()));
        let photon_maps = self.keep_maps.then(|| self.map_set(p));
        Ok(RenderOutput {
            film,
            stats,
            partial: None,
            photon_maps,
        })
    }

    /// One stage of a tile of a Jensen render (see `render::tile`): the photon maps and the
    /// irradiance cache must be given ([`Renderer::reuse_photon_maps`]), the cache filled
    /// for this view, so that every tile reads the same estimates.
    pub(super) fn render_jensen_tile(
        &self,
        rect: Rect,
        stage: TileStage,
        threads: usize,
        estimate: MemoryEstimate,
    ) -> Result<TileOutput> {
        let s = &self.settings;
        if s.budget_seconds().is_some() || s.progressive {
            return Err(Error::InvalidSetting {
                setting: if s.progressive {
                    "progressive"
                } else {
                    "time_budget"
                }
                .into(),
                message: "a frame rendered in tiles takes its samples in one stratified pass: \
                          render it whole"
                    .into(),
            });
        }
        let mut p = self.prepare_jensen()?;
        if p.built.is_some() || p.reuse.cache == "extended" || p.reuse.cache == "filled" {
            return Err(Error::Internal(
                "a tile needs the frame's photon maps and irradiance cache, built for its view"
                    .into(),
            ));
        }
        let maps = self.maps_of(&p);
        let ctx = self.eye_ctx(s, maps, p.cache.as_deref(), eye_settings(s));
        let t2 = Instant::now();
        let driver = self.camera_pass(s, "render");
        let mut jensen = Jensen { ctx };
        let pass = jensen.begin_pass(0)?;
        let adaptive = Adaptive::of(s);
        let out = match stage {
            TileStage::First => {
                let pixels = driver.first_round(&jensen, &pass, s.spp, rect, (0.0, 1.0))?;
                let (means, errors) = first_round_noise(&pixels);
                TileOutput::First {
                    means,
                    errors,
                    state: tile::encode_pixels(&pixels),
                }
            }
            TileStage::Finish { rounds, state } => {
                let mut pixels = match state {
                    Some(bytes) => tile::decode_pixels(&bytes, rect.len())?,
                    None => driver.first_round(&jensen, &pass, s.spp, rect, (0.0, 0.8))?,
                };
                let rounds =
                    match (adaptive, rounds) {
                        (Some(_), Some(r)) if r.len() == rect.len() => r,
                        (Some(_), Some(r)) => {
                            return Err(Error::Internal(format!(
                                "{} rounds for a tile of {} pixels",
                                r.len(),
                                rect.len()
                            )))
                        }
                        (Some(_), None) => return Err(Error::Internal(
                            "adaptive sampling: a tile needs the rounds decided from the whole \
                             image's first round"
                                .into(),
                        )),
                        (None, _) => vec![1; rect.len()],
                    };
                let extra = driver.more_rounds(
                    &jensen,
                    &pass,
                    s.spp,
                    rect,
                    &mut pixels,
                    &rounds,
                    (0.8, 1.0),
                )?;
                let film = driver.rect_film(&jensen, rect, &pixels, &rounds, s.spp);
                p.seconds
                    .insert("render".to_string(), t2.elapsed().as_secs_f64());
                let stats = self.jensen_stats(
                    &p,
                    threads,
                    estimate,
                    s.spp,
                    driver.non_finite_samples(),
                    adaptive.map(|a| AdaptiveStats::of(a, &rounds, s.spp, extra)),
                );
                TileOutput::Finished { film, stats }
            }
        };
        Ok(out)
    }
}
