//! The memory a render will take, estimated before the photon pass and checked against the
//! memory limit.

use super::photons;
use super::renderer::Renderer;
use super::settings::BYTES_PER_TRIANGLE;
use serde::Serialize;

/// Memory that the photon maps and the BVH of a render take, estimated before the photon
/// pass from the stored-photon targets of the maps that will be built.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct MemoryEstimate {
    /// Photons stored over every map that will be built.
    pub photons: u64,
    /// `photons * RenderSettings::bytes_per_photon()` (20 B RGBE, 28 B `f32` power).
    pub photon_bytes: u64,
    pub triangles: u64,
    /// `triangles * BYTES_PER_TRIANGLE`.
    pub bvh_bytes: u64,
    /// The global map's precomputed irradiance points: one per `irradiance::STRIDE` photons,
    /// `size_of::<IrradiancePoint>()` (20) bytes each.
    pub irradiance_bytes: u64,
    /// `photon_bytes + bvh_bytes + irradiance_bytes`.
    pub total_bytes: u64,
    /// The most the render holds at once, which the memory limit is checked against: the
    /// BVH and the maps. A map's photons are traced as their stored records and its kd-tree
    /// is balanced in place, so building the maps holds no more than the maps
    /// (`trace::build_map`).
    pub peak_bytes: u64,
}

impl Renderer<'_> {
    /// The memory the photon maps (stored targets of every map that will be built, at
    /// `RenderSettings::bytes_per_photon`) and the BVH (`BYTES_PER_TRIANGLE`) take.
    pub fn memory_estimate(&self) -> MemoryEstimate {
        let p = &self.settings;
        let [need_global, need_caustic, need_volume] = self.needed_maps();
        let built: Vec<u64> = if self.scene.lights.is_empty() {
            Vec::new()
        } else {
            let caustic = need_caustic
                && p.caustic_photons > 0
                && !photons::specular_targets(self.scene).is_empty();
            [
                (need_global, p.photons),
                (caustic, p.caustic_photons),
                (need_volume, p.volume_photons),
            ]
            .iter()
            .filter(|(b, _)| *b)
            .map(|(_, n)| *n as u64)
            .collect()
        };
        let photons = built.iter().fold(0u64, |acc, n| acc.saturating_add(*n));
        let global = if need_global && !self.scene.lights.is_empty() {
            p.photons as u64
        } else {
            0
        };
        let irradiance_bytes = global
            .div_ceil(crate::photon::irradiance::STRIDE as u64)
            .saturating_mul(
                std::mem::size_of::<crate::photon::irradiance::IrradiancePoint>() as u64,
            );
        let triangles = self.scene.triangle_count as u64;
        let record = p.bytes_per_photon();
        let photon_bytes = photons.saturating_mul(record);
        let bvh_bytes = triangles.saturating_mul(BYTES_PER_TRIANGLE);
        let total_bytes = photon_bytes
            .saturating_add(bvh_bytes)
            .saturating_add(irradiance_bytes);
        MemoryEstimate {
            photons,
            photon_bytes,
            triangles,
            bvh_bytes,
            irradiance_bytes,
            total_bytes,
            peak_bytes: total_bytes,
        }
    }
}
