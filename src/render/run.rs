//! A render from start to end: the settings checked, the memory estimated against the limit,
//! the thread pool made, and the mode's pipeline run in it.

use super::compositing::AovLayout;
use super::memory::MemoryEstimate;
use super::output::RenderOutput;
use super::renderer::Renderer;
use super::settings::{RenderMode, BYTES_PER_TRIANGLE};
use crate::error::{Error, Result};
use std::time::Instant;

impl Renderer<'_> {
    /// Renders: the mode's pipeline over the scene with the settings, on `threads` threads
    /// (0: all cores).
    pub fn render(mut self) -> Result<RenderOutput> {
        let start = Instant::now();
        self.aovs = AovLayout::new(self.scene, &self.settings, &self.scene.light_groups);
        let s = &self.settings;
        if let Some(b) = s.time_budget {
            super::settings::check_budget(b).map_err(|message| Error::InvalidSetting {
                setting: "time_budget".into(),
                message,
            })?;
        }
        if s.spp == 0 {
            return Err(Error::InvalidSetting {
                setting: "spp".into(),
                message: "must be at least 1".into(),
            });
        }
        let estimate = self.memory_estimate();
        if let Some(limit) = s.memory_limit_bytes() {
            if estimate.peak_bytes > limit {
                return Err(Error::InvalidSetting {
                    setting: "memory_limit".into(),
                    message: format!(
                        "the render needs an estimated {} bytes at its peak ({} photons x {} B \
                         = {} B for the photon maps, {} B of precomputed irradiance, {} \
                         triangles x {} B = {} B for the BVH), over the limit of {limit} \
                         bytes; store fewer photons or raise the limit",
                        estimate.peak_bytes,
                        estimate.photons,
                        s.bytes_per_photon(),
                        estimate.photon_bytes,
                        estimate.irradiance_bytes,
                        estimate.triangles,
                        BYTES_PER_TRIANGLE,
                        estimate.bvh_bytes,
                    ),
                });
            }
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(s.threads)
            .build()
            .map_err(|e| Error::Internal(format!("thread pool: {e}")))?;
        pool.install(|| self.render_in_pool(pool.current_num_threads(), estimate, start))
    }

    fn render_in_pool(
        &self,
        threads: usize,
        estimate: MemoryEstimate,
        start: Instant,
    ) -> Result<RenderOutput> {
        match self.settings.mode {
            RenderMode::Jensen => self.render_jensen(threads, estimate, start),
            RenderMode::Sppm => self.render_sppm(threads, estimate, start),
            RenderMode::Pppm => self.render_pppm(threads, estimate, start),
        }
    }
}
