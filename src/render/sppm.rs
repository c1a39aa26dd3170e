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
//! distance to the `initial_photons`-th nearest photon around the pixel's first visible
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

use super::accumulate::Sums;
use super::aov::Term;
use super::budget::BudgetStats;
use super::driver::{Pixel, Schedule};
use super::error_aov::Replicates;
use super::eye::{EyeCtx, VisiblePoint};
use super::film::TermRadiance;
use super::memory::MemoryEstimate;
use super::output::RenderOutput;
use super::photons::PhotonMaps;
use super::progressive::{self, Progressive, ProgressivePass, Radii};
use super::renderer::Renderer;
use super::settings::{RenderMode, RenderSettings};
use super::stats::{SppmStats, StatsParts};
use crate::error::Result;
use crate::math::{is_finite3, Spectrum, PI};
use crate::photon::map::{group_of, PhotonMap};
use crate::photon::KnnScratch;
use crate::sampling::mix64;
use std::collections::BTreeMap;
use std::time::Instant;

/// A pixel's progressive statistics, beside the driver's (whose `acc` sums the terms
/// estimated at the eye over the passes).
#[derive(Default)]
struct Radius {
    /// Accumulated photon flux per term (τ), at the current radius.
    tau: TermRadiance,
    /// With light groups, the same flux per group (the photons' groups); empty without.
    tau_groups: Vec<Spectrum>,
    /// Squared search radius; 0 until the pixel first reaches a visible point.
    r2: f32,
    initial_r2: f32,
    /// Photons kept (N).
    n: f32,
    /// Batch means of each pass's estimate of the density-estimation bias (see `gather`).
    bias: Replicates,
}

/// sppm's radii: each pixel's own, shrinking with the photons it keeps.
struct Shrinking<'a> {
    settings: &'a RenderSettings,
    /// Light groups of the scene.
    groups: usize,
}

impl Radii for Shrinking<'_> {
    type Extra = Radius;
    type Acc = Sums;
    const IRRADIANCE_POINTS: bool = true;

    fn pass_seed(&self, seed: u64, k: u32) -> u64 {
        mix64(seed ^ mix64(0x5350_504D ^ k as u64))
    }

    fn gather(
        &self,
        _ctx: &EyeCtx,
        pass: &ProgressivePass,
        global: &PhotonMap,
        vps: &[VisiblePoint],
        px: &mut Radius,
        scratch: &mut KnnScratch,
        _l: &mut TermRadiance,
    ) -> Spectrum {
        gather(
            pass.k,
            global,
            &pass.maps,
            vps,
            px,
            self.settings,
            scratch,
            self.groups,
        )
    }

    /// The eye terms' mean over the passes plus τ / (π R² K); the `error` with the bias.
    fn resolve(&self, px: &Pixel<Radius>, passes: u32) -> (TermRadiance, Spectrum) {
        let k = passes.max(1) as f32;
        let x = &px.extra;
        let mut v = TermRadiance::default();
        for t in Term::ALL {
            let photon = if x.r2 > 0.0 {
                x.tau.0[t.index()] / (PI * x.r2 * k)
            } else {
                Spectrum::ZERO
            };
            v.0[t.index()] = px.sums.acc.0[t.index()] / k + photon;
        }
        (v, total_error(&px.sums.batches, &x.bias))
    }

    /// Each light group's photon flux, τ_g / (π R² K), beside the means of its eye terms.
    fn resolve_groups(&self, px: &Pixel<Radius>, passes: u32, groups: &mut [Spectrum]) {
        let x = &px.extra;
        if x.r2 > 0.0 {
            let k = passes.max(1) as f32;
            for (g, tau) in groups.iter_mut().zip(&x.tau_groups) {
                *g += *tau / (PI * x.r2 * k);
            }
        }
    }
}

