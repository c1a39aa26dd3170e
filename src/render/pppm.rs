//! Probabilistic progressive photon mapping (Knaus & Zwicker 2011, "Progressive Photon
//! Mapping: A Probabilistic Approach", ACM TOG 30(3)): the `pppm` render mode, the one whose
//! passes can be rendered anywhere and merged.
//!
//! **A pass.** Pass k (0-based; i = k + 1 in the paper's numbering) is an independent
//! estimate of the image: a fresh global (and volume) photon map of `photons.global` stored
//! photons traced with the pass's own seed ([`pass_seed`]), one camera sample per pixel
//! (the pixel's Sobol (0,2)-point k, as the other progressive modes place them, and the rest
//! of its random numbers from a stream of (pass seed, pixel)), traced to its visible points
//! as in `sppm`, where the photons within the pass's radius are gathered (Jensen 2001, eq.
//! 7.6, over a fixed disk) into `caustic` and `indirect` (routed to `specular` behind a
//! specular bounce). Direct light, emission and media are estimated at the eye.
//!
//! **The radius** is global, the same for every pixel, and depends only on the pass index
//! (K&Z 2011, §4.3, eq. 15):
//!
//! ```text
//! r_i² = r_1² · i^(α − 1),   i = 1, 2, ...
//! ```
//!
//! so that the variance of the average of N passes falls as N^(−α) and its bias as
//! N^(α−1), both to zero. r_1 is computed once ([`Renderer::pppm_initial_radius`]: the median
//! over a grid of pixels of the distance to the `initial_photons`-th nearest photon of pass
//! 1's map around the pixel's first visible point, at most the largest search radius) and
//! recorded in the stats and in every partial sum; `initial_radius` gives it explicitly.
//!
//! **Order-free sums.** Each pass's value of each term is rounded to a fixed point of
//! 2^−24 (`accumulate::FixedSums`, the driver's accumulator for this mode) and added to 64-bit integer sums per pixel. Integer addition is
//! associative and commutative (wrapping, so even an intermediate overflow cancels out), so
//! the sums of passes 0..N are the same bits whatever blocks they were rendered in, on
//! whatever machines, and in whatever order the blocks are merged: N workers × K passes give
//! the image of one process rendering N·K passes. A pass's value is clamped to
//! ±`accumulate::MAX_PASS_VALUE`; a pixel's image is exact while its sum over the passes stays below
//! 2^39 (5.5e11) in absolute value. The `error` AOV comes from per-replicate sums of the
//! combined image (pass k in replicate k mod 4), the same way. The sums of a block of passes
//! are a [`Partial`] (`partial`, the `.ppart` file and the merge).
//!
//! Everything a pass computes depends on (scene, settings, seed, r_1, k) only, and every
//! pixel on its own stream (of the pass seed and the pixel, [`Integrator::pass_rng`]), so the sums are bit-identical for any thread count too.

use super::accumulate::FixedSums;
use super::aov::Term;
use super::compositing::NO_AOVS;
use super::driver::Schedule;
use super::eye::{self, EyeCtx, EyeSettings, VisiblePoint};
use super::film::TermRadiance;
use super::memory::MemoryEstimate;
use super::output::RenderOutput;
use super::partial::{pass_radius2, Partial, PartialHeader, Tally};
use super::photons::{self};
use super::progressive::{self, Progressive, ProgressivePass, Radii};
use super::renderer::Renderer;
use super::settings::RenderMode;
use super::stats::{PppmStats, StatsParts};
use crate::error::{Error, Result};
use crate::math::{is_finite3, Spectrum, PI};
use crate::photon::map::PhotonMap;
use crate::photon::KnnScratch;
use crate::sampling::{mix64, Rng};
use std::collections::BTreeMap;
use std::time::Instant;

/// The seed of pass `k` of a render seeded with `seed`.
pub fn pass_seed(seed: u64, k: u32) -> u64 {
    mix64(seed ^ mix64(0x5050_504D_0000_0000 ^ k as u64))
}

/// The photon terms of pass `k` at the visible points, over the disk of squared radius `r2`:
/// Φ / (π r²) per term (first-hit photons left out: direct light is estimated at the eye).
fn gather(global: &PhotonMap, vps: &[VisiblePoint], r2: f32, ctx: &EyeCtx) -> TermRadiance {
    let mut phi = TermRadiance::default();
    for vp in vps {
        global.tree.for_each_in_radius(vp.p, r2, |ph, _| {
            let Some(t) = vp.photon_term(ph.user_flags()) else {
                return;
            };
            let wi = ph.incoming();
            if wi.dot(vp.n) <= 0.0 || !ctx.settings.terms.contains(t) {
                return;
            }
            let c = vp.beta * vp.bsdf.eval_flux(vp.wo, wi) * ph.power();
            if is_finite3(c) {
                phi.add(t, c);
            }
        });
    }
    let inv = 1.0 / (PI * r2);
    for v in phi.0.iter_mut() {
        *v *= inv;
    }
    phi
}

/// Seed stream tags.
const TAG_PIXEL: u64 = 0x5050_4D5F_5049_5845;
const TAG_RADIUS: u64 = 0x5050_4D5F_5231_5F5F;

