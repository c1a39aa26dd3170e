//! The stats of a render: what it did, what it skipped and why, with the settings it was
//! given. Written as the stats JSON (`command::report`). The stats of a merged pppm image are
//! made here too ([`RenderStats::of_partial`]), by the same code as a render's.

use super::adaptive::AdaptiveStats;
use super::aov::Term;
use super::budget::BudgetStats;
use super::memory::MemoryEstimate;
use super::partial::{pass_radius2, Partial};
use super::photons::{self, MapStats, PhotonMaps};
use super::renderer::Renderer;
use super::settings::RenderSettings;
use super::settings::{RenderMode, BYTES_PER_TRIANGLE};
use crate::error::{Error, Result};
use serde::Serialize;
use std::collections::BTreeMap;

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

/// What a progressive (pppm) render did.
#[derive(Clone, Debug, Default, Serialize)]
pub struct PppmStats {
    /// Passes in the image.
    pub passes: u32,
    /// The passes rendered, as half-open ranges `[first, end)` (one for a whole render, one
    /// per block in a merge).
    pub pass_ranges: Vec<(u32, u32)>,
    pub alpha: f32,
    /// The first pass's radius r_1, and whether it was computed or given.
    pub initial_radius: f32,
    pub initial_radius_source: String,
    /// The last pass's radius.
    pub final_radius: f32,
    /// Photons stored per pass (the target; the last batch may overshoot it).
    pub photons_per_pass: u64,
    /// Photon paths emitted over all passes.
    pub photons_emitted: u64,
    /// Seconds in the photon passes and in the camera passes, summed over the blocks.
    pub photon_seconds: f64,
    pub camera_seconds: f64,
    /// Partial sums merged into this image (1 for a render in one piece).
    pub partials: u32,
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
    /// The scene's warnings (`Scene::warnings`): what renders other than the IR says.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// What the materials' shading graphs compiled to (all zero without graphs: nothing of
    /// them runs).
    pub shading_graphs: crate::materials::graph::GraphStats,
    /// Estimates that came out NaN or infinite and were dropped.
    pub non_finite_samples: u64,
    /// Approximate bytes held by the render (film and scene geometry).
    pub memory_bytes: u64,
    /// Of `memory_bytes`, the compositing AOVs (`render::compositing`): their images and
    /// each pixel's sums; 0 when none were asked for.
    pub aov_memory_bytes: u64,
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
    /// What a distributable progressive (pppm) render did; absent in the other modes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pppm: Option<PppmStats>,
    /// Jensen's mode: where the photon maps and the irradiance cache came from (built,
    /// reused from an earlier frame, or loaded from a file) and where they were saved.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub photon_map_reuse: Option<super::map_file::ReuseStats>,
    /// What adaptive sampling did (pixels refined, samples added); absent where it was off
    /// or the camera pass ran in whole passes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adaptive: Option<AdaptiveStats>,
    /// Work done per kind (march steps, volume and caustic map lookups).
    pub work: crate::render::work::WorkStats,
    /// What denoised the terms (filter, version, binding, terms, seconds), set by the front
    /// end that ran the denoiser; absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub denoise: Option<serde_json::Value>,
    /// The settings the render was given (a budgeted render's plan is under `time_budget`).
    pub settings: RenderSettings,
    /// The same settings without the engine's own, as the keywords and flags take them
    /// (`render::settings`): `photonmap.render(scene, **stats["options"])` renders the same
    /// image (a budgeted render is replayed from its plan, `time_budget`).
    pub options: serde_json::Value,
    /// The figures these stats do not know, which the stats JSON gives as `null`: in the stats
    /// of a merged pppm image, [`RenderStats::SCENE_FIGURES`].
    #[serde(skip)]
    pub unknown: &'static [&'static str],
}

/// What a render measured, for [`RenderStats`].
pub(super) struct StatsParts {
    pub(super) width: usize,
    pub(super) height: usize,
    pub(super) spp: u32,
    pub(super) threads: usize,
    pub(super) seconds: std::collections::BTreeMap<String, f64>,
    pub(super) maps: Vec<MapStats>,
    pub(super) irradiance_cache_records: u64,
    pub(super) skipped: Vec<SkippedTerm>,
    pub(super) non_finite_samples: u64,
    pub(super) estimate: MemoryEstimate,
    pub(super) time_budget: Option<BudgetStats>,
    pub(super) mode: RenderMode,
    pub(super) sppm: Option<SppmStats>,
    pub(super) adaptive: Option<AdaptiveStats>,
}

