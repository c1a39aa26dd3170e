//! Photon maps (Jensen 2001, chapter 7): a kd-tree of photons and the radiance estimate.

mod estimate;

pub use estimate::{on_disc, DISC_THICKNESS};

use super::{KdRecord, KnnScratch, Neighbor, Photon, PhotonF32, PhotonKdTree, PhotonRecord};
use crate::materials::bsdf::Bsdf;
use crate::math::Spectrum;
use estimate::{for_each_nearest_in, radiance_in, volume_radiance_in};
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
/// User flag of a photon that left a surface at the end of its walk below a subsurface
/// material: light leaving the surface, not arriving at it. Its incoming direction is the
/// surface's outward normal. Every [`Select`] leaves these out unless it asks for them.
pub const FLAG_SUBSURFACE_EXIT: u16 = 8;

/// The user flags above this bit hold the photon's light group (`Scene::light_group`): 8
/// bits, beside the `FLAG_*` bits below it, inside the 20-byte photon's flag word.
pub const GROUP_SHIFT: u16 = 4;
/// The `FLAG_*` bits of a photon's user flags, without its group.
pub const FLAG_MASK: u16 = (1 << GROUP_SHIFT) - 1;

/// A photon's light group, from its user flags.
#[inline]
pub fn group_of(flags: u16) -> usize {
    (flags >> GROUP_SHIFT) as usize
}

/// Receives an estimate's share of each light group: (group, share), the shares summing to
/// the estimate.
pub type GroupShare<'a> = &'a mut dyn FnMut(usize, Spectrum);

/// Which photons of a map an estimate takes, by their user flags: those with every `require`
/// bit and no `exclude` bit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Select {
    pub require: u16,
    pub exclude: u16,
}

impl Select {
    /// Every photon arriving at a surface (all but the subsurface exits).
    pub const ALL: Select = Select {
        require: 0,
        exclude: FLAG_SUBSURFACE_EXIT,
    };

    /// The photons with every bit of `flags` (subsurface exits only when `flags` has
    /// [`FLAG_SUBSURFACE_EXIT`]).
    pub const fn with(flags: u16) -> Select {
        Select {
            require: flags,
            exclude: FLAG_SUBSURFACE_EXIT & !flags,
        }
    }

    /// The photons arriving at a surface with no bit of `flags`.
    pub const fn without(flags: u16) -> Select {
        Select {
            require: 0,
            exclude: flags | FLAG_SUBSURFACE_EXIT,
        }
    }

    #[inline]
    pub fn takes(self, flags: u16) -> bool {
        flags & self.require == self.require && flags & self.exclude == 0
    }
}

/// Density-estimation filter (Jensen 2001, §7.2.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EstimateFilter {
    /// Constant kernel over the disk of radius r.
    Constant,
    /// Cone filter w = 1 - d / (k r), normalised by 1 - 2/(3k) (eq. 7.8).
    Cone { k: f32 },
}

/// The kd-tree of a map, over one of the two photon records: the 20-byte [`Photon`] with RGBE
/// power (the default; Jensen 2001, §6.4), or the 28-byte [`PhotonF32`] with `f32` power
/// (`photon_power f32`), which trades memory for the RGBE quantisation (≤ 1/256 of a
/// photon's largest channel).
///
/// The records hold each photon's power as traced, before the division by the photon paths
/// emitted (which is known only once tracing stops); the `f32` beside the tree is that
/// division's factor, the map's power scale (1 / emitted), applied to each photon's power as
/// it is read ([`PhotonRef::power`]). So a traced photon is already its final record, and the
/// photon pass holds nothing but the records. Power read is `decoded · scale`, one `f32`
/// product, the same as dividing before storing for `f32` records; for RGBE records the
/// quantisation falls on the traced power instead of the divided one.
pub enum PhotonTree {
    Rgbe(PhotonKdTree<Photon>, f32),
    F32(PhotonKdTree<PhotonF32>, f32),
}

/// Calls `$body` with `$t` bound to the tree, whichever photon record it holds (and `$s` to
/// the map's power scale): one branch per query, then the monomorphised code of that record.
macro_rules! with_tree {
    ($tree:expr, $t:ident => $body:expr) => {
        match $tree {
            PhotonTree::Rgbe($t, _) => $body,
            PhotonTree::F32($t, _) => $body,
        }
    };
    ($tree:expr, $t:ident, $s:ident => $body:expr) => {
        match $tree {
            PhotonTree::Rgbe($t, $s) => {
                let $s = *$s;
                $body
            }
            PhotonTree::F32($t, $s) => {
                let $s = *$s;
                $body
            }
        }
    };
}