/// pppm's radii: one per pass, the same for every pixel (K&Z 2011, eq. 15); each pass's
/// estimate goes whole into the fixed-point sums.
struct Global {
    r1: f32,
    alpha: f32,
}

impl Radii for Global {
    type Extra = ();
    type Acc = FixedSums;
    const IRRADIANCE_POINTS: bool = false;

    fn pass_seed(&self, seed: u64, k: u32) -> u64 {
        pass_seed(seed, k)
    }

    fn pass_radius2(&self, k: u32) -> f32 {
        pass_radius2(self.r1, self.alpha, k)
    }

    /// A stream of (pass seed, pixel): a pass depends on its index only, so that blocks of
    /// passes render anywhere.
    fn pass_rng(&self, pass_seed: u64, pixel: usize) -> Option<Rng> {
        Some(Rng::derive(pass_seed, TAG_PIXEL, pixel as u64))
    }

    /// The pass's photons within its radius, added to the sample's terms: the pass's whole
    /// estimate of the pixel.
    fn gather(
        &self,
        ctx: &EyeCtx,
        pass: &ProgressivePass,
        global: &PhotonMap,
        vps: &[VisiblePoint],
        _extra: &mut (),
        _scratch: &mut KnnScratch,
        l: &mut TermRadiance,
    ) -> Spectrum {
        let p = gather(global, vps, pass.r2, ctx);
        for (v, p) in l.0.iter_mut().zip(p.0) {
            *v += p;
        }
        Spectrum::ZERO
    }
}