impl Renderer<'_> {
    /// The terms that are zero in this render, and why: first what the settings and the scene
    /// rule out (both modes), then, given Jensen's `maps`, the maps that were not built.
    pub(super) fn skipped_terms(&self, maps: Option<&PhotonMaps>) -> Vec<SkippedTerm> {
        let s = &self.settings;
        let photon_term = |t| matches!(t, Term::Caustic | Term::Indirect);
        let mut out = Vec::new();
        for t in Term::ALL {
            let reason = if !s.terms.contains(t) {
                "disabled in the render settings"
            } else if self.scene.lights.is_empty() && photon_term(t) {
                "the scene has no lights"
            } else if t == Term::Caustic && photons::specular_targets(self.scene).is_empty() {
                "the scene has no specular or transmissive surfaces"
            } else if t == Term::Volume && !self.scene.has_media() {
                "the scene has no participating media"
            } else if t == Term::Subsurface && !self.scene.has_subsurface() {
                "the scene has no subsurface materials"
            } else {
                match (t, maps) {
                    (Term::Indirect, Some(m)) if m.global.is_none() => {
                        "no global photon map (see photon_maps)"
                    }
                    (Term::Indirect, Some(_)) if s.final_gather_rays == 0 => {
                        "final gathering disabled (0 rays)"
                    }
                    (Term::Caustic, Some(m)) if m.caustic.is_none() => {
                        "no caustic photon map (see photon_maps)"
                    }
                    _ => continue,
                }
            };
            out.push(SkippedTerm {
                term: t.name(),
                reason: reason.to_string(),
            });
        }
        out
    }

    /// The stats of a render of any mode, from what it measured: the figures of the settings
    /// and the measures ([`RenderStats::measured`]) and those of the scene.
    pub(super) fn stats(&self, p: StatsParts) -> RenderStats {
        let aov_bytes = self.aovs.memory_bytes(p.width, p.height);
        let mut st = RenderStats::measured(&self.settings, p);
        st.warnings = self.scene.warnings.clone();
        st.shading_graphs = self.scene.graph_stats;
        st.work = self.work.stats();
        st.triangles = self.scene.triangle_count;
        st.lights = self.scene.lights.len();
        // The film (one image per term and the error AOV), the scene geometry, the photon
        // maps and the compositing AOVs.
        st.memory_bytes += self.scene.triangle_count as u64 * 64 + aov_bytes;
        st.aov_memory_bytes = aov_bytes;
        st
    }
}

