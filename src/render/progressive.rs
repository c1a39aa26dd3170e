//! The progressive integrator that `sppm` and `pppm` share (as SmallVCM serves its algorithms
//! from one class): every pass traces a fresh global (and volume) photon map with the pass's
//! own seed; every camera sample is traced through perfect specular bounces to its visible
//! points, where direct light, emission and media are estimated at the eye as in Jensen's
//! mode, and where the pass's photons are gathered within a radius.
//!
//! The modes differ in their [`Radii`]: how a pass is seeded, how the radius goes down (per
//! pixel with the photons it kept, `sppm`; globally with the pass index, `pppm`), where the
//! gathered flux goes, and what a pixel accumulates. A new progressive mode is one more
//! `Radii`.

use super::accumulate::Accumulator;
use super::compositing::SampleAovs;
use super::driver::{Integrator, Pixel};
use super::eye::{self, EyeCtx, EyeSettings, VisiblePoint};
use super::film::TermRadiance;
use super::photons::{self, MapStats, PhotonMaps};
use super::renderer::Renderer;
use super::settings::RenderSettings;
use crate::error::{Error, Result};
use crate::geometry::Ray;
use crate::math::Spectrum;
use crate::photon::map::PhotonMap;
use crate::photon::KnnScratch;
use crate::sampling::Rng;
use std::time::Instant;

/// What a progressive mode supplies: its radius schedule and where the photons go.
pub trait Radii: Sync {
    /// Per-pixel state beyond the driver's.
    type Extra: Send + Sync + Default;
    /// What a pixel sums over its passes.
    type Acc: Accumulator;
    /// Whether the global map carries precomputed irradiance points.
    const IRRADIANCE_POINTS: bool;

    /// The seed of pass `k`'s photon map in a render seeded with `seed`.
    fn pass_seed(&self, seed: u64, k: u32) -> u64;

    /// Pass `k`'s squared radius where it is the same for every pixel; 0 where the pixels
    /// keep their own.
    fn pass_radius2(&self, _k: u32) -> f32 {
        0.0
    }

    /// A random stream of its own for `pixel` in the pass seeded `pass_seed`; `None`
    /// continues the pixel's stream from pass to pass.
    fn pass_rng(&self, _pass_seed: u64, _pixel: usize) -> Option<Rng> {
        None
    }

    /// Gathers the pass's photons at the sample's visible points `vps`: adds to the eye terms
    /// `l` what belongs to this sample, keeps in `extra` what the pixel keeps, and returns the
    /// sample's further share of the combined image (for the `error` AOV).
    #[allow(clippy::too_many_arguments)]
    fn gather(
        &self,
        ctx: &EyeCtx,
        pass: &ProgressivePass,
        global: &PhotonMap,
        vps: &[VisiblePoint],
        extra: &mut Self::Extra,
        scratch: &mut KnnScratch,
        l: &mut TermRadiance,
    ) -> Spectrum;

    /// The pixel's terms and `error` after `passes` passes.
    fn resolve(&self, px: &Pixel<Self::Extra, Self::Acc>, passes: u32) -> (TermRadiance, Spectrum) {
        px.sums.resolve(passes)
    }

    /// Adds to the pixel's light groups what the pixel keeps apart from its samples.
    fn resolve_groups(
        &self,
        _px: &Pixel<Self::Extra, Self::Acc>,
        _passes: u32,
        _groups: &mut [Spectrum],
    ) {
    }
}

/// The eye's settings in the progressive modes: no final gathering (the photons are gathered
/// at the visible points).
pub fn eye_settings(s: &RenderSettings) -> EyeSettings {
    EyeSettings {
        terms: s.terms,
        max_specular_depth: s.max_specular_depth,
        final_gather_rays: 0,
        gather_rays_per_sample: 0,
    }
}

/// A pass: its photons, its seed and (where global) its radius.
pub struct ProgressivePass {
    pub maps: PhotonMaps,
    pub seed: u64,
    pub k: u32,
    /// The pass's squared radius where global (`Radii::pass_radius2`).
    pub r2: f32,
}

/// What the passes did, for the stats.
#[derive(Clone, Debug, Default)]
pub struct PassTotals {
    /// Photon paths emitted for the global maps.
    pub photons_emitted: u64,
    /// Seconds in the photon passes, and in the camera passes with their gathering.
    pub photon_seconds: f64,
    pub camera_seconds: f64,
    /// Per map: the last pass's stored photons and memory, emitted paths and seconds summed
    /// over the passes; or why the map was not built.
    pub maps: Vec<MapStats>,
}