impl Renderer<'_> {
    /// r_1: the median, over the pixels of a grid (about 4096 of them), of the distance to
    /// the `initial_photons`-th nearest photon of pass 1's global map around the pixel's
    /// first visible point (the pixel centre's camera ray), at most the largest search
    /// radius; that radius where no pixel finds enough photons. Deterministic.
    pub fn pppm_initial_radius(&self) -> Result<f32> {
        let s = &self.settings;
        let (maps, _) = photons::build_with(
            self.scene,
            s,
            pass_seed(s.seed, 0),
            [true, false, false],
            self.cancel(),
            false,
        );
        if self.is_cancelled() {
            return Err(Error::Cancelled);
        }
        let max_r2 = maps.global_r2;
        let Some(global) = maps.global.as_ref() else {
            return Ok(max_r2.sqrt());
        };
        let (w, h) = (self.scene.width, self.scene.height);
        let stride = (((w * h) as f64 / 4096.0).sqrt().ceil() as usize).max(1);
        let settings = EyeSettings {
            terms: s.terms.without(Term::Volume),
            ..progressive::eye_settings(s)
        };
        let ctx = self.eye_ctx(s, &maps, None, settings);
        use rayon::prelude::*;
        let pixels: Vec<usize> = (0..h)
            .step_by(stride)
            .flat_map(|y| (0..w).step_by(stride).map(move |x| y * w + x))
            .collect();
        let k = s.initial_photons.max(1);
        let filter = s.pixel_filter();
        let mut r2s: Vec<f32> = pixels
            .par_iter()
            .map_init(
                || (KnnScratch::new(), Vec::new()),
                |(scratch, vps), &i| {
                    let mut rng = Rng::derive(s.seed, TAG_RADIUS, i as u64);
                    let ray = eye::camera_ray(
                        self.scene,
                        &filter,
                        i % w,
                        i / w,
                        glam::Vec2::splat(0.5),
                        &mut rng,
                    );
                    vps.clear();
                    let mut record = |vp: VisiblePoint| vps.push(vp);
                    eye::trace_split(
                        &ctx,
                        ray,
                        &mut rng,
                        scratch,
                        Some(&mut record),
                        &mut NO_AOVS.sample(),
                    );
                    let vp = vps.first()?;
                    let found = global.tree.knn(vp.p, k, max_r2, scratch);
                    (found.len() >= k)
                        .then(|| found.iter().map(|nb| nb.dist2).fold(0.0f32, f32::max))
                        .filter(|r2| *r2 > 0.0 && r2.is_finite())
                },
            )
            .flatten()
            .collect();
        if r2s.is_empty() {
            return Ok(max_r2.sqrt());
        }
        let mid = r2s.len() / 2;
        let (_, m, _) = r2s.select_nth_unstable_by(mid, f32::total_cmp);
        Ok(m.min(max_r2).sqrt())
    }

    /// Renders passes `first .. first + count` of the pppm mode with first radius `r1` into a
    /// partial sum (fewer under a time budget, as many as fit before `start` plus the
    /// budget). `key` identifies the scene and settings (see [`PartialHeader::key`]).
    pub fn pppm_passes(
        &self,
        r1: f32,
        (first, count): (u32, u32),
        total: u32,
        key: u64,
        start: Instant,
    ) -> Result<Partial> {
        let s = &self.settings;
        first
            .checked_add(count)
            .ok_or_else(|| Error::InvalidSetting {
                setting: "pass_range".into(),
                message: format!("{first} + {count} passes overflow"),
            })?;
        let header = PartialHeader {
            width: self.scene.width as u32,
            height: self.scene.height as u32,
            seed: s.seed,
            alpha: s.alpha,
            initial_radius: r1,
            photons_per_pass: s.photons as u64,
            total_passes: total,
            key,
        };
        let radii = Global { r1, alpha: s.alpha };
        let mut it = Progressive::new(self, radii);
        let driver = self.camera_pass(s, "progressive");
        // A block of passes (`pass_range`) is whole: the CLI refuses a time budget with it.
        let schedule = match s.pass_range {
            Some(_) => Schedule::Passes(count),
            None => Schedule::of(s.budget_seconds(), count, start),
        };
        let out = driver.progressive(&mut it, schedule, first)?;
        let mut partial = Partial::of_pixels(
            header,
            out.pixels.iter().map(|px| &px.sums),
            first,
            out.passes,
        );
        let t = it.totals;
        partial.tally = Tally {
            non_finite: driver.non_finite_samples(),
            photons_emitted: t.photons_emitted,
            photon_seconds: t.photon_seconds,
            camera_seconds: t.camera_seconds,
            partials: 1,
        };
        partial.maps = t.maps;
        partial.options = s.options_json().to_string();
        Ok(partial)
    }

    /// The pppm render: r_1 (given or computed), then passes `0..spp` (or the settings'
    /// `pass_range`, or as many as a time budget allows), as one partial sum and its image.
    pub(super) fn render_pppm(
        &self,
        threads: usize,
        estimate: MemoryEstimate,
        start: Instant,
    ) -> Result<RenderOutput> {
        let s = &self.settings;
        super::compositing::require_none(self.scene, s, "pppm's passes")?;
        let t0 = Instant::now();
        let (r1, source) = match s.initial_radius {
            Some(r) => (r, "given"),
            None => (self.pppm_initial_radius()?, "computed"),
        };
        if !(r1 > 0.0 && r1.is_finite()) {
            return Err(Error::InvalidSetting {
                setting: "initial_radius".into(),
                message: format!("must be a positive distance, got {r1}"),
            });
        }
        let radius_seconds = t0.elapsed().as_secs_f64();
        let (first, count) = match s.pass_range {
            Some((a, b)) => (a, b - a),
            None if s.budget_seconds().is_some() => (0, u32::MAX),
            None => (0, s.spp),
        };
        let key = self.keys.map_or(0, |k| k.render);
        let mut partial = self.pppm_passes(r1, (first, count), s.spp, key, start)?;
        if s.pass_range.is_none() {
            // A whole render (under a time budget, of the passes that fit).
            partial.header.total_passes = partial.passes();
        }
        let mut out = self.pppm_output(&partial, threads, estimate)?;
        if let Some(p) = out.stats.pppm.as_mut() {
            p.initial_radius_source = source.into();
        }
        out.stats
            .seconds
            .insert("initial_radius".into(), radius_seconds);
        if let Some(b) = s.budget_seconds() {
            out.stats.time_budget = Some(
                super::budget::BudgetStats {
                    passes: partial.passes(),
                    spp: partial.passes(),
                    planned_seconds: start.elapsed().as_secs_f64(),
                    seconds_per_pass: (partial.tally.photon_seconds + partial.tally.camera_seconds)
                        / partial.passes().max(1) as f64,
                    photons_global: s.photons,
                    photons_volume: s.volume_photons,
                    ..super::budget::BudgetStats::for_budget(b)
                }
                .finish(start.elapsed().as_secs_f64()),
            );
        }
        out.partial = Some(Box::new(partial));
        Ok(out)
    }

    /// The image and stats of a partial sum (one block, or merged blocks).
    pub fn pppm_output(
        &self,
        partial: &Partial,
        threads: usize,
        estimate: MemoryEstimate,
    ) -> Result<RenderOutput> {
        let t = &partial.tally;
        let mut seconds = BTreeMap::new();
        seconds.insert("photons".to_string(), t.photon_seconds);
        seconds.insert("render".to_string(), t.camera_seconds);
        let mut stats = self.stats(StatsParts {
            width: partial.header.width as usize,
            height: partial.header.height as usize,
            spp: partial.passes(),
            threads,
            seconds,
            maps: progressive::map_stats(&partial.maps),
            irradiance_cache_records: 0,
            skipped: self.skipped_terms(None),
            non_finite_samples: t.non_finite,
            estimate,
            time_budget: None,
            mode: RenderMode::Pppm,
            sppm: None,
            adaptive: None,
        });
        stats.pppm = Some(PppmStats::of_partial(partial));
        Ok(RenderOutput {
            film: partial.film(),
            stats,
            partial: None,
            photon_maps: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radii_follow_knaus_and_zwicker() {
        let r1 = 0.2f32;
        assert_eq!(pass_radius2(r1, 0.7, 0), r1 * r1);
        let r2 = pass_radius2(r1, 0.7, 99) as f64;
        let expect = 0.04 * 100f64.powf(-0.3);
        assert!((r2 - expect).abs() < 1e-7 * expect, "{r2} {expect}");
        assert!(pass_radius2(r1, 0.7, 10) < pass_radius2(r1, 0.7, 9));
    }
}