impl PhotonTree {
    pub fn len(&self) -> usize {
        with_tree!(self, t => t.len())
    }
    pub fn is_empty(&self) -> bool {
        with_tree!(self, t => t.is_empty())
    }
    pub fn memory_bytes(&self) -> usize {
        with_tree!(self, t => t.memory_bytes())
    }
    /// Bytes per stored photon: 20 (RGBE) or 28 (`f32` power).
    pub fn bytes_per_photon(&self) -> usize {
        match self {
            PhotonTree::Rgbe(..) => std::mem::size_of::<Photon>(),
            PhotonTree::F32(..) => std::mem::size_of::<PhotonF32>(),
        }
    }

    /// The `k` photons nearest to `p` within `max_r2`, as [`PhotonKdTree::knn`].
    #[inline]
    pub fn knn<'s>(
        &self,
        p: Vec3,
        k: usize,
        max_r2: f32,
        scratch: &'s mut KnnScratch,
    ) -> &'s [Neighbor] {
        with_tree!(self, t => t.knn(p, k, max_r2, scratch))
    }

    /// The photon at heap index `index` (a [`Neighbor::index`]).
    #[inline]
    pub fn get(&self, index: u32) -> PhotonRef<'_> {
        match self {
            PhotonTree::Rgbe(t, s) => PhotonRef::Rgbe(t.get(index), *s),
            PhotonTree::F32(t, s) => PhotonRef::F32(t.get(index), *s),
        }
    }

    /// Calls `visitor(photon, distance²)` for every photon within `r2` of `p`, as
    /// [`PhotonKdTree::for_each_in_radius`].
    #[inline]
    pub fn for_each_in_radius(
        &self,
        p: Vec3,
        r2: f32,
        mut visitor: impl FnMut(PhotonRef<'_>, f32),
    ) {
        match self {
            PhotonTree::Rgbe(t, s) => {
                t.for_each_in_radius(p, r2, |ph, d2| visitor(PhotonRef::Rgbe(ph, *s), d2))
            }
            PhotonTree::F32(t, s) => {
                t.for_each_in_radius(p, r2, |ph, d2| visitor(PhotonRef::F32(ph, *s), d2))
            }
        }
    }
}

/// A photon of a [`PhotonTree`], whichever record it is, with its map's power scale; decodes
/// only what is asked for.
#[derive(Clone, Copy, Debug)]
pub enum PhotonRef<'a> {
    Rgbe(&'a Photon, f32),
    F32(&'a PhotonF32, f32),
}

impl PhotonRef<'_> {
    #[inline]
    pub fn position(self) -> Vec3 {
        match self {
            PhotonRef::Rgbe(p, _) => KdRecord::position(p),
            PhotonRef::F32(p, _) => KdRecord::position(p),
        }
    }
    /// Power (flux): the stored power, decoded from RGBE if stored so, times the map's power
    /// scale.
    #[inline]
    pub fn power(self) -> Vec3 {
        match self {
            PhotonRef::Rgbe(p, s) => PhotonRecord::power(p) * s,
            PhotonRef::F32(p, s) => PhotonRecord::power(p) * s,
        }
    }
    /// Unit vector from the surface back towards where the photon came from.
    #[inline]
    pub fn incoming(self) -> Vec3 {
        match self {
            PhotonRef::Rgbe(p, _) => PhotonRecord::incoming(p),
            PhotonRef::F32(p, _) => PhotonRecord::incoming(p),
        }
    }
    /// The renderer's flag bits (`FLAG_*`).
    #[inline]
    pub fn user_flags(self) -> u16 {
        match self {
            PhotonRef::Rgbe(p, _) => PhotonRecord::user_flags(p),
            PhotonRef::F32(p, _) => PhotonRecord::user_flags(p),
        }
    }
}