/// The progressive integrator of a mode's [`Radii`].
pub struct Progressive<'a, R> {
    pub renderer: &'a Renderer<'a>,
    pub radii: R,
    /// The maps a pass builds: global, caustic (never: the global map holds the caustic
    /// photons), volume.
    need: [bool; 3],
    pub totals: PassTotals,
}

impl<'a, R: Radii> Progressive<'a, R> {
    pub fn new(renderer: &'a Renderer<'a>, radii: R) -> Self {
        let [global, _, volume] = renderer.needed_maps();
        Progressive {
            renderer,
            radii,
            need: [global, false, volume],
            totals: PassTotals::default(),
        }
    }
}

impl<R: Radii> Integrator for Progressive<'_, R> {
    type Extra = R::Extra;
    type Acc = R::Acc;
    type Scratch = (KnnScratch, Vec<VisiblePoint>);
    type Pass = ProgressivePass;

    fn scratch(&self) -> Self::Scratch {
        (KnnScratch::new(), Vec::with_capacity(4))
    }

    /// Traces pass `k`'s photon map, with the pass's own seed.
    fn begin_pass(&mut self, k: u32) -> Result<ProgressivePass> {
        let r = self.renderer;
        let s = &r.settings;
        let seed = self.radii.pass_seed(s.seed, k);
        let tp = Instant::now();
        let (maps, map_stats) = photons::build_with(
            r.scene,
            s,
            seed,
            self.need,
            r.cancel(),
            R::IRRADIANCE_POINTS,
        );
        if r.is_cancelled() {
            return Err(Error::Cancelled);
        }
        let t = &mut self.totals;
        t.photons_emitted += map_stats
            .iter()
            .filter(|m| m.built && m.map == "global")
            .map(|m| m.emitted)
            .sum::<u64>();
        if t.maps.is_empty() {
            t.maps = map_stats;
        } else {
            for (acc, m) in t.maps.iter_mut().zip(map_stats) {
                acc.emitted += m.emitted;
                acc.seconds += m.seconds;
                acc.stored = m.stored;
                acc.memory_bytes = m.memory_bytes;
            }
        }
        t.photon_seconds += tp.elapsed().as_secs_f64();
        Ok(ProgressivePass {
            maps,
            seed,
            k,
            r2: self.radii.pass_radius2(k),
        })
    }

    fn end_pass(&mut self, _pass: ProgressivePass, camera_seconds: f64) {
        self.totals.camera_seconds += camera_seconds;
    }

    fn pass_rng(&self, pass: &ProgressivePass, pixel: usize) -> Option<Rng> {
        self.radii.pass_rng(pass.seed, pixel)
    }

    /// A camera sample to its visible points, where its eye terms are estimated; then the
    /// visible points gather the pass's photons.
    fn sample(
        &self,
        pass: &ProgressivePass,
        ray: Ray,
        rng: &mut Rng,
        extra: &mut R::Extra,
        _k: u32,
        (scratch, vps): &mut Self::Scratch,
        aovs: &mut SampleAovs,
    ) -> (TermRadiance, Spectrum) {
        let r = self.renderer;
        let ctx = r.eye_ctx(&r.settings, &pass.maps, None, eye_settings(&r.settings));
        vps.clear();
        let mut record = |vp: VisiblePoint| vps.push(vp);
        let mut l = eye::trace_split(&ctx, ray, rng, scratch, Some(&mut record), aovs);
        let further = match &pass.maps.global {
            Some(global) => self
                .radii
                .gather(&ctx, pass, global, vps, extra, scratch, &mut l),
            None => Spectrum::ZERO,
        };
        (l, further)
    }

    fn resolve(&self, px: &Pixel<R::Extra, R::Acc>, passes: u32) -> (TermRadiance, Spectrum) {
        self.radii.resolve(px, passes)
    }

    fn resolve_groups(&self, px: &Pixel<R::Extra, R::Acc>, passes: u32, groups: &mut [Spectrum]) {
        self.radii.resolve_groups(px, passes, groups)
    }
}

/// The stats of the passes' photon maps as the progressive modes report them: the caustic map
/// is never built, its photons being in each pass's global map.
pub fn map_stats(maps: &[MapStats]) -> Vec<MapStats> {
    let mut maps = maps.to_vec();
    for m in maps.iter_mut().filter(|m| m.map == "caustic") {
        m.skipped_because =
            Some("progressive mode: each pass's global map holds the caustic photons".into());
    }
    maps
}
