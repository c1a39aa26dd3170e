//! Photon maps (Jensen 2001, chapter 7): a kd-tree of photons and the radiance estimate.

use super::{KdRecord, KnnScratch, Neighbor, Photon, PhotonF32, PhotonKdTree, PhotonRecord};
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
/// (`PhotonSettings::f32_power`), which trades memory for the RGBE quantisation (≤ 1/256 of a
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

/// [`PhotonMap::radiance`] over one kind of photon record.
#[allow(clippy::too_many_arguments)]
#[inline]
fn radiance_in<P: PhotonRecord>(
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

/// [`PhotonMap::for_each_nearest`] over one kind of photon record.
#[inline]
fn for_each_nearest_in<P: PhotonRecord>(
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

/// [`PhotonMap::volume_radiance`] over one kind of photon record.
#[inline]
fn volume_radiance_in<P: PhotonRecord>(
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
