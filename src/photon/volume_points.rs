//! Precomputed in-scattered radiance at volume photons, for isotropic media: Christensen's
//! precomputation (1999, "Faster Photon Map Global Illumination", JGT 4(3)) applied to the
//! volume map. At every [`STRIDE`]-th photon the volume radiance estimate
//! sum_p Phi_p / (4 pi 4/3 pi r^3) is computed once, already divided by the part of its sphere
//! that lies in the medium; a march step in an isotropic medium then reads the nearest such
//! point instead of a k-nearest search and the support rays of its boundary correction.
//!
//! A point answers a query only within [`REACH`] of its own estimate's radius: beyond that
//! (the edge of a beam, where the nearest point's estimate reaches light the query's would
//! not) the caller takes the full estimate. The points are kept in their own left-balanced
//! kd-tree of 20-byte records.

use super::kdtree::{KnnScratch, PhotonKdTree};
use super::map::PhotonMap;
use super::photon::{rgbe_decode, rgbe_encode, KdRecord};
use crate::math::{Spectrum, PI};
use glam::Vec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Every `STRIDE`-th photon of the volume map becomes a point (an estimate spans k photons,
/// so neighbouring points would repeat it).
pub const STRIDE: usize = 4;

/// Points considered per query; the nearest that reaches the query answers.
const CANDIDATES: usize = 4;

/// A point answers queries within this fraction of its estimate's radius.
pub const REACH: f32 = 0.75;

/// A point of precomputed volume radiance: position, RGBE radiance (isotropic, boundary
/// corrected), its estimate's radius as a fraction of the map's largest, and the split axis.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct VolumePoint {
    pos: [f32; 3],
    rgbe: [u8; 4],
    radius: u16,
    axis: u8,
    _pad: u8,
}

const _: () = assert!(std::mem::size_of::<VolumePoint>() == 20);

impl KdRecord for VolumePoint {
    #[inline(always)]
    fn pos(&self) -> &[f32; 3] {
        &self.pos
    }
    #[inline(always)]
    fn axis(&self) -> u8 {
        self.axis
    }
    #[inline]
    fn set_axis(&mut self, axis: u8) {
        self.axis = axis;
    }
}

impl VolumePoint {
    pub const BYTES: usize = 20;

    pub fn radiance(&self) -> Spectrum {
        rgbe_decode(self.rgbe)
    }

    /// The record as little-endian bytes (photon-map files).
    pub fn to_le_bytes(&self) -> [u8; 20] {
        let mut b = [0u8; 20];
        for (i, v) in self.pos.iter().enumerate() {
            b[4 * i..4 * i + 4].copy_from_slice(&v.to_le_bytes());
        }
        b[12..16].copy_from_slice(&self.rgbe);
        b[16..18].copy_from_slice(&self.radius.to_le_bytes());
        b[18] = self.axis;
        b
    }

    /// The record of [`VolumePoint::to_le_bytes`].
    pub fn from_le_bytes(b: &[u8]) -> VolumePoint {
        let f = |i: usize| f32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
        VolumePoint {
            pos: [f(0), f(4), f(8)],
            rgbe: [b[12], b[13], b[14], b[15]],
            radius: u16::from_le_bytes([b[16], b[17]]),
            axis: b[18],
            _pad: 0,
        }
    }
}

/// The volume points of a volume map.
pub struct VolumePointMap {
    tree: PhotonKdTree<VolumePoint>,
    max_r: f32,
}

impl VolumePointMap {
    /// The points of `volume`: at every [`STRIDE`]-th photon, the isotropic estimate from its
    /// `k` nearest within `max_r2`, divided by `reach(point index, position, radius)`, the part
    /// of the estimate's sphere in the medium. None when cancelled. Deterministic: each point
    /// depends on the map and its index alone.
    pub fn build(
        volume: &PhotonMap,
        k: usize,
        max_r2: f32,
        reach: &(dyn Fn(u64, Vec3, f32) -> f32 + Sync),
        cancel: Option<&AtomicBool>,
    ) -> Option<VolumePointMap> {
        let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
        let max_r = max_r2.sqrt();
        let sites: Vec<(u64, Vec3)> = volume
            .positions()
            .into_iter()
            .enumerate()
            .step_by(STRIDE)
            .map(|(i, p)| (i as u64, p))
            .collect();
        let iso = crate::media::HenyeyGreenstein::new(0.0);
        let records: Vec<Option<VolumePoint>> = sites
            .par_chunks(1024)
            .map_init(KnnScratch::new, |scratch, chunk| {
                if cancelled() {
                    return Vec::new();
                }
                chunk
                    .iter()
                    .map(|&(i, p)| {
                        let (l, r2) =
                            volume.volume_radiance(p, Vec3::Z, &iso, k, max_r2, scratch, None)?;
                        let r = r2.sqrt();
                        let l = l / reach(i, p, r);
                        Some(VolumePoint {
                            pos: p.to_array(),
                            rgbe: rgbe_encode(l).ok()?,
                            radius: ((r / max_r).clamp(0.0, 1.0) * u16::MAX as f32).round() as u16,
                            axis: 0,
                            _pad: 0,
                        })
                    })
                    .collect()
            })
            .flatten_iter()
            .collect();
        if cancelled() {
            return None;
        }
        let tree = PhotonKdTree::build(records.into_iter().flatten().collect());
        Some(VolumePointMap { tree, max_r })
    }

