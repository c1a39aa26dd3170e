//! Stochastic progressive photon mapping (Hachisuka & Jensen 2009): the `sppm` render mode.
//!
//! **A pass.** Every pixel traces one camera sample (film position from the pixel's
//! replicated Sobol (0,2)-sequence, `render::error_aov::Shifts`, as in the progressive camera
//! pass) through
//! perfect specular bounces to its *visible points*, the non-specular points the path
//! reaches. There direct light, emission and the volume term are estimated as in Jensen's
//! mode. Then a fresh global photon map of `photons.global` stored photons is traced for the
//! pass (its own seed), and each visible point gathers the photons within its pixel's radius
//! R (Jensen 2001, eq. 7.6, over a fixed disk): photons whose path was light -> specular+ ->
//! here add to `caustic`, the others (after a non-specular bounce or a medium) to
//! `indirect`, routed to `specular` behind a specular bounce as everywhere. First-hit
//! photons are left out: light sampling already estimates direct light.
//!
//! **The radius reduction** (H&J 2009, §4.2, eqs. 7–11). With N photons kept so far at the
//! pixel, M found this pass and their flux Φ (BSDF and eye-path throughput included):
//!
//! ```text
//! N' = N + αM,   R'² = R² (N + αM) / (N + M),   τ' = (τ + Φ) R'² / R²
//! ```
//!
//! Each pass's photon powers are normalised by the paths it emitted, so after K passes the
//! photon terms are τ / (π R² K) and the other terms the mean of the passes. R starts at the
//! distance to the `sppm_initial_photons`-th nearest photon around the pixel's first visible
//! point (at most the maximum radius). R² shrinks like K^(α−1), so the density-estimation bias (∝ R²) goes
//! to zero while the variance of the accumulated estimate goes down like K^(−α) (Knaus &
//! Zwicker 2011): the estimate is consistent.
//!
//! **Error estimate.** Each pass also yields its own estimate of the pixel (its eye terms
//! plus Φ / (π R²) with that pass's radius); the `error` AOV is the standard error of their
//! mean over independent replicates (`render::error_aov`). Each pass also estimates the bias of
//! its disk estimate from the photons within R/√2 (see `gather`); the AOV adds the squared
//! mean bias, less that estimate's own variance, to the variance.
//!
//! Deterministic: pass `k`'s photon map depends only on (seed, k), and each pixel's random
//! stream continues across passes, so the image after K passes is the same whatever the
//! thread count and however many passes follow.

use super::aov::Term;
use super::error_aov::{Replicates, Shifts};
use super::eye::{self, EyeCtx, EyeSettings, VisiblePoint};
use super::film::{Film, TermRadiance};
use super::photons::{self, MapStats, PhotonMaps};
use super::renderer::{preview_due, PreviewFn};
use super::settings::RenderSettings;
use super::terms::specular;
use super::terms::volume::MarchSettings;
use crate::error::{Error, Result};
use crate::math::{is_finite3, Spectrum, PI};
use crate::photon::map::PhotonMap;
use crate::photon::map::{FLAG_CAUSTIC_PATH, FLAG_FIRST_HIT};
use crate::photon::KnnScratch;
use crate::sampling::{mix64, Rng};
use crate::scene::Scene;
use serde::Serialize;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

/// What a progressive render did.
#[derive(Clone, Debug, Default, Serialize)]
pub struct SppmStats {
    pub passes: u32,
    pub alpha: f32,
    /// Photons stored per pass (the target; the last batch may overshoot it).
    pub photons_per_pass: u64,
    /// Photon paths emitted over all passes.
    pub photons_emitted: u64,
    /// Mean over pixels with a radius of the first and the final search radius.
    pub mean_initial_radius: f64,
    pub mean_final_radius: f64,
    /// Seconds in the photon passes and in the camera passes with their gathering.
    pub photon_seconds: f64,
    pub camera_seconds: f64,
}

