//! The render settings: one struct, [`RenderSettings`], which is the schema users set and what
//! the engine reads. The `render` command's flags, the Python `render` keywords and the
//! Blender add-on's properties all come from its fields.
//!
//! Each schema field carries its documentation (the doc comment: the flag's help, the
//! keyword's and the property's description), its default (the clap attribute, which is also
//! what serde and Python fill in, and the `medium` preset's value), and its range, label, unit
//! and panel (the `schema` attribute). The internal fields are the engine's and the tests'
//! (the term mask, photon bounces, the block of pppm passes): no flag, keyword or property sets
//! them.
//!
//! A quality preset ([`RenderSettings::preset`], `presets.rs`) is a value of the struct. A
//! preset field (`preset: true`) that the user does not give takes the chosen preset's value;
//! every other field keeps its default. Adding a setting is one field here plus its use
//! (CONTRIBUTING.md, "Adding a setting").

use crate::error::{Error, Result};
use crate::render::aov::{AovRequest, TermMask};
use crate::render::film::Filter;
use clap::{Args, FromArgMatches};
use serde::{Deserialize, Serialize};

mod json;
mod presets;
mod schema;
mod sizes;
pub use presets::*;
pub use schema::*;
pub use sizes::*;

macro_rules! render_settings {
    (
        schema {$(
            $(#[doc = $doc:literal])+
            #[arg($($arg:tt)*)]
            #[schema($($key:ident: $value:expr),* $(,)?)]
            pub $name:ident: $ty:ty,
        )*}
        internal {$(
            $(#[doc = $idoc:literal])+
            #[arg($($iarg:tt)*)]
            pub $iname:ident: $ity:ty,
        )*}
    ) => {
        /// Everything a render is asked to do (see the module's documentation). The stats of
        /// a render record it (`settings`).
        #[derive(Args, Clone, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields, default)]
        pub struct RenderSettings {
            $(
                $(#[doc = $doc])+
                #[arg($($arg)*)]
                pub $name: $ty,
            )*
            $(
                $(#[doc = $idoc])+
                #[arg($($iarg)*)]
                #[serde(skip_deserializing)]
                pub $iname: $ity,
            )*
        }

        impl RenderSettings {
            /// Every setting of the schema, in the order of the fields.
            pub fn fields() -> Vec<Field> {
                vec![$(
                    Field {
                        name: stringify!($name),
                        doc: join_doc(&[$($doc),+]),
                        kind: <$ty as OptionValue>::kind(),
                        choices: <$ty as OptionValue>::choices(),
                        optional: <$ty as OptionValue>::OPTIONAL,
                        spec: Spec { $($key: $value,)* ..Spec::BASE },
                    },
                )*]
            }

            /// Each numeric setting's value, by name.
            fn numbers(&self) -> Vec<(&'static str, Option<f64>)> {
                vec![$((stringify!($name), OptionValue::number(&self.$name)),)*]
            }

            /// Sets the schema field `name` to `from`'s value.
            fn take(&mut self, from: &RenderSettings, name: &str) {
                match name {
                    $(stringify!($name) => self.$name = from.$name.clone(),)*
                    _ => unreachable!("`{name}` is a schema field"),
                }
            }
        }
    };
}

/// A doc comment's lines as one text: paragraphs kept, lines joined.
fn join_doc(lines: &[&str]) -> String {
    let mut out = String::new();
    for l in lines {
        let l = l.trim();
        if l.is_empty() {
            out.push_str("\n\n");
        } else {
            if !out.is_empty() && !out.ends_with('\n') {
                out.push(' ');
            }
            out.push_str(l);
        }
    }
    out.trim().to_string()
}

render_settings! {
    schema {
    /// Quality preset: draft, medium, high or final. It sets the samples, photon counts and
    /// final gathering that are not given.
    #[arg(long, value_enum, default_value_t = Quality::Medium)]
    #[schema(label: "Quality")]
    pub quality: Quality,
    /// Render mode: `jensen` (photon maps built once, final gathering, irradiance cache),
    /// `sppm` (stochastic progressive photon mapping: `spp` passes, each with a fresh map of
    /// `photons` stored photons and a shrinking search radius per pixel; consistent) or
    /// `pppm` (probabilistic progressive photon mapping: `spp` independent passes with a
    /// global radius shrinking with the pass index; consistent, and its passes can be
    /// rendered in blocks on several machines and merged to the same image).
    #[arg(long, value_enum, default_value_t = RenderMode::Jensen)]
    #[schema(label: "Mode")]
    pub mode: RenderMode,
    /// Progressive modes' radius reduction α in (0, 1): in sppm the fraction of each pass's
    /// photons a pixel keeps (Hachisuka & Jensen 2009); in pppm pass i's radius² is
    /// r_1² i^(α-1) (Knaus & Zwicker 2011).
    #[arg(long, default_value_t = SPPM_ALPHA)]
    #[schema(label: "Alpha", min: Some(0.0), min_open: true, max: Some(1.0), max_open: true,
             modes: PROGRESSIVE)]
    pub alpha: f32,
    /// Progressive modes: photons within the first search radius (sppm: the k nearest around
    /// each pixel's first visible point; pppm: the median of that distance over the image);
    /// the radius shrinks from there.
    #[arg(long, default_value_t = SPPM_INITIAL_PHOTONS)]
    #[schema(label: "Initial Photons", min: Some(1.0), modes: PROGRESSIVE)]
    pub initial_photons: usize,
    /// pppm: the first pass's search radius r_1, in scene units (default: computed from the
    /// first pass's photons, see initial_photons; the stats record it under pppm).
    #[arg(long)]
    #[schema(label: "Initial Radius", min: Some(0.0), min_open: true, unit: Some("distance"),
             modes: &[RenderMode::Pppm])]
    pub initial_radius: Option<f32>,
    /// Camera samples per pixel (default: the preset's).
    #[arg(long, default_value_t = 32)]
    #[schema(label: "Samples", min: Some(1.0), soft_max: Some(4096.0), preset: true)]
    pub spp: u32,
    /// Adaptive sampling, on or off: after `spp` samples, pixels whose neighbours are noisier
    /// than `noise_threshold` take more, in rounds of `spp`, up to `max_spp` (default: the
    /// preset's, on).
    #[arg(long, value_name = "on|off", value_parser = parse_on_off, default_value_t = true, action = clap::ArgAction::Set)]
    #[schema(label: "Adaptive Sampling", preset: true)]
    pub adaptive_sampling: bool,
    /// Adaptive sampling's noise threshold: standard error over the square root of the mean
    /// times the image's brightness. Smaller is less noisy and slower (default: the preset's).
    #[arg(long, default_value_t = 0.2)]
    #[schema(label: "Noise Threshold", min: Some(0.0), min_open: true, soft_max: Some(1.0),
             preset: true, requires: Some("adaptive_sampling"))]
    pub noise_threshold: f32,
    /// Adaptive sampling: the most camera samples a pixel takes, in whole rounds of `spp`
    /// (default: the preset's, 16 x its `spp`).
    #[arg(long, default_value_t = 512)]
    #[schema(label: "Max Samples", min: Some(1.0), soft_max: Some(16384.0), preset: true,
             requires: Some("adaptive_sampling"))]
    pub max_spp: u32,
    /// Seconds the whole render should take (photon pass, irradiance cache, camera pass);
    /// photon counts and camera passes are planned to fill it, and the plan is written to the
    /// stats (`time_budget`). 0 = off.
    #[arg(long, value_name = "SECONDS", value_parser = parse_time_budget)]
    #[schema(label: "Time Budget", min: Some(0.0), unit: Some("seconds"))]
    pub time_budget: Option<f64>,
    /// Largest memory the photon maps and the BVH may take, in bytes or with a binary suffix
    /// (`512M`, `8G`); checked against an estimate before the photon pass (default: the
    /// available memory, MemAvailable in /proc/meminfo; no limit where that cannot be read).
    #[arg(long, value_name = "BYTES_OR_SIZE", value_parser = parse_bytes_arg)]
    #[schema(label: "Memory Limit")]
    pub memory_limit: Option<Bytes>,
    /// Pixel reconstruction filter: box, tent or gaussian.
    #[arg(long, value_enum, default_value_t = FilterName::Gaussian)]
    #[schema(label: "Pixel Filter")]
    pub filter: FilterName,
    /// Jensen mode: take the camera samples in whole passes over the image (as a time budget
    /// does), to replay a budgeted render's recorded plan.
    #[arg(long)]
    #[schema(label: "Whole Passes", modes: &[RenderMode::Jensen])]
    pub progressive: bool,
    /// Random seed; the same seed gives the same image for any thread count.
    #[arg(long, default_value_t = 0)]
    #[schema(label: "Seed")]
    pub seed: u64,
    /// Worker threads (0 = all cores).
    #[arg(long, default_value_t = 0)]
    #[schema(label: "Threads")]
    pub threads: usize,
    /// Photons to store in the global map (default: the preset's).
    #[arg(long, default_value_t = 100_000)]
    #[schema(label: "Photons", group: Group::Photons, min: Some(0.0), preset: true)]
    pub photons: usize,
    /// Photons to store in the caustic map (default: the preset's).
    #[arg(long, default_value_t = 50_000)]
    #[schema(label: "Caustic Photons", group: Group::Photons, min: Some(0.0), preset: true)]
    pub caustic_photons: usize,
    /// Photons to store in the volume map, for scenes with participating media (default: the
    /// preset's).
    #[arg(long, default_value_t = 50_000)]
    #[schema(label: "Volume Photons", group: Group::Photons, min: Some(0.0), preset: true)]
    pub volume_photons: usize,
    /// Ray-marching step through media, in scene units (default: from the scene size).
    #[arg(long)]
    #[schema(label: "Volume Step", group: Group::Photons, min: Some(0.0), min_open: true,
             unit: Some("distance"))]
    pub volume_step: Option<f32>,
    /// Photons per radiance estimate (k nearest).
    #[arg(long, default_value_t = 50)]
    #[schema(label: "Gather", group: Group::Photons, min: Some(1.0), preset: true)]
    pub gather: usize,
    /// Largest photon search radius, in scene units (default: from the scene size).
    #[arg(long)]
    #[schema(label: "Radius", group: Group::Photons, min: Some(0.0), min_open: true,
             unit: Some("distance"), preset: true)]
    pub radius: Option<f32>,
    /// Photon power encoding: rgbe (20-byte photons, Ward's shared exponent) or f32 (28
    /// bytes, unquantised).
    #[arg(long, value_enum, default_value_t = PhotonPower::Rgbe)]
    #[schema(label: "Photon Power", group: Group::Photons)]
    pub photon_power: PhotonPower,
    /// Final-gathering rays per irradiance-cache record, and per pixel elsewhere (default:
    /// the preset's).
    #[arg(long, default_value_t = 128)]
    #[schema(label: "Final Gather Rays", group: Group::Gathering, min: Some(0.0), preset: true)]
    pub final_gather_rays: u32,
    /// Irradiance caching for final gathering (Ward's cache): on or off (default: the
    /// preset's).
    #[arg(long, value_name = "on|off", value_parser = parse_on_off, default_value_t = true, action = clap::ArgAction::Set)]
    #[schema(label: "Irradiance Cache", group: Group::Gathering, preset: true)]
    pub irradiance_cache: bool,
    /// Irradiance-cache error tolerance (Ward's a; smaller is more accurate and slower;
    /// default: the preset's).
    #[arg(long, default_value_t = 0.1)]
    #[schema(label: "Cache Tolerance", group: Group::Gathering, min: Some(0.0), min_open: true,
             soft_max: Some(1.0), preset: true, requires: Some("irradiance_cache"))]
    pub cache_tolerance: f32,
    /// Final-gathering rays per camera sample where the irradiance cache does not apply
    /// (default: final_gather_rays / spp, at least 4).
    #[arg(long)]
    #[schema(label: "Gather Rays per Sample", group: Group::Gathering, min: Some(1.0))]
    pub gather_rays_per_sample: Option<u32>,
    /// Specular and rough-glass bounces followed from the eye at most (Russian roulette ends
    /// most chains earlier; light trapped in rough glass needs dozens).
    #[arg(long, default_value_t = MAX_SPECULAR_DEPTH)]
    #[schema(label: "Max Specular Depth", group: Group::Gathering, min: Some(0.0),
             soft_max: Some(128.0), preset: true)]
    pub max_specular_depth: u32,
    /// Jensen mode: save the photon maps and the irradiance cache to this file (a versioned,
    /// checksummed file keyed by the scene without its camera, the photon settings and the
    /// seed), to render other views of the scene from them.
    #[arg(long, value_name = "FILE")]
    #[schema(label: "Save Photon Maps", group: Group::Photons, modes: &[RenderMode::Jensen])]
    pub save_photon_maps: Option<std::path::PathBuf>,
    /// Jensen mode: load the photon maps and the irradiance cache from this file instead of
    /// building them (the cache is extended for this view). A file of another scene (the
    /// camera aside), other photon settings, seed or version is an error, or rebuilt (see
    /// photon_maps_mismatch).
    #[arg(long, value_name = "FILE")]
    #[schema(label: "Load Photon Maps", group: Group::Photons, modes: &[RenderMode::Jensen])]
    pub load_photon_maps: Option<std::path::PathBuf>,
    /// Jensen mode: what a photon-map file that does not match the render (or cannot be
    /// read) does: error, or rebuild (build the maps, and save them where save_photon_maps
    /// says: with both set to one file, frames build it once and load it after).
    #[arg(long, value_enum, default_value_t = OnMismatch::Error)]
    #[schema(label: "On Mismatch", group: Group::Photons, modes: &[RenderMode::Jensen])]
    pub photon_maps_mismatch: OnMismatch,
    /// Write the denoising guides: `albedo` (the reflectance of the first non-specular
    /// surface, seen through perfect mirrors and glass) and `normal` (its normal, in camera
    /// space), as Open Image Denoise and Blender's Denoise node expect them.
    #[arg(long)]
    #[schema(label: "Denoising Data", group: Group::Passes)]
    pub denoising_data: bool,
    /// Denoise with Open Image Denoise (the Python package with its `denoise` extra: pip
    /// install photonmap[denoise]), guided by `albedo` and `normal`: each noisy term on its
    /// own, the beauty their sum; the noisy terms are kept as `<term>_noisy`.
    #[arg(long)]
    #[schema(label: "Denoise", group: Group::Passes)]
    pub denoise: bool,
    /// Cryptomatte mattes to write: off, object, material or both (`CryptoObject00`, ...,
    /// with the manifest in the EXR metadata).
    #[arg(long, value_enum, default_value_t = Cryptomatte::Off)]
    #[schema(label: "Cryptomatte", group: Group::Passes)]
    pub cryptomatte: Cryptomatte,
    /// Cryptomatte ranks per pixel: the most objects (or materials) a pixel's matte tells
    /// apart; two per layer.
    #[arg(long, default_value_t = CRYPTOMATTE_LEVELS)]
    #[schema(label: "Cryptomatte Levels", group: Group::Passes, min: Some(1.0),
             max: Some(16.0))]
    pub cryptomatte_levels: u32,
    }
    internal {
        /// The terms rendered (all but in comparisons of single terms).
        #[arg(skip = TermMask::ALL)]
        pub terms: TermMask,
        /// Largest number of bounces a photon makes (Russian roulette ends most paths
        /// earlier).
        #[arg(skip = 64u32)]
        pub max_bounces: u32,
        /// Photons emitted at most per stored photon requested, so that a scene that stores
        /// nothing still ends.
        #[arg(skip = 20usize)]
        pub max_emitted_factor: usize,
        /// Precompute the volume map's radiance at every fourth photon for isotropic media
        /// (`photon::volume_points`) and read it in the march; off, every march step runs the
        /// k-nearest estimate (for comparisons).
        #[arg(skip = true)]
        pub volume_points: bool,
        /// pppm: render only passes `[first, end)` (a block of a render split into several;
        /// the command's `--pass-range`).
        #[arg(skip)]
        pub pass_range: Option<(u32, u32)>,
    }
}

