//! The options and the engine's settings (`RenderSettings`), each way: the settings the
//! renderer uses from the options given, the options that give a render's settings, and a
//! quality preset's options.

use super::*;
use crate::render::aov::AovRequest;

impl RenderOptions {
    /// The options of a quality preset: `quality` and every preset field set to its value.
    pub fn preset(quality: Quality) -> RenderOptions {
        let s = quality.settings();
        let p = &s.photons;
        RenderOptions {
            quality,
            spp: Some(s.spp),
            adaptive_sampling: Some(s.adaptive_sampling),
            noise_threshold: Some(s.noise_threshold),
            max_spp: Some(s.max_spp),
            photons: Some(p.global),
            caustic_photons: Some(p.caustic),
            volume_photons: Some(p.volume),
            gather: Some(p.gather),
            radius: p.radius,
            final_gather_rays: Some(p.final_gather_rays),
            irradiance_cache: Some(p.irradiance_cache),
            cache_tolerance: Some(p.cache_tolerance),
            max_specular_depth: s.max_specular_depth,
            ..RenderOptions::default()
        }
    }

    /// The options that give `s`: every field explicit. A filter is named by its kind (the
    /// front ends have only the named widths); the term mask has no option.
    pub fn from_settings(s: &RenderSettings) -> RenderOptions {
        let p = &s.photons;
        RenderOptions {
            quality: Quality::Medium,
            mode: s.mode,
            alpha: s.alpha,
            initial_photons: s.initial_photons,
            spp: Some(s.spp),
            adaptive_sampling: Some(s.adaptive_sampling),
            noise_threshold: Some(s.noise_threshold),
            max_spp: Some(s.max_spp),
            time_budget: s.time_budget,
            memory_limit: s.memory_limit.map(Bytes),
            filter: match s.filter {
                Filter::Box => FilterName::Box,
                Filter::Tent { .. } => FilterName::Tent,
                Filter::Gaussian { .. } => FilterName::Gaussian,
            },
            progressive: s.progressive,
            seed: s.seed,
            threads: s.threads,
            photons: Some(p.global),
            caustic_photons: Some(p.caustic),
            volume_photons: Some(p.volume),
            volume_step: p.volume_step,
            gather: Some(p.gather),
            radius: p.radius,
            photon_power: if p.f32_power {
                PhotonPower::F32
            } else {
                PhotonPower::Rgbe
            },
            final_gather_rays: Some(p.final_gather_rays),
            irradiance_cache: Some(p.irradiance_cache),
            cache_tolerance: Some(p.cache_tolerance),
            gather_rays_per_sample: s.gather_rays_per_sample,
            max_specular_depth: s.max_specular_depth,
            initial_radius: s.initial_radius,
            save_photon_maps: s.photon_map_files.save.clone(),
            load_photon_maps: s.photon_map_files.load.clone(),
            photon_maps_mismatch: s.photon_map_files.on_mismatch,
            denoising_data: s.aovs.denoising_data,
            denoise: s.aovs.denoise,
            cryptomatte: s.aovs.cryptomatte,
            cryptomatte_levels: s.aovs.cryptomatte_levels,
        }
    }

    /// The settings the renderer uses: the preset, with every given option over it.
    pub fn settings(&self) -> RenderSettings {
        let mut s = self.quality.settings();
        s.spp = self.spp.unwrap_or(s.spp);
        s.adaptive_sampling = self.adaptive_sampling.unwrap_or(s.adaptive_sampling);
        s.noise_threshold = self.noise_threshold.unwrap_or(s.noise_threshold);
        s.max_spp = self.max_spp.unwrap_or(s.max_spp);
        s.seed = self.seed;
        s.threads = self.threads;
        s.max_specular_depth = self.max_specular_depth;
        s.filter = self.filter.filter();
        let p = &mut s.photons;
        p.global = self.photons.unwrap_or(p.global);
        p.caustic = self.caustic_photons.unwrap_or(p.caustic);
        p.volume = self.volume_photons.unwrap_or(p.volume);
        p.volume_step = self.volume_step.or(p.volume_step);
        p.gather = self.gather.unwrap_or(p.gather);
        p.radius = self.radius.or(p.radius);
        p.final_gather_rays = self.final_gather_rays.unwrap_or(p.final_gather_rays);
        p.irradiance_cache = self.irradiance_cache.unwrap_or(p.irradiance_cache);
        p.cache_tolerance = self.cache_tolerance.unwrap_or(p.cache_tolerance);
        p.f32_power = self.photon_power == PhotonPower::F32;
        s.memory_limit = self.memory_limit.map(|b| b.0).or_else(available_memory);
        s.time_budget = self.time_budget.filter(|b| *b > 0.0);
        s.mode = self.mode;
        s.alpha = self.alpha;
        s.initial_photons = self.initial_photons;
        s.progressive = self.progressive;
        s.gather_rays_per_sample = self.gather_rays_per_sample;
        s.initial_radius = self.initial_radius;
        s.photon_map_files = crate::render::map_file::MapFiles {
            save: self
                .save_photon_maps
                .clone()
                .filter(|p| !p.as_os_str().is_empty()),
            load: self
                .load_photon_maps
                .clone()
                .filter(|p| !p.as_os_str().is_empty()),
            on_mismatch: self.photon_maps_mismatch,
        };
        s.aovs = AovRequest {
            denoising_data: self.denoising_data,
            denoise: self.denoise,
            cryptomatte: self.cryptomatte,
            cryptomatte_levels: self.cryptomatte_levels,
        };
        s
    }
}