    pub fn len(&self) -> usize {
        self.tree.len()
    }

    /// The balanced records and the largest radius (photon-map files).
    pub fn parts(&self) -> (&[VolumePoint], f32) {
        (self.tree.photons(), self.max_r)
    }

    /// The map of [`VolumePointMap::parts`].
    pub fn from_parts(heap: Vec<VolumePoint>, max_r: f32) -> VolumePointMap {
        VolumePointMap {
            tree: PhotonKdTree::from_heap(heap),
            max_r,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.tree.is_empty()
    }

    pub fn memory_bytes(&self) -> usize {
        self.tree.memory_bytes()
    }

    fn radius(&self, p: &VolumePoint) -> f32 {
        p.radius as f32 / u16::MAX as f32 * self.max_r
    }

    /// The isotropic in-scattered radiance at `x` from the nearest point whose estimate
    /// reaches it ([`REACH`] of its radius); None where none does.
    pub fn lookup(&self, x: Vec3, scratch: &mut KnnScratch) -> Option<Spectrum> {
        let found = self
            .tree
            .knn(x, CANDIDATES, self.max_r * self.max_r, scratch);
        let best = found
            .iter()
            .filter(|nb| {
                let r = REACH * self.radius(self.tree.get(nb.index));
                nb.dist2 <= r * r
            })
            .min_by(|a, b| a.dist2.total_cmp(&b.dist2))?;
        Some(self.tree.get(best.index).radiance())
    }
}

/// The isotropic phase function's value, 1 / (4 pi): a point's radiance is the estimate with
/// it, so the march adds it unchanged.
pub const ISOTROPIC: f32 = 1.0 / (4.0 * PI);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photon::map::{MapKind, PhotonTree};
    use crate::photon::photon::Photon;
    use crate::sampling::Rng;

    /// A volume map of `n` photons of equal power uniform in the unit cube.
    fn uniform_map(n: usize, power: f32) -> PhotonMap {
        let mut rng = Rng::new(5, 0);
        let photons: Vec<Photon> = (0..n)
            .map(|_| {
                let p = Vec3::new(rng.f32(), rng.f32(), rng.f32());
                Photon::new(p, Spectrum::splat(power), Vec3::Z).unwrap()
            })
            .collect();
        PhotonMap::from_tree(
            MapKind::Volume,
            PhotonTree::Rgbe(PhotonKdTree::build(photons), 1.0),
        )
    }

    /// In a uniform photon cloud each point's radiance is the cloud's: power density over 4 pi;
    /// the reach divides it; and a query reads the nearest point within [`REACH`] of its radius, or
    /// none.
    #[test]
    fn points_hold_the_isotropic_estimate_and_answer_near_them() {
        let (n, power) = (40_000usize, 1e-3f32);
        let map = uniform_map(n, power);
        let vp = VolumePointMap::build(&map, 50, 0.04, &|_, _, _| 1.0, None).unwrap();
        assert_eq!(vp.len(), n.div_ceil(STRIDE));
        let expected = n as f32 * power / (4.0 * PI);
        let mut scratch = KnnScratch::new();
        let got = vp.lookup(Vec3::splat(0.5), &mut scratch).unwrap().x;
        // The mean over many interior queries is within 3% (one estimate of k = 50 photons
        // is within about 14%).
        let mut rng = Rng::new(9, 0);
        let (mut sum, mut count) = (0.0f64, 0);
        for _ in 0..2000 {
            let x = Vec3::new(rng.f32(), rng.f32(), rng.f32()) * 0.6 + Vec3::splat(0.2);
            if let Some(l) = vp.lookup(x, &mut scratch) {
                sum += l.x as f64;
                count += 1;
            }
        }
        assert!(count > 1950, "{count} of 2000 interior queries answered");
        let mean = sum / count as f64;
        assert!(
            (mean / expected as f64 - 1.0).abs() < 0.03,
            "{mean} against {expected}"
        );
        // Half the medium: the reach doubles the points' radiance.
        let half = VolumePointMap::build(&map, 50, 0.04, &|_, _, _| 0.5, None).unwrap();
        let h = half.lookup(Vec3::splat(0.5), &mut scratch).unwrap().x;
        assert!((h / got - 2.0).abs() < 1e-2, "{h} against 2 x {got}");
        // Far outside the cloud no point reaches.
        assert!(vp.lookup(Vec3::splat(3.0), &mut scratch).is_none());
        assert!(vp.lookup(Vec3::new(0.5, 0.5, 1.15), &mut scratch).is_none());
    }
}
