//! The quality presets, written once as values of [`RenderSettings`], the render modes and
//! the settings' constants.

use super::RenderSettings;
use serde::{Deserialize, Serialize};

/// Quality presets. Each maps to camera samples and photon-map parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Quality {
    /// Draft: the fastest, for previews and look development.
    Draft,
    /// Medium: the default.
    Medium,
    /// High: less noise, for reviews.
    High,
    /// Final: the least noise, for final frames.
    Final,
}

impl Quality {
    pub const ALL: [Quality; 4] = [
        Quality::Draft,
        Quality::Medium,
        Quality::High,
        Quality::Final,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Quality::Draft => "draft",
            Quality::Medium => "medium",
            Quality::High => "high",
            Quality::Final => "final",
        }
    }

    pub fn parse(s: &str) -> Option<Quality> {
        Self::ALL.into_iter().find(|q| q.name() == s)
    }
}

impl RenderSettings {
    /// The settings of a quality preset. `medium` is the fields' defaults; the others change
    /// the preset fields (`#[schema(preset: true)]`) and nothing else (a test checks it).
    ///
    /// The photon-map parameters were calibrated with `photonmap trade` on
    /// `tests/data/scenes/cornell_spheres.json` against Mitsuba's reference (BENCHMARKS.md,
    /// "Speed and accuracy"): camera samples and a tighter irradiance cache bought the most
    /// error per second, while photons beyond ~10^5, gather k above 50 and more than 256
    /// final-gathering rays bought almost none. On Blender-made rooms (the parity corpus)
    /// `high` and `final` carry more global photons than that calibration asked for: their
    /// noise is low enough to show the density estimate's bias in concave corners, which
    /// shrinks with the search radius. At 300,000 the floor by a cube's foot was 6% dark per
    /// 8x8 block at `high` (beyond the corpus's tolerance), at 1,000,000 under 3%, for about
    /// 15% more time (BENCHMARKS.md, "Corner bias and the presets' photons").
    ///
    /// Adaptive sampling's threshold follows the first round's noise, which falls as
    /// 1/sqrt(spp): 0.1 at `high`'s 128 samples, and 16 times the samples at most. Measured on
    /// the parity corpus' glass sphere under an area light through USD (BENCHMARKS.md,
    /// "Adaptive sampling"): 3-4x less squared error per second at every preset, where 1% of
    /// the pixels (the light's image through the glass) held 80% of it.
    pub fn preset(quality: Quality) -> RenderSettings {
        let medium = RenderSettings::default();
        match quality {
            Quality::Medium => medium,
            Quality::Draft => RenderSettings {
                quality,
                spp: 8,
                noise_threshold: 0.4,
                max_spp: 128,
                photons: 50_000,
                caustic_photons: 20_000,
                volume_photons: 20_000,
                final_gather_rays: 64,
                cache_tolerance: 0.15,
                ..medium
            },
            Quality::High => RenderSettings {
                quality,
                spp: 128,
                noise_threshold: 0.1,
                max_spp: 2048,
                photons: 1_000_000,
                caustic_photons: 150_000,
                volume_photons: 150_000,
                final_gather_rays: 256,
                cache_tolerance: 0.07,
                ..medium
            },
            Quality::Final => RenderSettings {
                quality,
                spp: 384,
                noise_threshold: 0.06,
                max_spp: 6144,
                photons: 2_000_000,
                caustic_photons: 250_000,
                volume_photons: 250_000,
                final_gather_rays: 512,
                cache_tolerance: 0.05,
                ..medium
            },
        }
    }
}

/// How the photon terms are estimated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum RenderMode {
    /// Jensen: photon maps built once; caustics from the caustic map, indirect light by final
    /// gathering with the irradiance cache.
    #[default]
    Jensen,
    /// Progressive: stochastic progressive photon mapping (Hachisuka & Jensen 2009); `spp`
    /// passes, each with a fresh map of `photons` stored photons and a shrinking search radius
    /// per pixel, converging to the exact image as passes grow.
    Sppm,
    /// Progressive (farm): probabilistic progressive photon mapping (Knaus & Zwicker 2011);
    /// `spp` independent passes, each with a fresh map and a global radius that depends on
    /// the pass index only, summed so that blocks of passes rendered anywhere merge to the
    /// same image.
    Pppm,
}

impl RenderMode {
    /// The modes of progressive photon mapping (a fresh photon map per pass).
    pub fn is_progressive(self) -> bool {
        matches!(self, RenderMode::Sppm | RenderMode::Pppm)
    }
}

/// Default fraction of the new photons a progressive pass keeps (Hachisuka & Jensen 2009, α).
pub const SPPM_ALPHA: f32 = 0.7;

/// Default photons within a pixel's first progressive radius. Fewer than Jensen's `gather`:
/// the radius shrinks from there, and a small start keeps the early bias (light spread across
/// caustic edges and contact shadows) low; measured on the caustic reference scene, 20 gave
/// 35% less error than 100 at equal time.
pub const SPPM_INITIAL_PHOTONS: usize = 20;

/// Specular and rough-glass bounces an eye path follows at most, by default (every preset).
pub const MAX_SPECULAR_DEPTH: u32 = 64;

/// Cryptomatte ranks per pixel by default: the specification's suggested 6 (three layers).
pub const CRYPTOMATTE_LEVELS: u32 = 6;
