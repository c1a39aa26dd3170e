//! Precomputed irradiance at photon positions (Christensen 1999, "Faster Photon Map Global
//! Illumination", JGT 4(3)): at a subset of the global map's photons the irradiance estimate
//! from the map's k nearest photons is computed once, with the surface normal there. A
//! final-gathering ray then reads the nearest such point with a matching normal instead of
//! running a k-nearest-neighbour radiance estimate with the BSDF at every photon.
//!
//! The points are kept in their own left-balanced kd-tree of 20-byte records.

use super::append::append_parallel;
use super::kdtree::{KnnScratch, PhotonKdTree};
use super::map::{PhotonMap, Select, FLAG_SUBSURFACE_EXIT};
use super::photon::{decode_direction, encode_direction, rgbe_decode, rgbe_encode, KdRecord};
use crate::math::{Spectrum, PI};
use glam::Vec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Every `STRIDE`-th photon of the global map becomes an irradiance point (Christensen uses
/// every fourth: the estimate spans about k photons, so neighbouring points would repeat it).
pub const STRIDE: usize = 4;

/// Smallest cosine between a query's normal and a point's for the point to answer it.
const MIN_COS: f32 = 0.9;

/// Points considered per query: the nearest with a matching normal among them answers.
const CANDIDATES: usize = 4;
/// Points averaged by [`IrradianceMap::lookup_smooth`].
const SMOOTH_CANDIDATES: usize = 8;

/// A point of precomputed irradiance: position, RGBE irradiance, the quantised normal (on the
/// side the photons arrived from), and the kd-tree split axis.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct IrradiancePoint {
    pos: [f32; 3],
    rgbe: [u8; 4],
    normal: (u8, u8),
    axis: u8,
    _pad: u8,
}

const _: () = assert!(std::mem::size_of::<IrradiancePoint>() == 20);

impl KdRecord for IrradiancePoint {
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

impl IrradiancePoint {
    /// The record as little-endian bytes (the layout of the struct), for saved maps.
    pub fn to_le_bytes(&self) -> [u8; 20] {
        let mut b = [0u8; 20];
        for (i, v) in self.pos.iter().enumerate() {
            b[4 * i..4 * i + 4].copy_from_slice(&v.to_le_bytes());
        }
        b[12..16].copy_from_slice(&self.rgbe);
        b[16] = self.normal.0;
        b[17] = self.normal.1;
        b[18] = self.axis;
        b
    }

    /// The record of [`IrradiancePoint::to_le_bytes`].
    pub fn from_le_bytes(b: &[u8]) -> IrradiancePoint {
        let f = |i: usize| f32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
        IrradiancePoint {
            pos: [f(0), f(4), f(8)],
            rgbe: [b[12], b[13], b[14], b[15]],
            normal: (b[16], b[17]),
            axis: b[18],
            _pad: 0,
        }
    }

    fn new(p: Vec3, n: Vec3, est: &IrradianceEstimate) -> Option<Self> {
        let rgbe = rgbe_encode(est.irradiance).ok()?;
        Some(IrradiancePoint {
            pos: p.to_array(),
            rgbe,
            normal: encode_direction(n),
            axis: 0,
            _pad: 0,
        })
    }

    pub fn irradiance(&self) -> Spectrum {
        rgbe_decode(self.rgbe)
    }

