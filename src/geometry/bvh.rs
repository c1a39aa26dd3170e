//! Generic binary bounding volume hierarchy over primitives given by their bounds (after
//! pbrt-v4 §7.3, `BVHAggregate`): flattened 32-byte nodes, siblings stored side by side in
//! one 64-byte line and sibling pairs in depth-first order; a stack-based traversal tests
//! both children together and visits the nearer first. The builder is in
//! [`super::bvh_build`].
//!
//! The acceleration structure traces rays through the 4-wide form of the same tree
//! ([`super::bvh_wide`]), whose walk reproduces this one leaf for leaf; this form is the
//! reference it is tested against. The box test and the per-ray constants here are shared
//! by both.

use super::float::gamma;
use crate::math::Bounds3;
use glam::Vec3;

/// One node of a flattened BVH, 32 bytes.
///
/// | field | meaning |
/// |-------|---------|
/// | `min`, `max` | bounds of everything below the node |
/// | `offset` | leaf: index of the first entry in [`Bvh::prims`]; interior: index of the [`NodePair`] holding its two children |
/// | `count` | number of primitives in a leaf; 0 for an interior node |
/// | `axis` | split axis of an interior node (0 = x, 1 = y, 2 = z); informative, traversal orders children by entry distance |
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub struct BvhNode {
    pub min: Vec3,
    pub offset: u32,
    pub max: Vec3,
    pub count: u16,
    pub axis: u8,
    pub pad: u8,
}

const _: () = assert!(std::mem::size_of::<BvhNode>() == 32);

impl BvhNode {
    /// Bounds of the node.
    #[inline]
    pub fn bounds(&self) -> Bounds3 {
        Bounds3 {
            min: self.min,
            max: self.max,
        }
    }
}

/// The two children of an interior node, side by side in one 64-byte cache line, so
/// that testing both costs one memory access.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(64))]
pub struct NodePair(pub [BvhNode; 2]);

const _: () = assert!(std::mem::size_of::<NodePair>() == 64);

/// Depth of the traversal stack. The builder bounds the tree depth well below this.
pub(crate) const STACK_DEPTH: usize = 128;

/// A flattened BVH. Node `i` is `pairs[i / 2].0[i % 2]`; the root is node 0 (its slot
/// partner is unused) and sibling pairs follow in depth-first order. `prims` lists
/// primitive indices in leaf order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    pub pairs: Vec<NodePair>,
    pub prims: Vec<u32>,
}

/// Per-ray constants for box tests.
///
/// | field | meaning |
/// |-------|---------|
/// | `o` | ray origin |
/// | `inv_d` | component-wise `1/d` (infinite where `d` is zero) |
/// | `neg` | whether each component of `inv_d` is negative (so `-0.0` counts as negative) |
#[derive(Clone, Copy, Debug)]
pub struct BoxRay {
    pub o: Vec3,
    pub inv_d: Vec3,
    pub neg: [bool; 3],
}

impl BoxRay {
    #[inline]
    pub fn new(o: Vec3, d: Vec3) -> Self {
        // The sign of 1/d, not of d, so that a -0.0 component (1/d = -inf) is negative.
        let inv_d = Vec3::ONE / d;
        BoxRay {
            o,
            inv_d,
            neg: [inv_d.x < 0.0, inv_d.y < 0.0, inv_d.z < 0.0],
        }
    }
}