impl RenderStats {
    /// The figures that come from the render's scene and machine (`Renderer::stats`), which
    /// partial sums do not carry: the stats of a merged pppm image give them as `null`.
    pub const SCENE_FIGURES: &'static [&'static str] = &[
        "threads",
        "triangles",
        "lights",
        "memory_bytes",
        "memory_estimate",
        "shading_graphs",
        "skipped",
        "work",
    ];

    /// Bytes of a `width` x `height` film: one RGB `f32` image per term and the error AOV.
    fn film_memory_bytes(width: usize, height: usize) -> u64 {
        (width * height * (Term::COUNT + 1) * 12) as u64
    }

    /// The stats of `settings` and of what a render measured, without its scene's figures
    /// (zero here; `Renderer::stats` fills them in). `memory_bytes` holds the film and the
    /// photon maps.
    fn measured(s: &RenderSettings, p: StatsParts) -> RenderStats {
        let photon_bytes: u64 = p.maps.iter().map(|m| m.memory_bytes).sum();
        RenderStats {
            settings: s.clone(),
            options: s.options_json(),
            version: env!("CARGO_PKG_VERSION"),
            seed: s.seed,
            width: p.width,
            height: p.height,
            spp: p.spp,
            threads: p.threads,
            seconds: p.seconds,
            camera_rays: (p.width * p.height) as u64 * p.spp as u64
                + p.adaptive.map_or(0, |a| a.extra_samples),
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
            memory_bytes: Self::film_memory_bytes(p.width, p.height) + photon_bytes,
            memory_estimate: p.estimate,
            bytes_per_photon: s.bytes_per_photon(),
            bytes_per_triangle: BYTES_PER_TRIANGLE,
            time_budget: p.time_budget,
            mode: p.mode,
            sppm: p.sppm,
            adaptive: p.adaptive,
            ..RenderStats::default()
        }
    }

    /// The stats of the image of partial sums `p` (a merge of blocks of pppm passes): what a
    /// render of those passes in one piece reports, from the partial sums alone. The settings
    /// are those the blocks recorded (the thread count of the block `p` took them from); the
    /// photon maps are those `p` keeps, a block's last pass's (`command::merge::sum` keeps
    /// the latest block's: the render's last pass); the figures of the scene and the machine
    /// ([`Self::SCENE_FIGURES`]) are unknown.
    pub fn of_partial(p: &Partial) -> Result<RenderStats> {
        let settings = RenderSettings::from_json(&p.options).map_err(|e| {
            Error::Internal(format!(
                "the partial sums' render options are not readable: {e}"
            ))
        })?;
        let t = &p.tally;
        let mut seconds = BTreeMap::new();
        seconds.insert("photons".to_string(), t.photon_seconds);
        seconds.insert("render".to_string(), t.camera_seconds);
        let mut st = RenderStats::measured(
            &settings,
            StatsParts {
                width: p.header.width as usize,
                height: p.header.height as usize,
                spp: p.passes(),
                threads: 0,
                seconds,
                maps: super::progressive::map_stats(&p.maps),
                irradiance_cache_records: 0,
                skipped: Vec::new(),
                non_finite_samples: t.non_finite,
                estimate: MemoryEstimate::default(),
                time_budget: None,
                mode: RenderMode::Pppm,
                sppm: None,
                adaptive: None,
            },
        );
        let mut pppm = PppmStats::of_partial(p);
        if settings.initial_radius.is_none() {
            pppm.initial_radius_source = "computed".into();
        }
        st.pppm = Some(pppm);
        st.unknown = Self::SCENE_FIGURES;
        Ok(st)
    }
}

