//! Render settings and the quality presets shared by the CLI, the Python API and Blender.

use super::aov::{AovRequest, TermMask};
use super::film::Filter;
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

    /// Camera samples per pixel.
    pub fn spp(self) -> u32 {
        match self {
            Quality::Draft => 8,
            Quality::Medium => 32,
            Quality::High => 128,
            Quality::Final => 384,
        }
    }

    /// Photon-map parameters of the preset.
    ///
    /// Calibrated with `photonmap trade` on `tests/data/scenes/cornell_spheres.json` against
    /// Mitsuba's reference (BENCHMARKS.md, "Speed and accuracy"): around the former presets,
    /// camera samples and a tighter irradiance cache bought the most error per second, while
    /// photons beyond ~10^5, gather k above 50 and more than 256 final-gathering rays bought
    /// almost none; each preset below has less error than the former one of about its time.
    /// On Blender-made rooms (the parity corpus) `high` and `final` carry more global photons
    /// than that calibration asked for: their noise is low enough to show the density
    /// estimate's bias in concave corners, which shrinks with the search radius. At 300,000
    /// the floor by a cube's foot was 6% dark per 8x8 block at `high` (beyond the corpus's
    /// tolerance), at 1,000,000 under 3%, for about 15% more time (BENCHMARKS.md, "Corner
    /// bias and the presets' photons").
    pub fn photons(self) -> PhotonSettings {
        let (global, caustic, fg_rays, tolerance) = match self {
            Quality::Draft => (50_000, 20_000, 64, 0.15),
            Quality::Medium => (100_000, 50_000, 128, 0.1),
            Quality::High => (1_000_000, 150_000, 256, 0.07),
            Quality::Final => (2_000_000, 250_000, 512, 0.05),
        };
        PhotonSettings {
            global,
            caustic,
            volume: caustic,
            volume_step: None,
            gather: 50,
            radius: None,
            final_gather_rays: fg_rays,
            irradiance_cache: true,
            cache_tolerance: tolerance,
            max_bounces: 64,
            max_emitted_factor: 20,
            volume_points: true,
            f32_power: false,
        }
    }

    /// Adaptive sampling: the noise threshold and the most samples a pixel takes
    /// (`render::adaptive`). The threshold follows the first round's noise, which falls as
    /// 1/sqrt(spp): 0.1 at `high`'s 128 samples, and 16 times the samples at most. Measured on
    /// the parity corpus' glass sphere under an area light through USD (BENCHMARKS.md,
    /// "Adaptive sampling"): 3-4x less squared error per second at every preset, where
    /// 1% of the pixels (the light's image through the glass) held 80% of it.
    pub fn adaptive(self) -> (f32, u32) {
        match self {
            Quality::Draft => (0.4, 128),
            Quality::Medium => (0.2, 512),
            Quality::High => (0.1, 2048),
            Quality::Final => (0.06, 6144),
        }
    }

    /// The full settings of the preset.
    pub fn settings(self) -> RenderSettings {
        let (noise_threshold, max_spp) = self.adaptive();
        RenderSettings {
            spp: self.spp(),
            adaptive_sampling: true,
            noise_threshold,
            max_spp,
            seed: 0,
            threads: 0,
            max_specular_depth: MAX_SPECULAR_DEPTH,
            filter: Filter::gaussian(0.5),
            terms: TermMask::ALL,
            photons: self.photons(),
            memory_limit: None,
            time_budget: None,
            progressive: false,
            gather_rays_per_sample: None,
            mode: RenderMode::Jensen,
            alpha: SPPM_ALPHA,
            initial_photons: SPPM_INITIAL_PHOTONS,
            initial_radius: None,
            pass_range: None,
            photon_map_files: Default::default(),
            aovs: AovRequest {
                cryptomatte_levels: CRYPTOMATTE_LEVELS,
                ..AovRequest::default()
            },
        }
    }
}

/// Photon-map parameters (Jensen 2001, chapters 6-9).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PhotonSettings {
    /// Photons to store in the global map (Jensen shoots until this many are stored).
    pub global: usize,
    /// Photons to store in the caustic map.
    pub caustic: usize,
    /// Photons to store in the volume map (scenes with participating media).
    pub volume: usize,
    /// Ray-marching step in scene units; `None` derives it from the scene size.
    pub volume_step: Option<f32>,
    /// Photons in each radiance estimate (k nearest).
    pub gather: usize,
    /// Largest search radius in scene units; `None` derives it from the scene size.
    pub radius: Option<f32>,
    /// Final-gathering rays per pixel: each irradiance-cache record gathers this many; a
    /// point gathered without the cache uses this many divided among the pixel's samples.
    pub final_gather_rays: u32,
    /// Ward's irradiance cache for final gathering.
    pub irradiance_cache: bool,
    /// Irradiance-cache error tolerance (Ward's a).
    pub cache_tolerance: f32,
    /// Largest number of bounces a photon makes (Russian roulette ends most paths earlier).
    pub max_bounces: u32,
    /// Photons emitted at most per stored photon requested, so that a scene that stores
    /// nothing still ends.
    pub max_emitted_factor: usize,
    /// Precompute the volume map's radiance at every fourth photon for isotropic media
    /// (`photon::volume_points`) and read it in the march; off, every march step runs the
    /// k-nearest estimate (for comparisons).
    pub volume_points: bool,
    /// Store photon power as `f32` (28-byte `photon::PhotonF32`) instead of Ward's RGBE
    /// (20-byte `photon::Photon`, the default): 40% more memory, no power quantisation.
    pub f32_power: bool,
}