/// `max(a, b)` where a NaN `a` is ignored (compiles to a single `maxss`).
#[inline(always)]
fn max_nan_a(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

/// `min(a, b)` where a NaN `a` is ignored.
#[inline(always)]
fn min_nan_a(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

/// Slab test of `node` against the ray; see [`hit_bounds`].
#[inline(always)]
fn hit_box(node: &BvhNode, r: &BoxRay, t_max: f32) -> f32 {
    hit_bounds(node.min, node.max, r, t_max)
}

/// Slab test of the box `min..max` against the ray; conservative under rounding (the far
/// distance is scaled by 1 + 2γ₃ as in pbrt-v4 §6.8.2) and when a slab computation yields
/// NaN. Returns the entry distance when the box is hit, else `f32::INFINITY`.
#[inline(always)]
pub(crate) fn hit_bounds(min: Vec3, max: Vec3, r: &BoxRay, t_max: f32) -> f32 {
    let (nx, fx) = if r.neg[0] {
        (max.x, min.x)
    } else {
        (min.x, max.x)
    };
    let (ny, fy) = if r.neg[1] {
        (max.y, min.y)
    } else {
        (min.y, max.y)
    };
    let (nz, fz) = if r.neg[2] {
        (max.z, min.z)
    } else {
        (min.z, max.z)
    };
    let t0x = (nx - r.o.x) * r.inv_d.x;
    let t0y = (ny - r.o.y) * r.inv_d.y;
    let t0z = (nz - r.o.z) * r.inv_d.z;
    let t1x = (fx - r.o.x) * r.inv_d.x;
    let t1y = (fy - r.o.y) * r.inv_d.y;
    let t1z = (fz - r.o.z) * r.inv_d.z;
    let t0 = max_nan_a(t0x, max_nan_a(t0y, max_nan_a(t0z, 0.0)));
    let t1 = min_nan_a(t1x, min_nan_a(t1y, min_nan_a(t1z, t_max)));
    if t0 <= t1 * ROBUST_SCALE {
        t0
    } else {
        f32::INFINITY
    }
}

/// 1 + 2γ₃: the factor on the far slab distance that makes the box test conservative.
pub(crate) const ROBUST_SCALE: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

impl Bvh {
    /// True when the hierarchy holds no primitive.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// Node `i`, if it exists.
    #[inline(always)]
    pub fn node(&self, i: usize) -> Option<&BvhNode> {
        self.pairs.get(i >> 1).map(|p| &p.0[i & 1])
    }

    /// Bounds of the root (empty for an empty hierarchy).
    pub fn bounds(&self) -> Bounds3 {
        self.node(0).map(|n| n.bounds()).unwrap_or(Bounds3::EMPTY)
    }

    /// Walks the nodes hit by a ray, nearer child first: both children of an interior
    /// node are tested, the nearer (by entry distance) is visited and the farther is
    /// pushed with its entry distance, and skipped when popped if a closer hit was found
    /// meanwhile.
    ///
    /// | parameter | meaning |
    /// |-----------|---------|
    /// | `r` | per-ray box-test constants |
    /// | `t_max` | current search distance; `leaf` shrinks it when it finds a closer hit |
    /// | `leaf` | called as `leaf(first, count, &mut t_max)` for each leaf hit, with the range of [`Bvh::prims`] it holds; returns `true` to stop the walk (any-hit queries) |
    ///
    /// Returns `true` when `leaf` stopped the walk.
    #[inline(always)]
    pub fn traverse<F>(&self, r: &BoxRay, t_max: &mut f32, mut leaf: F) -> bool
    where
        F: FnMut(usize, usize, &mut f32) -> bool,
    {
        let Some(root) = self.node(0) else {
            return false;
        };
        if hit_box(root, r, *t_max) == f32::INFINITY {
            return false;
        }
        let mut stack = [(0u32, 0.0f32); STACK_DEPTH];
        let mut sp = 0usize;
        let mut current = 0usize;
        while let Some(node) = self.node(current) {
            if node.count > 0 {
                if leaf(node.offset as usize, node.count as usize, t_max) {
                    return true;
                }
            } else {
                let Some(NodePair([na, nb])) = self.pairs.get(node.offset as usize) else {
                    break;
                };
                let (a, b) = (2 * node.offset as usize, 2 * node.offset as usize + 1);
                let ta = hit_box(na, r, *t_max);
                let tb = hit_box(nb, r, *t_max);
                if ta != f32::INFINITY {
                    if tb != f32::INFINITY {
                        let (near, far, tf) = if tb < ta { (b, a, ta) } else { (a, b, tb) };
                        if sp < STACK_DEPTH {
                            stack[sp] = (far as u32, tf);
                            sp += 1;
                        }
                        current = near;
                    } else {
                        current = a;
                    }
                    continue;
                } else if tb != f32::INFINITY {
                    current = b;
                    continue;
                }
            }
            // Pop the next subtree that may still hold a closer hit.
            loop {
                if sp == 0 {
                    return false;
                }
                sp -= 1;
                let (i, t) = stack[sp];
                if t <= *t_max {
                    current = i as usize;
                    break;
                }
            }
        }
        false
    }
}

impl Bvh {
    /// Walks the leaves whose bounds overlap the box `q`, calling `leaf(first, count)` with
    /// the range of [`Bvh::prims`] each holds until it returns `true`. Returns whether it did.
    pub fn any_overlapping<F>(&self, q: &Bounds3, mut leaf: F) -> bool
    where
        F: FnMut(usize, usize) -> bool,
    {
        match self.node(0) {
            Some(root) if root.bounds().overlaps(q) => {}
            _ => return false,
        }
        let mut stack = [0u32; STACK_DEPTH];
        let mut sp = 0usize;
        let mut current = 0usize;
        loop {
            let Some(node) = self.node(current) else {
                return false;
            };
            if node.count > 0 {
                if leaf(node.offset as usize, node.count as usize) {
                    return true;
                }
            } else if let Some(NodePair([na, nb])) = self.pairs.get(node.offset as usize) {
                let (a, b) = (2 * node.offset as usize, 2 * node.offset as usize + 1);
                let (ha, hb) = (na.bounds().overlaps(q), nb.bounds().overlaps(q));
                if ha {
                    if hb && sp < STACK_DEPTH {
                        stack[sp] = b as u32;
                        sp += 1;
                    }
                    current = a;
                    continue;
                } else if hb {
                    current = b;
                    continue;
                }
            }
            if sp == 0 {
                return false;
            }
            sp -= 1;
            current = stack[sp] as usize;
        }
    }
}

/// Conservative world bounds of `b` under the affine map `m` (the eight corners, padded by
/// the rounding error of transforming them).
pub fn transform_bounds(m: &glam::Mat4, b: &Bounds3) -> Bounds3 {
    if b.is_empty() {
        return Bounds3::EMPTY;
    }
    let mut out = Bounds3::EMPTY;
    for i in 0..8 {
        let c = Vec3::new(
            if i & 1 == 0 { b.min.x } else { b.max.x },
            if i & 2 == 0 { b.min.y } else { b.max.y },
            if i & 4 == 0 { b.min.z } else { b.max.z },
        );
        let p = m.transform_point3(c);
        let err = super::interaction::transform_point_error(m, c, Vec3::ZERO);
        out.extend(p - err);
        out.extend(p + err);
    }
    let pad = out.min.abs().max(out.max.abs()) * gamma(1);
    Bounds3 {
        min: out.min - pad,
        max: out.max + pad,
    }
}
