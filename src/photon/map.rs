//! Photon maps (Jensen 2001, chapter 7): a kd-tree of photons and the radiance estimate.

use super::{KnnScratch, Photon, PhotonKdTree};
use crate::materials::bsdf::Bsdf;
use crate::math::{Spectrum, PI};
use glam::Vec3;
use serde::Serialize;

/// Which map: the global map takes every photon at a non-specular surface; the caustic map
/// only those whose path is light -> specular+ -> non-specular.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum MapKind {
    Global,
    Caustic,
    /// Photons at scattering events in participating media, after at least one earlier
    /// interaction (single scattering is estimated directly).
    Volume,
}

impl MapKind {
    pub fn name(self) -> &'static str {
        match self {
            MapKind::Global => "global",
            MapKind::Caustic => "caustic",
            MapKind::Volume => "volume",
        }
    }
}

/// User flag (see `Photon::user_flags`) of a photon stored at its first surface hit.
pub const FLAG_FIRST_HIT: u16 = 1;
/// User flag of a photon whose last event before this surface was scattering in a medium: the
/// light a participating medium sends straight to the surface.
pub const FLAG_FROM_MEDIUM: u16 = 2;
/// User flag of a photon whose every earlier interaction was a specular surface bounce
/// (light -> specular+ -> here): the photons of a caustic map, and the caustic part of a
/// global map.
pub const FLAG_CAUSTIC_PATH: u16 = 4;

/// Density-estimation filter (Jensen 2001, §7.2.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EstimateFilter {
    /// Constant kernel over the disk of radius r.
    Constant,
    /// Cone filter w = 1 - d / (k r), normalised by 1 - 2/(3k) (eq. 7.8).
    Cone { k: f32 },
}

pub struct PhotonMap {
    pub kind: MapKind,
    pub tree: PhotonKdTree<Photon>,
    /// Photon paths emitted to fill the map (the photons' power is already divided by it).
    pub emitted: u64,
    /// Seconds the kd-tree took to build (balance).
    pub build_seconds: f64,
}

impl PhotonMap {
    pub fn len(&self) -> usize {
        self.tree.len()
    }
    pub fn is_empty(&self) -> bool {
        self.tree.is_empty()
    }
    pub fn memory_bytes(&self) -> usize {
        self.tree.memory_bytes()
    }

    /// The k nearest photons within `max_r2`, the squared radius of the estimate, and which
    /// photon to leave out. With k photons found, the radius is the k-th photon's distance, and
    /// that photon lies on the boundary: (k - 1) photons over the disk (or sphere) is the
    /// unbiased k-NN density, so the farthest is left out. With fewer found, the search radius
    /// itself bounds the region and every photon counts.
    fn nearest<'s>(
        &self,
        p: Vec3,
        k: usize,
        max_r2: f32,
        scratch: &'s mut KnnScratch,
    ) -> Option<(&'s [super::Neighbor], f32, Option<usize>)> {
        let found = self.tree.knn(p, k, max_r2, scratch);
        if found.is_empty() {
            return None;
        }
        let (r2, skip) = if found.len() >= k && k > 1 {
            let (i, far) = found.iter().enumerate().fold((0, 0.0f32), |acc, (i, nb)| {
                if nb.dist2 > acc.1 {
                    (i, nb.dist2)
                } else {
                    acc
                }
            });
            (far, Some(i))
        } else {
            (max_r2, None)
        };
        (r2 > 0.0 && r2.is_finite()).then_some((found, r2, skip))
    }

    /// Reflected radiance at `p` towards `wo` (Jensen 2001, eq. 7.6):
    /// L = sum_p f(wo, wi_p) Phi_p / (pi r^2), over the `k` nearest photons within `max_r2`,
    /// counting only photons that arrived on the side of `n` (the side `wo` is on) and carry
    /// every user flag in `only` (0: all photons).
    #[allow(clippy::too_many_arguments)]
    pub fn radiance(
        &self,
        p: Vec3,
        n: Vec3,
        wo: Vec3,
        bsdf: &Bsdf,
        k: usize,
        max_r2: f32,
        filter: EstimateFilter,
        only: u16,
        scratch: &mut KnnScratch,
    ) -> Spectrum {
        let Some((found, r2, skip)) = self.nearest(p, k, max_r2, scratch) else {
            return Spectrum::ZERO;
        };
        let r = r2.sqrt();
        let mut sum = Spectrum::ZERO;
        for (i, nb) in found.iter().enumerate() {
            if Some(i) == skip {
                continue;
            }
            let ph = self.tree.get(nb.index);
            if ph.user_flags() & only != only {
                continue;
            }
            let wi = ph.incoming();
            if wi.dot(n) <= 0.0 {
                continue;
            }
            let w = match filter {
                EstimateFilter::Constant => 1.0,
                EstimateFilter::Cone { k } => (1.0 - nb.dist2.sqrt() / (k * r)).max(0.0),
            };
            sum += bsdf.eval(wo, wi) * ph.power() * w;
        }
        let norm = match filter {
            EstimateFilter::Constant => 1.0,
            EstimateFilter::Cone { k } => 1.0 - 2.0 / (3.0 * k),
        };
        sum / (norm * PI * r2)
    }

    /// In-scattered radiance at `x` towards `wo` from a volume map (Jensen & Christensen 1998):
    /// sum_p p(wo, wi_p) Phi_p / (4/3 pi r^3), with the k-th photon bounding the sphere.
    pub fn volume_radiance(
        &self,
        x: Vec3,
        wo: Vec3,
        phase: &crate::media::HenyeyGreenstein,
        k: usize,
        max_r2: f32,
        scratch: &mut KnnScratch,
    ) -> Spectrum {
        let Some((found, r2, skip)) = self.nearest(x, k, max_r2, scratch) else {
            return Spectrum::ZERO;
        };
        let mut sum = Spectrum::ZERO;
        for (i, nb) in found.iter().enumerate() {
            if Some(i) == skip {
                continue;
            }
            let ph = self.tree.get(nb.index);
            sum += ph.power() * phase.eval(wo, ph.incoming());
        }
        sum / (4.0 / 3.0 * PI * r2 * r2.sqrt())
    }

    /// Total power of the photons flagged as first hits (for the energy test).
    pub fn first_hit_power(&self) -> Spectrum {
        self.tree
            .photons()
            .iter()
            .filter(|p| p.user_flags() & FLAG_FIRST_HIT != 0)
            .map(|p| p.power())
            .sum()
    }
}