    pub fn normal(&self) -> Vec3 {
        decode_direction(self.normal.0, self.normal.1)
    }
}

/// Points whose records [`IrradianceMap::build`] makes at a time, from the back.
const BUILD_PIECE: usize = 1 << 20;

/// The irradiance points of a global map.
pub struct IrradianceMap {
    tree: PhotonKdTree<IrradiancePoint>,
    max_r2: f32,
    /// With light groups: each point's fraction of its irradiance per group (per channel),
    /// `groups` entries per point in the tree's order.
    fractions: Vec<Spectrum>,
    groups: usize,
}

impl IrradianceMap {
    /// Irradiance at each of `points` (position, and normal on the photons' side as
    /// [`encode_direction`] bytes) from the photons `select` takes among the `k` nearest of
    /// `global` within `max_r2`; None when cancelled. Deterministic: each point's estimate
    /// depends on the map alone. The points are consumed and freed as their records are made
    /// (`BUILD_PIECE` at a time), and the points' tree is balanced in place, in the records'
    /// own array.
    pub fn build(
        global: &PhotonMap,
        points: Vec<(Vec3, (u8, u8))>,
        k: usize,
        max_r2: f32,
        select: Select,
        cancel: Option<&AtomicBool>,
    ) -> Option<IrradianceMap> {
        let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
        // The records are made a piece of points at a time from the back, each piece's points
        // freed once its records are made, so the points and the records are never all live
        // together. The points whose irradiance cannot be encoded are dropped, keeping the
        // others' order.
        let mut points = points;
        let mut pieces: Vec<Vec<IrradiancePoint>> = Vec::new();
        while !points.is_empty() {
            let start = points.len().saturating_sub(BUILD_PIECE);
            let piece: Vec<Vec<IrradiancePoint>> = points[start..]
                .par_chunks(4096)
                .map_init(KnnScratch::new, |scratch, chunk| {
                    if cancelled() {
                        return Vec::new();
                    }
                    chunk
                        .iter()
                        .filter_map(|&(p, nb)| {
                            let n = decode_direction(nb.0, nb.1);
                            let est = global.irradiance_estimate(p, n, k, max_r2, select, scratch);
                            IrradiancePoint::new(p, n, &est)
                        })
                        .collect()
                })
                .collect();
            if cancelled() {
                return None;
            }
            points.truncate(start);
            points.shrink_to_fit();
            let mut records = Vec::new();
            append_parallel(
                &mut records,
                &piece.iter().map(|c| &c[..]).collect::<Vec<_>>(),
            );
            pieces.push(records);
        }
        drop(points);
        let records = match pieces.len() {
            0 | 1 => pieces.pop().unwrap_or_default(),
            _ => {
                let mut records = Vec::with_capacity(pieces.iter().map(Vec::len).sum());
                while let Some(piece) = pieces.pop() {
                    append_parallel(&mut records, &[&piece[..]]);
                }
                records
            }
        };
        let tree = PhotonKdTree::build(records);
        Some(IrradianceMap {
            tree,
            max_r2,
            fractions: Vec::new(),
            groups: 0,
        })
    }

    /// Adds each point's light-group fractions (`groups` groups): the same estimate as the
    /// point's, split by the photons' groups. None when cancelled.
    pub fn split_groups(
        &mut self,
        global: &PhotonMap,
        groups: usize,
        k: usize,
        select: Select,
        cancel: Option<&AtomicBool>,
    ) -> Option<()> {
        let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
        let max_r2 = self.max_r2;
        let points: Vec<(Vec3, Vec3)> = self
            .tree
            .photons()
            .iter()
            .map(|pt| (KdRecord::position(pt), pt.normal()))
            .collect();
        let fractions: Vec<Spectrum> = points
            .par_chunks(4096)
            .map_init(KnnScratch::new, |scratch, chunk| {
                let mut out = Vec::with_capacity(chunk.len() * groups);
                if cancelled() {
                    return out;
                }
                let mut parts = vec![Spectrum::ZERO; groups];
                for &(p, n) in chunk {
                    parts.iter_mut().for_each(|v| *v = Spectrum::ZERO);
                    let est = global
                        .irradiance_estimate_split(p, n, k, max_r2, select, scratch, &mut parts);
                    out.extend(crate::math::fractions(&parts, est.irradiance));
                }
                out
            })
            .flatten_iter()
            .collect();
        if cancelled() {
            return None;
        }
        self.fractions = fractions;
        self.groups = groups;
        Some(())
    }

    /// The light-group fractions of the point at heap index `index` (empty without groups).
    pub fn fractions(&self, index: u32) -> &[Spectrum] {
        let i = index as usize * self.groups;
        self.fractions.get(i..i + self.groups).unwrap_or(&[])
    }

    pub fn len(&self) -> usize {
        self.tree.len()
    }

    /// The points in heap order, and the search radius²: what a saved map keeps.
    pub fn parts(&self) -> (&[IrradiancePoint], f32) {
        (self.tree.photons(), self.max_r2)
    }

    /// The light groups per point and every point's fractions, in heap order (empty
    /// without groups): what a saved map keeps with its points.
    pub fn group_parts(&self) -> (usize, &[Spectrum]) {
        (self.groups, &self.fractions)
    }