/// The outcome of a progressive render.
pub struct SppmOutput {
    pub film: Film,
    /// Per map: the last pass's stored photons and memory, emitted paths and seconds summed
    /// over the passes; or why the map was not built.
    pub maps: Vec<MapStats>,
    pub passes: u32,
    pub seconds_per_pass: f64,
    pub stats: SppmStats,
}

/// What the progressive loop reads from the renderer.
pub struct SppmJob<'a> {
    pub scene: &'a Scene,
    pub settings: &'a RenderSettings,
    /// Maps the scene needs: global (read by caustic and indirect), volume.
    pub need_global: bool,
    pub need_volume: bool,
    pub cancel: Option<&'a AtomicBool>,
    pub report: &'a (dyn Fn(f32, &str) + Sync),
    /// Seconds since `start` by which the last pass must end; `None` runs `spp` passes.
    pub deadline: Option<f64>,
    pub start: Instant,
    pub non_finite: &'a AtomicUsize,
    pub preview: Option<&'a PreviewFn>,
    pub work: &'a crate::render::work::WorkCounts,
}

struct Pixel {
    rng: Rng,
    shifts: Shifts,
    /// Sum over passes of the terms estimated at the eye.
    eye: TermRadiance,
    /// Accumulated photon flux per term (τ), at the current radius.
    tau: TermRadiance,
    /// Squared search radius; 0 until the pixel first reaches a visible point.
    r2: f32,
    initial_r2: f32,
    /// Photons kept (N).
    n: f32,
    /// Batch means of each pass's own estimate of the pixel (the `error` AOV).
    batches: Replicates,
    /// Batch means of each pass's estimate of the density-estimation bias (see `gather`).
    bias: Replicates,
}