/// The progressive modes.
const PROGRESSIVE: &[RenderMode] = &[RenderMode::Sppm, RenderMode::Pppm];

/// The `medium` preset: the fields' defaults, the values the flags, the keywords and the
/// properties start at.
impl Default for RenderSettings {
    fn default() -> Self {
        let cmd =
            RenderSettings::augment_args(clap::Command::new("photonmap").no_binary_name(true));
        let m = cmd
            .try_get_matches_from(Vec::<String>::new())
            .unwrap_or_else(|e| unreachable!("the defaults parse: {e}"));
        RenderSettings::from_arg_matches(&m).unwrap_or_else(|e| unreachable!("{e}"))
    }
}

impl RenderSettings {
    /// The preset fields that were not `given` take the value of the `quality` preset.
    pub fn apply_preset(&mut self, given: impl Fn(&str) -> bool) {
        let preset = RenderSettings::preset(self.quality);
        for f in Self::fields() {
            if f.spec.preset && !given(f.name) {
                self.take(&preset, f.name);
            }
        }
    }
}

/// What the engine reads of the settings, as its own types.
impl RenderSettings {
    /// The pixel reconstruction filter.
    pub fn pixel_filter(&self) -> Filter {
        self.filter.filter()
    }

    /// The memory limit in bytes: the one given, or the available memory (MemAvailable);
    /// `None` where neither is known.
    pub fn memory_limit_bytes(&self) -> Option<u64> {
        self.memory_limit.map(|b| b.0).or_else(available_memory)
    }

