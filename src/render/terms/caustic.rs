//! `caustic`: light focused by mirrors and glass onto a non-specular surface, visualised
//! directly from the caustic photon map with a cone filter (Jensen 2001, §9.1, §7.2.2).

use crate::geometry::SurfaceInteraction;
use crate::materials::bsdf::Bsdf;
use crate::math::Spectrum;
use crate::photon::map::{EstimateFilter, Select};
use crate::photon::KnnScratch;
use crate::render::photons::PhotonMaps;

/// Jensen's cone-filter constant.
pub const CONE_K: f32 = 1.1;

pub fn estimate(
    maps: &PhotonMaps,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    scratch: &mut KnnScratch,
) -> Spectrum {
    match &maps.caustic {
        Some(m) => m.radiance(
            si.p,
            si.ng,
            si.wo,
            bsdf,
            maps.gather,
            maps.caustic_r2,
            EstimateFilter::Cone { k: CONE_K },
            Select::ALL,
            scratch,
        ),
        None => Spectrum::ZERO,
    }
}