impl<'a> SppmJob<'a> {
    fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }

    pub fn run(&self) -> Result<SppmOutput> {
        use rayon::prelude::*;
        let s = self.settings;
        let scene = self.scene;
        let (w, h) = (scene.width, scene.height);
        let alpha = s.sppm_alpha;
        let mut pixels: Vec<Pixel> = (0..w * h)
            .into_par_iter()
            .map(|i| {
                let mut rng = Rng::new(s.seed, i as u64);
                let shifts = Shifts::draw(&mut rng);
                Pixel {
                    rng,
                    shifts,
                    eye: TermRadiance::default(),
                    tau: TermRadiance::default(),
                    r2: 0.0,
                    initial_r2: 0.0,
                    n: 0.0,
                    batches: Replicates::default(),
                    bias: Replicates::default(),
                }
            })
            .collect();
        let mut stats = SppmStats {
            alpha,
            photons_per_pass: s.photons.global as u64,
            ..SppmStats::default()
        };
        let t = Instant::now();
        let mut passes: u32 = 0;
        let mut all_maps: Vec<MapStats> = Vec::new();
        let mut last_preview = Instant::now();
        loop {
            match self.deadline {
                Some(d) if passes > 0 => {
                    let per_pass = t.elapsed().as_secs_f64() / passes as f64;
                    if self.start.elapsed().as_secs_f64() + per_pass > d || passes == u32::MAX {
                        break;
                    }
                    let f = (self.start.elapsed().as_secs_f64() / d).min(1.0) as f32;
                    (self.report)(f, "progressive");
                }
                None if passes >= s.spp => break,
                None => (self.report)(passes as f32 / s.spp as f32, "progressive"),
                _ => {}
            }
            let tp = Instant::now();
            let pass_seed = mix64(s.seed ^ mix64(0x5350_504D ^ passes as u64));
            let (maps, map_stats) = photons::build(
                scene,
                &s.photons,
                pass_seed,
                [self.need_global, false, self.need_volume],
                self.cancel,
            );
            if self.cancelled() {
                return Err(Error::Cancelled);
            }
            stats.photons_emitted += map_stats
                .iter()
                .filter(|m| m.built && m.map == "global")
                .map(|m| m.emitted)
                .sum::<u64>();
            if all_maps.is_empty() {
                all_maps = map_stats;
            } else {
                for (acc, m) in all_maps.iter_mut().zip(map_stats) {
                    acc.emitted += m.emitted;
                    acc.seconds += m.seconds;
                    acc.stored = m.stored;
                    acc.memory_bytes = m.memory_bytes;
                }
            }
            stats.photon_seconds += tp.elapsed().as_secs_f64();
            let tc = Instant::now();
            self.pass(&maps, passes, alpha, &mut pixels);
            stats.camera_seconds += tc.elapsed().as_secs_f64();
            if self.cancelled() {
                return Err(Error::Cancelled);
            }
            passes += 1;
            if let Some(p) = self.preview {
                if preview_due(passes, &mut last_preview) {
                    p(
                        &self.resolve(&pixels, passes, &mut SppmStats::default()),
                        passes,
                    );
                }
            }
        }
        (self.report)(1.0, "progressive");
        stats.passes = passes;
        let seconds_per_pass = t.elapsed().as_secs_f64() / passes.max(1) as f64;
        let film = self.resolve(&pixels, passes, &mut stats);
        Ok(SppmOutput {
            film,
            maps: all_maps,
            passes,
            seconds_per_pass,
            stats,
        })
    }

    /// One pass: a camera sample per pixel, then its visible points gather this pass's photons.
    fn pass(&self, maps: &PhotonMaps, k: u32, alpha: f32, pixels: &mut [Pixel]) {
        use rayon::prelude::*;
        let s = self.settings;
        let scene = self.scene;
        let w = scene.width.max(1);
        let ctx = EyeCtx {
            scene,
            work: self.work,
            maps,
            cache: None,
            settings: EyeSettings {
                terms: s.terms,
                max_specular_depth: s.max_specular_depth,
                final_gather_rays: 0,
                gather_rays_per_sample: 0,
            },
            march: MarchSettings::for_render(s, scene, maps.global_r2),
        };
        pixels.par_chunks_mut(w).enumerate().for_each_init(
            || (KnnScratch::new(), Vec::<VisiblePoint>::with_capacity(4)),
            |(scratch, vps), (y, row)| {
                if self.cancelled() {
                    return;
                }
                for (x, px) in row.iter_mut().enumerate() {
                    if self.cancelled() {
                        return;
                    }
                    let u = px.shifts.point(k);
                    let ray = eye::camera_ray(scene, &s.filter, x, y, u, &mut px.rng);
                    vps.clear();
                    let mut record = |vp: VisiblePoint| vps.push(vp);
                    let l = eye::trace_split(&ctx, ray, &mut px.rng, scratch, Some(&mut record));
                    let mut pass_total = Spectrum::ZERO;
                    for t in Term::ALL {
                        let v = l.0[t.index()];
                        if v.is_finite() {
                            px.eye.0[t.index()] += v;
                            pass_total += v;
                        } else {
                            self.non_finite.fetch_add(1, Ordering::Relaxed);
                        }
                    }
                    if let Some(global) = &maps.global {
                        pass_total += gather(k, global, maps, vps, px, alpha, s, scratch);
                    }
                    px.batches.add(k, pass_total);
                }
            },
        );
    }

    /// The image after `passes` passes, with the `error` AOV.
    fn resolve(&self, pixels: &[Pixel], passes: u32, stats: &mut SppmStats) -> Film {
        let (w, h) = (self.scene.width, self.scene.height);
        let mut film = Film::new(w, h);
        let k = passes.max(1) as f32;
        let (mut r0, mut r1, mut counted) = (0.0f64, 0.0f64, 0u64);
        for (i, px) in pixels.iter().enumerate() {
            let mut v = TermRadiance::default();
            for t in Term::ALL {
                let photon = if px.r2 > 0.0 {
                    px.tau.0[t.index()] / (PI * px.r2 * k)
                } else {
                    Spectrum::ZERO
                };
                v.0[t.index()] = px.eye.0[t.index()] / k + photon;
            }
            film.set_pixel(i % w, i / w, &v);
            film.error.data[i] = total_error(&px.batches, &px.bias).to_array();
            if px.r2 > 0.0 {
                r0 += (px.initial_r2 as f64).sqrt();
                r1 += (px.r2 as f64).sqrt();
                counted += 1;
            }
        }
        if counted > 0 {
            stats.mean_initial_radius = r0 / counted as f64;
            stats.mean_final_radius = r1 / counted as f64;
        }
        film
    }
}