    /// The map of [`IrradianceMap::parts`] and [`IrradianceMap::group_parts`].
    pub fn from_parts(
        points: Vec<IrradiancePoint>,
        max_r2: f32,
        groups: usize,
        fractions: Vec<Spectrum>,
    ) -> IrradianceMap {
        IrradianceMap {
            tree: PhotonKdTree::from_heap(points),
            max_r2,
            groups,
            fractions,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.tree.is_empty()
    }

    pub fn memory_bytes(&self) -> usize {
        self.tree.memory_bytes() + self.fractions.len() * std::mem::size_of::<Spectrum>()
    }

    /// The nearest point to `p` whose normal is within about 25 degrees of `n`, within the
    /// map's search radius, and its light-group fractions (empty without groups).
    /// The mean of the points among the [`SMOOTH_CANDIDATES`] nearest to `p` whose normal
    /// matches `n`, weighted by their distance's complement to the farthest candidate's
    /// (a cone over the candidates); `None` when none matches. For the exitance points, where
    /// the nearest point alone favours points in sparse (dim) parts.
    pub fn lookup_smooth(&self, p: Vec3, n: Vec3, scratch: &mut KnnScratch) -> Option<Spectrum> {
        let found = self.tree.knn(p, SMOOTH_CANDIDATES, self.max_r2, scratch);
        let r = found
            .iter()
            .map(|nb| nb.dist2)
            .fold(0.0f32, f32::max)
            .sqrt()
            * 1.01
            + 1e-12;
        let (mut sum, mut wsum) = (Spectrum::ZERO, 0.0f32);
        for nb in found.iter() {
            let pt = self.tree.get(nb.index);
            if pt.normal().dot(n) >= MIN_COS {
                let w = 1.0 - nb.dist2.sqrt() / r;
                sum += w * pt.irradiance();
                wsum += w;
            }
        }
        (wsum > 0.0).then(|| sum / wsum)
    }

    pub fn lookup(
        &self,
        p: Vec3,
        n: Vec3,
        scratch: &mut KnnScratch,
    ) -> Option<(&IrradiancePoint, &[Spectrum])> {
        let found = self.tree.knn(p, CANDIDATES, self.max_r2, scratch);
        let best = found
            .iter()
            .filter(|nb| self.tree.get(nb.index).normal().dot(n) >= MIN_COS)
            .min_by(|a, b| a.dist2.total_cmp(&b.dist2))?;
        Some((self.tree.get(best.index), self.fractions(best.index)))
    }
}

/// An irradiance estimate from a photon map.
#[derive(Clone, Copy, Debug)]
pub struct IrradianceEstimate {
    pub irradiance: Spectrum,
}

impl PhotonMap {
    /// Irradiance at `p` (normal `n`) from those of the `k` nearest photons that arrived on
    /// the side of `n` and that `select` takes: E = sum Phi_p / (pi r^2) (the k-th photon on
    /// the boundary left out, as in the radiance estimate).
    pub fn irradiance_estimate(
        &self,
        p: Vec3,
        n: Vec3,
        k: usize,
        max_r2: f32,
        select: Select,
        scratch: &mut KnnScratch,
    ) -> IrradianceEstimate {
        self.irradiance_estimate_split(p, n, k, max_r2, select, scratch, &mut [])
    }

    /// As [`PhotonMap::irradiance_estimate`], each light group's share added to `groups`
    /// (as many entries as groups; none: no split).
    #[allow(clippy::too_many_arguments)]
    pub fn irradiance_estimate_split(
        &self,
        p: Vec3,
        n: Vec3,
        k: usize,
        max_r2: f32,
        select: Select,
        scratch: &mut KnnScratch,
        groups: &mut [Spectrum],
    ) -> IrradianceEstimate {
        let mut sum = Spectrum::ZERO;
        // An estimate of the subsurface exits' exitance leaves out an exit lying exactly at its
        // centre: at a point placed on an exit photon, that photon would count in full, a bias
        // of about one photon in the k.
        let exits = select.require & FLAG_SUBSURFACE_EXIT != 0;
        let r2 = self.for_each_nearest(p, k, max_r2, scratch, n, |power, wi, flags, d2| {
            if exits && d2 == 0.0 {
                return;
            }
            if wi.dot(n) > 0.0 && select.takes(flags) {
                sum += power;
                if let Some(g) = groups.get_mut(super::map::group_of(flags)) {
                    *g += power;
                }
            }
        });
        let norm = r2.map_or(0.0, |r2| 1.0 / (PI * r2));
        for g in groups.iter_mut() {
            *g *= norm;
        }
        IrradianceEstimate {
            irradiance: sum * norm,
        }
    }
}
