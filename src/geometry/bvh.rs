//! Generic bounding volume hierarchy over primitives given by their bounds: flattened
//! depth-first 32-byte nodes and a stack-based traversal that visits the child nearer
//! along the ray first (pbrt-v4 §7.3, `BVHAggregate`). The builder is in
//! [`super::bvh_build`].

use super::float::gamma;
use crate::math::Bounds3;
use glam::Vec3;

/// One node of a flattened BVH, 32 bytes.
///
/// | field | meaning |
/// |-------|---------|
/// | `min`, `max` | bounds of everything below the node |
/// | `offset` | leaf: index of the first entry in [`Bvh::prims`]; interior: index of the second child (the first child follows the node) |
/// | `count` | number of primitives in a leaf; 0 for an interior node |
/// | `axis` | split axis of an interior node (0 = x, 1 = y, 2 = z) |
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

/// Depth of the traversal stack. The builder bounds the tree depth well below this.
pub(crate) const STACK_DEPTH: usize = 128;

/// A flattened BVH. `prims` lists primitive indices in leaf order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    pub nodes: Vec<BvhNode>,
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

/// Slab test of `node` against the ray; conservative under rounding (the far distance is
/// scaled by 1 + 2γ₃ as in pbrt-v4 §6.8.2) and when a slab computation yields NaN.
#[inline(always)]
fn hit_box(node: &BvhNode, r: &BoxRay, t_max: f32) -> bool {
    let (nx, fx) = if r.neg[0] {
        (node.max.x, node.min.x)
    } else {
        (node.min.x, node.max.x)
    };
    let (ny, fy) = if r.neg[1] {
        (node.max.y, node.min.y)
    } else {
        (node.min.y, node.max.y)
    };
    let (nz, fz) = if r.neg[2] {
        (node.max.z, node.min.z)
    } else {
        (node.min.z, node.max.z)
    };
    let t0x = (nx - r.o.x) * r.inv_d.x;
    let t0y = (ny - r.o.y) * r.inv_d.y;
    let t0z = (nz - r.o.z) * r.inv_d.z;
    let t1x = (fx - r.o.x) * r.inv_d.x;
    let t1y = (fy - r.o.y) * r.inv_d.y;
    let t1z = (fz - r.o.z) * r.inv_d.z;
    let t0 = max_nan_a(t0x, max_nan_a(t0y, max_nan_a(t0z, 0.0)));
    let t1 = min_nan_a(t1x, min_nan_a(t1y, min_nan_a(t1z, t_max)));
    t0 <= t1 * ROBUST_SCALE
}

const ROBUST_SCALE: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

impl Bvh {
    /// True when the hierarchy holds no primitive.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Bounds of the root (empty for an empty hierarchy).
    pub fn bounds(&self) -> Bounds3 {
        self.nodes
            .first()
            .map(|n| n.bounds())
            .unwrap_or(Bounds3::EMPTY)
    }

    /// Walks the nodes hit by a ray, nearer child first.
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
        let nodes = &self.nodes[..];
        if nodes.is_empty() {
            return false;
        }
        let mut stack = [0u32; STACK_DEPTH];
        let mut sp = 0usize;
        let mut current = 0usize;
        loop {
            let Some(node) = nodes.get(current) else {
                break;
            };
            if hit_box(node, r, *t_max) {
                if node.count > 0 {
                    if leaf(node.offset as usize, node.count as usize, t_max) {
                        return true;
                    }
                } else {
                    let (near, far) = if r.neg[(node.axis & 3).min(2) as usize] {
                        (node.offset as usize, current + 1)
                    } else {
                        (current + 1, node.offset as usize)
                    };
                    if sp < STACK_DEPTH {
                        stack[sp] = far as u32;
                        sp += 1;
                    }
                    current = near;
                    continue;
                }
            }
            if sp == 0 {
                break;
            }
            sp -= 1;
            current = stack[sp] as usize;
        }
        false
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