    /// The time budget in seconds, `None` when off (not given, or 0).
    pub fn budget_seconds(&self) -> Option<f64> {
        self.time_budget.filter(|b| *b > 0.0)
    }

    /// Photon power as `f32` (28-byte photons) rather than RGBE (20 bytes).
    pub fn f32_power(&self) -> bool {
        self.photon_power == PhotonPower::F32
    }

    /// Bytes per stored photon: [`BYTES_PER_PHOTON`] or [`BYTES_PER_PHOTON_F32`].
    pub fn bytes_per_photon(&self) -> u64 {
        if self.f32_power() {
            BYTES_PER_PHOTON_F32
        } else {
            BYTES_PER_PHOTON
        }
    }

    /// Where photon maps are saved and loaded (an empty path is none).
    pub fn photon_map_files(&self) -> MapFiles {
        let path = |p: &Option<std::path::PathBuf>| p.clone().filter(|p| !p.as_os_str().is_empty());
        MapFiles {
            save: path(&self.save_photon_maps),
            load: path(&self.load_photon_maps),
            on_mismatch: self.photon_maps_mismatch,
        }
    }

    /// The optional AOVs asked for.
    pub fn aovs(&self) -> AovRequest {
        AovRequest {
            denoising_data: self.denoising_data,
            denoise: self.denoise,
            cryptomatte: self.cryptomatte,
            cryptomatte_levels: self.cryptomatte_levels,
        }
    }
}

#[cfg(test)]
mod tests;