pub struct PhotonMap {
    pub kind: MapKind,
    pub tree: PhotonTree,
    /// Precomputed irradiance at a subset of the photons (global map only).
    pub irradiance: Option<super::irradiance::IrradianceMap>,
    /// Precomputed exitance (flux leaving per unit area) of the subsurface exits at a subset
    /// of them (global map of a scene with subsurface materials only).
    pub exitance: Option<super::irradiance::IrradianceMap>,
    /// Photon paths emitted to fill the map (the tree's power scale is its inverse).
    pub emitted: u64,
    /// Seconds the kd-tree took to build (balance).
    pub build_seconds: f64,
}

impl PhotonMap {
    /// A map of `kind` holding `tree`, with no precomputed irradiance.
    pub fn from_tree(kind: MapKind, tree: PhotonTree) -> PhotonMap {
        PhotonMap {
            kind,
            tree,
            irradiance: None,
            exitance: None,
            emitted: 0,
            build_seconds: 0.0,
        }
    }

    /// Every photon's position, in the tree's order.
    pub fn positions(&self) -> Vec<Vec3> {
        with_tree!(&self.tree, t => t.photons().iter().map(KdRecord::position).collect())
    }

    pub fn len(&self) -> usize {
        self.tree.len()
    }
    pub fn is_empty(&self) -> bool {
        self.tree.is_empty()
    }
    /// The photons' memory and the precomputed irradiance points'.
    pub fn memory_bytes(&self) -> usize {
        self.tree.memory_bytes()
            + self.irradiance.as_ref().map_or(0, |m| m.memory_bytes())
            + self.exitance.as_ref().map_or(0, |m| m.memory_bytes())
    }
    /// Bytes per stored photon: 20 (RGBE power) or 28 (`f32` power).
    pub fn bytes_per_photon(&self) -> usize {
        self.tree.bytes_per_photon()
    }

    /// Calls `f(power, incoming direction, user flags, distance²)` for the photons of a k-nearest estimate at `p`
    /// on the disc of normal `n` ([`on_disc`])
    /// (the k-th, on the boundary, left out) and returns the estimate's squared radius; None
    /// when no photon is within `max_r2`.
    pub fn for_each_nearest(
        &self,
        p: Vec3,
        k: usize,
        max_r2: f32,
        scratch: &mut KnnScratch,
        n: Vec3,
        f: impl FnMut(Spectrum, Vec3, u16, f32),
    ) -> Option<f32> {
        with_tree!(&self.tree, t, s => for_each_nearest_in(t, s, p, k, max_r2, scratch, n, f))
    }

    /// Reflected radiance at `p` towards `wo` (Jensen 2001, eq. 7.6):
    /// L = sum_p f(wo, wi_p) Phi_p / (pi r^2), over the `k` nearest photons within `max_r2`,
    /// counting only photons that arrived on the side of `n` (the side `wo` is on) and carry
    /// the user flags `select` takes. `share` receives each light group's share.
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
        select: Select,
        scratch: &mut KnnScratch,
        share: Option<GroupShare>,
    ) -> Spectrum {
        with_tree!(&self.tree, t, s => radiance_in(t, s, p, n, wo, bsdf, k, max_r2, filter, select, scratch, share))
    }

    /// In-scattered radiance at `x` towards `wo` from a volume map (Jensen & Christensen 1998):
    /// sum_p p(wo, wi_p) Phi_p / (4/3 pi r^3), with the k-th photon bounding the sphere, and
    /// the sphere's squared radius r^2; None when no photon is within `max_r2`. The estimate
    /// takes the whole sphere as medium; where part of it is not (past a boundary or inside an
    /// object), the caller divides by the part that is. `share` receives each light group's
    /// share.
    #[allow(clippy::too_many_arguments)]
    pub fn volume_radiance(
        &self,
        x: Vec3,
        wo: Vec3,
        phase: &crate::media::HenyeyGreenstein,
        k: usize,
        max_r2: f32,
        scratch: &mut KnnScratch,
        share: Option<GroupShare>,
    ) -> Option<(Spectrum, f32)> {
        with_tree!(&self.tree, t, s => volume_radiance_in(t, s, x, wo, phase, k, max_r2, scratch, share))
    }

    /// Total power of the photons flagged as first hits (for the energy test).
    pub fn first_hit_power(&self) -> Spectrum {
        with_tree!(&self.tree, t, s => t
            .photons()
            .iter()
            .filter(|p| p.user_flags() & FLAG_FIRST_HIT != 0)
            .map(|p| p.power() * s)
            .sum())
    }
}
