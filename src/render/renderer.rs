//! The renderer builder: the scene, the settings, progress callback and cancel flag, photon
//! maps to reuse or keep; and what every mode asks of it (the camera pass, the eye context,
//! progress, cancellation). `run.rs` renders with it; each mode's pipeline is its own file.
//!
//! Each pixel draws its random numbers from its own stream, derived from (seed, pixel index),
//! and pixels are independent (see `driver`), so the output is bit-identical for any thread
//! count.

use super::aov::Term;
use super::compositing::AovLayout;
use super::driver::CameraPass;
use super::settings::RenderSettings;
use crate::scene::Scene;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

pub use super::driver::{OutputTimeFn, PreviewFn, ProgressFn};

/// Hashes that identify what a render's photon maps and partial sums depend on (computed by
/// the front end from the scene IR, `render::map_file::keys`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderKeys {
    /// Geometry, lights, materials, media, photon settings, seed and version: not the
    /// camera (the photon maps' key).
    pub maps: u64,
    /// The camera and the film (the view an irradiance cache was filled for).
    pub view: u64,
    /// Everything a pppm pass depends on: scene, camera, film and settings.
    pub render: u64,
}

pub struct Renderer<'a> {
    pub(super) scene: &'a Scene,
    pub(super) settings: RenderSettings,
    pub(super) progress: Option<Arc<ProgressFn>>,
    pub(super) cancel: Option<Arc<AtomicBool>>,
    pub(super) preview: Option<Arc<PreviewFn>>,
    pub(super) output_time: Option<Arc<OutputTimeFn>>,
    pub(super) work: super::work::WorkCounts,
    pub(super) keys: Option<RenderKeys>,
    /// Photon maps (and an irradiance cache) to use instead of building them.
    pub(super) reuse: Option<std::sync::Arc<super::map_file::MapSet>>,
    pub(super) keep_maps: bool,
    pub(super) key_parts: Option<super::map_file::KeyParts>,
    /// Jensen's mode: build the photon maps and the irradiance cache only.
    pub(super) maps_only: bool,
    /// The compositing AOVs of the render (set when it starts, from the settings).
    pub(super) aovs: AovLayout,
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
            keys: None,
            reuse: None,
            keep_maps: false,
            key_parts: None,
            maps_only: false,
            aovs: AovLayout::none(),
        }
    }
    /// The parts of the photon-map key, stored with kept maps (see `map_file::KeyParts`).
    pub fn key_parts(mut self, parts: super::map_file::KeyParts) -> Self {
        self.key_parts = Some(parts);
        self
    }
    /// Jensen's mode: build the photon maps and the irradiance cache for the view, and stop
    /// before the camera pass; the output's film is empty and `photon_maps` holds them.
    pub fn maps_only(mut self, only: bool) -> Self {
        self.maps_only = only;
        self.keep_maps |= only;
        self
    }
    /// The keys of the scene and settings (see [`RenderKeys`]).
    pub fn keys(mut self, keys: RenderKeys) -> Self {
        self.keys = Some(keys);
        self
    }
    /// Jensen's mode: render with these photon maps (and their irradiance cache, extended
    /// for this render's view) instead of building them. Their key must be this render's.
    pub fn reuse_photon_maps(mut self, maps: std::sync::Arc<super::map_file::MapSet>) -> Self {
        self.reuse = Some(maps);
        self
    }
    /// Jensen's mode: return the photon maps and irradiance cache in the output.
    pub fn keep_photon_maps(mut self, keep: bool) -> Self {
        self.keep_maps = keep;
        self
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

    pub(super) fn cancel(&self) -> Option<&AtomicBool> {
        self.cancel.as_deref()
    }

    /// The camera-pass driver of this render, reporting `phase`.
    pub(super) fn camera_pass<'r>(
        &'r self,
        s: &'r RenderSettings,
        phase: &'static str,
    ) -> CameraPass<'r> {
        let mut driver = CameraPass::new(self.scene, s.pixel_filter(), s.seed, phase);
        driver.progress = self.progress.as_deref();
        driver.cancel = self.cancel();
        driver.preview = self.preview.as_deref();
        driver.output_time = self.output_time.as_deref();
        driver.aovs = &self.aovs;
        driver
    }

    /// What the eye reads under settings `s` (the render's, or a budget's plan): the scene,
    /// the work counters, the photon maps, the irradiance cache, and the march through media
    /// at the maps' largest radius.
    pub(super) fn eye_ctx<'c>(
        &'c self,
        s: &RenderSettings,
        maps: &'c super::photons::PhotonMaps,
        cache: Option<&'c super::irradiance_cache::IrradianceCache>,
        settings: super::eye::EyeSettings,
    ) -> super::eye::EyeCtx<'c> {
        super::eye::EyeCtx {
            scene: self.scene,
            work: &self.work,
            maps,
            cache,
            settings,
            march: super::terms::volume::MarchSettings::for_render(s, self.scene, maps.global_r2),
        }
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
        if s.mode.is_progressive() {
            // One global map per pass serves both photon terms.
            let terms = s.terms.contains(Term::Caustic) || s.terms.contains(Term::Indirect);
            return [terms, false, need_volume];
        }
        let need_global = s.terms.contains(Term::Indirect) && s.final_gather_rays > 0;
        let need_caustic = s.terms.contains(Term::Caustic);
        [need_global, need_caustic, need_volume]
    }
}