/// Gathers this pass's photons at the pixel's visible points and updates its statistics.
/// Returns the pass's own estimate of the photon terms, Φ / (π R²) at the radius it used.
#[allow(clippy::too_many_arguments)]
fn gather(
    k: u32,
    global: &PhotonMap,
    maps: &PhotonMaps,
    vps: &[VisiblePoint],
    px: &mut Pixel,
    alpha: f32,
    s: &RenderSettings,
    scratch: &mut KnnScratch,
) -> Spectrum {
    let Some(first) = vps.first() else {
        return Spectrum::ZERO;
    };
    if px.r2 <= 0.0 {
        px.r2 = initial_radius2(
            global,
            first,
            s.sppm_initial_photons,
            maps.global_r2,
            scratch,
        );
        px.initial_r2 = px.r2;
    }
    let r2 = px.r2;
    let mut phi = TermRadiance::default();
    let mut phi_inner = Spectrum::ZERO;
    let mut m = 0u32;
    for vp in vps {
        global.tree.for_each_in_radius(vp.p, r2, |ph, d2| {
            let flags = ph.user_flags();
            if flags & FLAG_FIRST_HIT != 0 {
                return;
            }
            let wi = ph.incoming();
            if wi.dot(vp.n) <= 0.0 {
                return;
            }
            let term = if flags & FLAG_CAUSTIC_PATH != 0 {
                Term::Caustic
            } else {
                Term::Indirect
            };
            let t = specular::route(term, vp.bounces);
            if !s.terms.contains(t) {
                return;
            }
            let c = vp.beta * vp.bsdf.eval(vp.wo, wi) * ph.power();
            if is_finite3(c) {
                phi.add(t, c);
                m += 1;
                if 2.0 * d2 <= r2 {
                    phi_inner += c;
                }
            }
        });
    }
    let pass_estimate = phi.total() / (PI * r2);
    // Bias of a disk estimate grows as R² (R²/8 times the Laplacian of the radiance), so the
    // same photons over the disk of half the area, radius R/√2, have half of it: from
    // L_R = L + b and L_R/√2 = L + b/2, b = 2 (L_R - L_R/√2).
    let inner_estimate = phi_inner / (PI * r2 / 2.0);
    px.bias.add(k, (pass_estimate - inner_estimate) * 2.0);
    if m > 0 {
        let (n, m) = (px.n, m as f32);
        let kept = n + alpha * m;
        let ratio = kept / (n + m);
        px.n = kept;
        px.r2 = r2 * ratio;
        for t in Term::ALL {
            let i = t.index();
            px.tau.0[i] = (px.tau.0[i] + phi.0[i]) * ratio;
        }
    }
    pass_estimate
}

/// The `error` AOV of a progressive pixel: sqrt(s² + b²), the standard error of its passes
/// and its estimated bias, where b² is the squared mean of the per-pass bias estimates less
/// their own variance (so that noise in them does not pass for bias); the sum is at least 0.
fn total_error(passes: &Replicates, bias: &Replicates) -> Spectrum {
    let se = passes.standard_error();
    let b = bias.mean();
    let sb = bias.standard_error();
    (se * se + b * b - sb * sb)
        .max(Spectrum::ZERO)
        .to_array()
        .map(f32::sqrt)
        .into()
}

/// The pixel's first radius²: the distance² to the `k`-th nearest photon at `vp` (photons of
/// any kind, as a measure of the local density), at most `max_r2`.
fn initial_radius2(
    map: &PhotonMap,
    vp: &VisiblePoint,
    k: usize,
    max_r2: f32,
    scratch: &mut KnnScratch,
) -> f32 {
    let found = map.tree.knn(vp.p, k.max(1), max_r2, scratch);
    if found.len() >= k.max(1) {
        let far = found.iter().map(|nb| nb.dist2).fold(0.0f32, f32::max);
        if far > 0.0 && far.is_finite() {
            return far;
        }
    }
    max_r2
}