impl Renderer<'_> {
    /// A progressive photon-mapping render: `spp` passes, or as many as fit in the time
    /// budget.
    pub(super) fn render_sppm(
        &self,
        threads: usize,
        estimate: MemoryEstimate,
        start: Instant,
    ) -> Result<RenderOutput> {
        let s = &self.settings;
        let budget_seconds = s.budget_seconds();
        let driver = self.camera_pass(s, "progressive");
        let radii = Shrinking {
            settings: s,
            groups: self.scene.light_groups.len(),
        };
        let mut sppm = Progressive::new(self, radii);
        let schedule = Schedule::of(budget_seconds, s.spp, start);
        let out = driver.progressive(&mut sppm, schedule, 0)?;
        let t = sppm.totals;
        let mut stats = SppmStats {
            passes: out.passes,
            alpha: s.alpha,
            photons_per_pass: s.photons as u64,
            photons_emitted: t.photons_emitted,
            photon_seconds: t.photon_seconds,
            camera_seconds: t.camera_seconds,
            ..SppmStats::default()
        };
        let (mut r0, mut r1, mut counted) = (0.0f64, 0.0f64, 0u64);
        for x in out.pixels.iter().map(|px| &px.extra).filter(|x| x.r2 > 0.0) {
            r0 += (x.initial_r2 as f64).sqrt();
            r1 += (x.r2 as f64).sqrt();
            counted += 1;
        }
        if counted > 0 {
            stats.mean_initial_radius = r0 / counted as f64;
            stats.mean_final_radius = r1 / counted as f64;
        }
        let mut seconds = BTreeMap::new();
        seconds.insert("photons".to_string(), stats.photon_seconds);
        seconds.insert("render".to_string(), stats.camera_seconds);
        let maps = progressive::map_stats(&t.maps);
        let time_budget = budget_seconds.map(|b| {
            BudgetStats {
                planned_seconds: out.passes as f64 * out.seconds_per_pass,
                passes: out.passes,
                spp: out.passes,
                seconds_per_pass: out.seconds_per_pass,
                photons_global: s.photons,
                photons_volume: s.volume_photons,
                ..BudgetStats::for_budget(b)
            }
            .finish(start.elapsed().as_secs_f64())
        });
        let stats = self.stats(StatsParts {
            width: self.scene.width,
            height: self.scene.height,
            spp: out.passes,
            threads,
            seconds,
            maps,
            irradiance_cache_records: 0,
            skipped: self.skipped_terms(None),
            non_finite_samples: driver.non_finite_samples(),
            estimate,
            time_budget,
            mode: RenderMode::Sppm,
            sppm: Some(stats),
            adaptive: None,
        });
        Ok(RenderOutput {
            film: out.film,
            stats,
            partial: None,
            photon_maps: None,
        })
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
    px: &mut Radius,
    s: &RenderSettings,
    scratch: &mut KnnScratch,
    groups: usize,
) -> Spectrum {
    let Some(first) = vps.first() else {
        return Spectrum::ZERO;
    };
    if px.r2 <= 0.0 {
        px.r2 = initial_radius2(global, first, s.initial_photons, maps.global_r2, scratch);
        px.initial_r2 = px.r2;
    }
    let r2 = px.r2;
    let mut phi = TermRadiance::default();
    let mut phi_groups = vec![Spectrum::ZERO; groups];
    let mut phi_inner = Spectrum::ZERO;
    let mut m = 0u32;
    for vp in vps {
        global.tree.for_each_in_radius(vp.p, r2, |ph, d2| {
            let Some(t) = vp.photon_term(ph.user_flags()) else {
                return;
            };
            let wi = ph.incoming();
            if wi.dot(vp.n) <= 0.0 || !s.terms.contains(t) {
                return;
            }
            let c = vp.beta * vp.bsdf.eval_flux(vp.wo, wi) * ph.power();
            if is_finite3(c) {
                phi.add(t, c);
                if let Some(g) = phi_groups.get_mut(group_of(ph.user_flags())) {
                    *g += c;
                }
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
        let kept = n + s.alpha * m;
        let ratio = kept / (n + m);
        px.n = kept;
        px.r2 = r2 * ratio;
        for t in Term::ALL {
            let i = t.index();
            px.tau.0[i] = (px.tau.0[i] + phi.0[i]) * ratio;
        }
        px.tau_groups.resize(groups, Spectrum::ZERO);
        for (tau, p) in px.tau_groups.iter_mut().zip(&phi_groups) {
            *tau = (*tau + *p) * ratio;
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
