//! Density estimates over one kind of photon record: the k nearest photons, surface radiance
//! over Jensen's flattened disc, and radiance in a medium.

use super::{group_of, EstimateFilter, GroupShare, Select};
use crate::materials::bsdf::Bsdf;
use crate::math::{Spectrum, PI};
use crate::photon::{KnnScratch, Neighbor, PhotonKdTree, PhotonRecord};
use glam::Vec3;

/// The k nearest photons within `max_r2`, the squared radius of the estimate, and which
/// photon to leave out. With k photons found, the radius is the k-th photon's distance, and
/// that photon lies on the boundary: (k - 1) photons over the disk (or sphere) is the
/// unbiased k-NN density, so the farthest is left out. With fewer found, the search radius
/// itself bounds the region and every photon counts.
#[inline]
fn nearest<'s, P: PhotonRecord>(
    tree: &PhotonKdTree<P>,
    p: Vec3,
    k: usize,
    max_r2: f32,
    scratch: &'s mut KnnScratch,
) -> Option<(&'s [Neighbor], f32, Option<usize>)> {
    let found = tree.knn(p, k, max_r2, scratch);
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

/// [`super::PhotonMap::radiance`] over one kind of photon record.
#[allow(clippy::too_many_arguments)]
#[inline]
pub(super) fn radiance_in<P: PhotonRecord>(
    tree: &PhotonKdTree<P>,
    scale: f32,
    p: Vec3,
    n: Vec3,
    wo: Vec3,
    bsdf: &Bsdf,
    k: usize,
    max_r2: f32,
    filter: EstimateFilter,
    select: Select,
    scratch: &mut KnnScratch,
    mut share: Option<GroupShare>,
) -> Spectrum {
    let Some((found, r2, skip)) = nearest(tree, p, k, max_r2, scratch) else {
        return Spectrum::ZERO;
    };
    let r = r2.sqrt();
    let bsdf = bsdf.for_view(wo);
    // A surface that transmits diffusely takes the photons that arrived on either side.
    let both_sides = bsdf.transmits_diffusely();
    let norm = match filter {
        EstimateFilter::Constant => 1.0,
        EstimateFilter::Cone { k } => 1.0 - 2.0 / (3.0 * k),
    };
    let inv = 1.0 / (norm * PI * r2);
    let mut sum = Spectrum::ZERO;
    for (i, nb) in found.iter().enumerate() {
        if Some(i) == skip {
            continue;
        }
        let ph = tree.get(nb.index);
        if !select.takes(ph.user_flags()) || !on_disc(ph.position(), p, n, r) {
            continue;
        }
        let wi = ph.incoming();
        if wi.dot(n) <= 0.0 && !both_sides {
            continue;
        }
        let w = match filter {
            EstimateFilter::Constant => 1.0,
            EstimateFilter::Cone { k } => (1.0 - nb.dist2.sqrt() / (k * r)).max(0.0),
        };
        let c = bsdf.eval_flux(wo, wi) * (ph.power() * scale) * w;
        sum += c;
        if let Some(f) = share.as_mut() {
            f(group_of(ph.user_flags()), c * inv);
        }
    }
    sum / (norm * PI * r2)
}

/// Fraction of the estimate's radius that a photon may lie off the tangent plane of the
/// point estimated: Jensen's disc-shaped search (2001, §7.2.1), the sphere of the k nearest
/// photons flattened along the normal, so that photons on another surface close by (the far
/// side of a thin wall, the adjacent wall of a corner) do not leak into the estimate.
pub const DISC_THICKNESS: f32 = 0.25;

/// Whether photon position `q` lies within the flattened disc of radius `r` around `p` with
/// normal `n` (unit).
#[inline]
pub fn on_disc(q: Vec3, p: Vec3, n: Vec3, r: f32) -> bool {
    (q - p).dot(n).abs() <= DISC_THICKNESS * r
}

/// [`super::PhotonMap::for_each_nearest`] over one kind of photon record.
#[inline]
pub(super) fn for_each_nearest_in<P: PhotonRecord>(
    tree: &PhotonKdTree<P>,
    scale: f32,
    p: Vec3,
    k: usize,
    max_r2: f32,
    scratch: &mut KnnScratch,
    n: Vec3,
    mut f: impl FnMut(Spectrum, Vec3, u16, f32),
) -> Option<f32> {
    let (found, r2, skip) = nearest(tree, p, k, max_r2, scratch)?;
    for (i, nb) in found.iter().enumerate() {
        if Some(i) != skip {
            let ph = tree.get(nb.index);
            if on_disc(ph.position(), p, n, r2.sqrt()) {
                f(ph.power() * scale, ph.incoming(), ph.user_flags(), nb.dist2);
            }
        }
    }
    Some(r2)
}

/// [`super::PhotonMap::volume_radiance`] over one kind of photon record.
#[inline]
pub(super) fn volume_radiance_in<P: PhotonRecord>(
    tree: &PhotonKdTree<P>,
    scale: f32,
    x: Vec3,
    wo: Vec3,
    phase: &crate::media::HenyeyGreenstein,
    k: usize,
    max_r2: f32,
    scratch: &mut KnnScratch,
    mut share: Option<GroupShare>,
) -> Option<(Spectrum, f32)> {
    let (found, r2, skip) = nearest(tree, x, k, max_r2, scratch)?;
    let inv = 1.0 / (4.0 / 3.0 * PI * r2 * r2.sqrt());
    let mut sum = Spectrum::ZERO;
    for (i, nb) in found.iter().enumerate() {
        if Some(i) == skip {
            continue;
        }
        let ph = tree.get(nb.index);
        let c = (ph.power() * scale) * phase.eval(wo, ph.incoming());
        sum += c;
        if let Some(f) = share.as_mut() {
            f(group_of(ph.user_flags()), c * inv);
        }
    }
    Some((sum / (4.0 / 3.0 * PI * r2 * r2.sqrt()), r2))
}