impl PppmStats {
    /// What the passes of partial sums `p` did, with r_1 as given (the header's).
    pub fn of_partial(p: &Partial) -> PppmStats {
        let t = &p.tally;
        let last = p.ranges.last().map_or(0, |r| r.1.saturating_sub(1));
        PppmStats {
            passes: p.passes(),
            pass_ranges: p.ranges.clone(),
            alpha: p.header.alpha,
            initial_radius: p.header.initial_radius,
            initial_radius_source: "given".into(),
            final_radius: pass_radius2(p.header.initial_radius, p.header.alpha, last).sqrt(),
            photons_per_pass: p.header.photons_per_pass,
            photons_emitted: t.photons_emitted,
            photon_seconds: t.photon_seconds,
            camera_seconds: t.camera_seconds,
            partials: t.partials,
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::io::scene_json;
    use crate::render::aov::{Term, TermMask};
    use crate::render::settings::{RenderMode, RenderSettings};
    use crate::render::{RenderStats, Renderer};
    use crate::scene::{Scene, SceneDesc};

    fn scene(name: &str) -> Scene {
        let path = format!(
            "{}/tests/data/scenes/{name}.json",
            env!("CARGO_MANIFEST_DIR")
        );
        let mut desc: SceneDesc = scene_json::load(path).unwrap();
        desc.film.width = 10;
        desc.film.height = 8;
        Scene::build(&desc).unwrap()
    }

    fn small() -> RenderSettings {
        let mut s = RenderSettings {
            spp: 3,
            seed: 5,
            ..RenderSettings::default()
        };
        s.photons = 2_000;
        s.caustic_photons = 1_000;
        s.volume_photons = 1_000;
        s.final_gather_rays = 8;
        s
    }

    fn stats(scene: &Scene, s: RenderSettings) -> RenderStats {
        Renderer::new(scene).settings(s).render().unwrap().stats
    }

    fn reason(st: &RenderStats, t: Term) -> Option<&str> {
        st.skipped
            .iter()
            .find(|k| k.term == t.name())
            .map(|k| k.reason.as_str())
    }

    #[test]
    fn skipped_terms_name_what_the_scene_and_settings_rule_out() {
        let diffuse = scene("cornell_diffuse");
        for mode in [RenderMode::Jensen, RenderMode::Sppm] {
            let st = stats(&diffuse, RenderSettings { mode, ..small() });
            let caustic = reason(&st, Term::Caustic).unwrap_or_default();
            assert!(caustic.contains("no specular"), "{mode:?}: {caustic}");
            let volume = reason(&st, Term::Volume).unwrap_or_default();
            assert!(
                volume.contains("no participating media"),
                "{mode:?}: {volume}"
            );
            assert_eq!(reason(&st, Term::Direct), None);
            assert_eq!(reason(&st, Term::Indirect), None);
        }
        let mut s = small();
        s.terms = TermMask::ALL.without(Term::Direct);
        s.final_gather_rays = 0;
        let st = stats(&diffuse, s);
        assert_eq!(
            reason(&st, Term::Direct),
            Some("disabled in the render settings")
        );
        assert_eq!(
            reason(&st, Term::Indirect),
            Some("no global photon map (see photon_maps)")
        );
        // With glass and fog in the scene, nothing is skipped for want of them.
        let fog = stats(&scene("fog_glass"), small());
        assert_eq!(reason(&fog, Term::Caustic), None, "{:?}", fog.skipped);
        assert_eq!(reason(&fog, Term::Volume), None, "{:?}", fog.skipped);
    }

    /// A time budget of 0 is off in every mode (the flag's and the keyword's "0 = off"): the
    /// same image and passes as no budget.
    #[test]
    fn a_zero_time_budget_is_no_budget() {
        let sc = scene("cornell_spheres");
        for mode in [RenderMode::Jensen, RenderMode::Sppm, RenderMode::Pppm] {
            let render = |time_budget| {
                Renderer::new(&sc)
                    .settings(RenderSettings {
                        mode,
                        time_budget,
                        ..small()
                    })
                    .render()
                    .unwrap()
            };
            let (off, zero) = (render(None), render(Some(0.0)));
            assert!(zero.stats.time_budget.is_none(), "{mode:?}");
            assert_eq!(zero.stats.spp, off.stats.spp, "{mode:?}");
            assert_eq!(
                zero.film.combined().data,
                off.film.combined().data,
                "{mode:?}"
            );
        }
    }

    #[test]
    fn counts_follow_the_render_in_both_modes() {
        let sc = scene("cornell_spheres");
        for mode in [RenderMode::Jensen, RenderMode::Sppm] {
            let st = stats(&sc, RenderSettings { mode, ..small() });
            assert_eq!((st.width, st.height, st.spp), (10, 8, 3), "{mode:?}");
            // Jensen's camera pass adds adaptive sampling's rounds; the progressive one has none.
            let extra = st.adaptive.map_or(0, |a| a.extra_samples);
            assert_eq!(
                st.adaptive.is_some(),
                mode == RenderMode::Jensen,
                "{mode:?}"
            );
            assert_eq!(st.camera_rays, 10 * 8 * 3 + extra);
            assert_eq!(st.mode, mode);
            for m in st.photon_maps.iter().filter(|m| m.built) {
                assert_eq!(st.photons_stored.get(m.map), Some(&m.stored), "{}", m.map);
            }
            let photon_bytes: u64 = st.photon_maps.iter().map(|m| m.memory_bytes).sum();
            assert_eq!(
                st.memory_bytes,
                (10 * 8 * (Term::COUNT + 1) * 12) as u64 + st.triangles as u64 * 64 + photon_bytes
            );
            assert_eq!(
                st.sppm.as_ref().map(|p| p.passes),
                (mode == RenderMode::Sppm).then_some(3)
            );
            assert_eq!(st.irradiance_cache_records > 0, mode == RenderMode::Jensen);
            // The recorded options give back the settings, the engine's own aside.
            let again = RenderSettings::from_json(&st.options.to_string()).unwrap();
            assert_eq!(again.spp, 3);
            assert_eq!(again.options_json(), st.settings.options_json());
        }
    }
}