impl PhotonSettings {
    /// Bytes per stored photon of these settings: [`BYTES_PER_PHOTON`] or
    /// [`BYTES_PER_PHOTON_F32`].
    pub fn bytes_per_photon(&self) -> u64 {
        if self.f32_power {
            BYTES_PER_PHOTON_F32
        } else {
            BYTES_PER_PHOTON
        }
    }

    /// The photon power encoding by name: `rgbe` or `f32`.
    pub fn photon_power(&self) -> &'static str {
        if self.f32_power {
            "f32"
        } else {
            "rgbe"
        }
    }
}

/// The `medium` preset's photon settings: a `Renderer` without settings renders as the CLI,
/// Python and Blender do at their default quality.
impl Default for PhotonSettings {
    fn default() -> Self {
        Quality::Medium.photons()
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

/// Everything a render is asked to do. The stats of a render record it (`settings`).
#[derive(Clone, Debug, Serialize)]
pub struct RenderSettings {
    pub spp: u32,
    /// Adaptive sampling (`render::adaptive`).
    pub adaptive_sampling: bool,
    /// Adaptive sampling's noise threshold.
    pub noise_threshold: f32,
    /// The most camera samples a pixel takes with adaptive sampling, in whole rounds of
    /// `spp`; at most `spp` = off.
    pub max_spp: u32,
    pub seed: u64,
    /// 0 = all cores.
    pub threads: usize,
    /// Specular and rough-glass bounces an eye path follows at most.
    pub max_specular_depth: u32,
    pub filter: Filter,
    pub terms: TermMask,
    pub photons: PhotonSettings,
    /// Largest number of bytes the photon maps and the BVH may take, checked against an
    /// estimate before anything is allocated; `None` = no limit.
    pub memory_limit: Option<u64>,
    /// Seconds the whole render (photon pass, irradiance cache, camera pass) should take;
    /// the renderer plans photon counts and camera passes to fill it (see `budget`).
    /// `None` = off: the counts and `spp` are used as given.
    pub time_budget: Option<f64>,
    /// Camera pass in `spp` whole passes over the image, one sample per pixel each, placed on
    /// the Sobol (0,2)-sequence; the image after `k` passes does not depend on how many
    /// follow. Budgeted renders always use it; set it with the recorded plan to reproduce one.
    pub progressive: bool,
    /// Final-gathering rays per camera sample where the cache is not used; `None` derives
    /// it from `final_gather_rays / spp` (at least 4).
    pub gather_rays_per_sample: Option<u32>,
    /// Jensen's two passes or progressive photon mapping.
    pub mode: RenderMode,
    /// Progressive photon mapping's α in (0, 1): the fraction of each pass's photons kept
    /// when a pixel's radius shrinks.
    pub alpha: f32,
    /// Progressive photon mapping: a pixel's first radius reaches this many photons (k
    /// nearest around its first visible point).
    pub initial_photons: usize,
    /// pppm: the first pass's radius r_1; `None` computes it (`render::pppm`).
    pub initial_radius: Option<f32>,
    /// pppm: render only passes `[first, end)` (a block of a render split into several).
    pub pass_range: Option<(u32, u32)>,
    /// Jensen's mode: photon maps saved to and loaded from files (`render::map_file`).
    pub photon_map_files: super::map_file::MapFiles,
    /// The optional AOVs: denoising guides, noisy terms, Cryptomatte (`aov::AovRequest`).
    pub aovs: AovRequest,
}

/// The `medium` preset.
impl Default for RenderSettings {
    fn default() -> Self {
        Quality::Medium.settings()
    }
}

/// Bytes per stored photon: the 20-byte photon of `photon::Photon` (RGBE power, position,
/// quantised direction, split-axis flag).
pub const BYTES_PER_PHOTON: u64 = 20;

/// Bytes per stored photon with `PhotonSettings::f32_power`: the 28-byte `photon::PhotonF32`
/// (the same record with the power as three `f32`).
pub const BYTES_PER_PHOTON_F32: u64 = 28;

/// Bytes per triangle of the BVH in the memory estimate. The 4-wide BVH takes 128 bytes per
/// node plus a 4-byte index per triangle, and the leaf-ordered triangle copy 36 bytes per
/// triangle: about 24 + 36 = 60 bytes per triangle with leaves of three triangles on
/// average (the BVH bench's 808,200-triangle sphere: 127,006 nodes, 19.5 MB, and 29.1 MB of
/// triangles); the 68 bytes counted leave room for smaller leaves.
pub const BYTES_PER_TRIANGLE: u64 = 2 * 32 + 4;

/// Available memory: `MemAvailable` of `/proc/meminfo`, in bytes; `None` where it cannot be
/// read (other systems), which means no limit.
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let mut parts = line["MemAvailable:".len()..].split_whitespace();
    let value: u64 = parts.next()?.parse().ok()?;
    match parts.next() {
        Some("kB") => value.checked_mul(1024),
        None => Some(value),
        Some(_) => None,
    }
}

/// Parses a byte count: a plain integer, or one with a binary suffix `K`, `M`, `G`, `T`
/// (optionally followed by `B` or `iB`, any case): `8G` = 8 * 2^30, `512M` = 512 * 2^20.
pub fn parse_bytes(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let digits = t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len());
    let (num, suffix) = t.split_at(digits);
    let bad = || format!("`{s}` is not a size in bytes (expected e.g. 1000000, 512M or 8G)");
    let n: u64 = num.parse().map_err(|_| bad())?;
    let unit = suffix.trim().to_ascii_lowercase();
    let shift = match unit.trim_end_matches("ib").trim_end_matches('b') {
        "" => 0,
        "k" => 10,
        "m" => 20,
        "g" => 30,
        "t" => 40,
        _ => return Err(bad()),
    };
    if unit == "ib" {
        return Err(bad());
    }
    n.checked_mul(1u64 << shift).ok_or_else(bad)
}
