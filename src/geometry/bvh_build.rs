//! Binned SAH construction of a [`Bvh`] (Wald 2007, "On fast Construction of SAH-based
//! Bounding Volume Hierarchies"; pbrt-v4 §7.3.2).
//!
//! | parameter | value |
//! |-----------|-------|
//! | bins per axis | [`BINS`], all three axes are tried |
//! | leaf size | at most [`MAX_LEAF`]; smaller nodes become leaves when the SAH says so |
//! | SAH costs | traversal [`TRAVERSAL_COST`], intersection 1 per primitive |
//! | degenerate nodes | all centroids equal, or no useful SAH split: split in the middle of the list |
//! | depth | SAH splits stop at depth [`SAH_MAX_DEPTH`]; below, middle splits keep the tree shallower than the traversal stack |
//! | parallelism | subtrees larger than [`PARALLEL_THRESHOLD`] are built with `rayon::join`; the tree does not depend on the thread count |
//! | cancel | [`Bvh::build_cancellable`] reads a cancel flag at every node of more than [`PARALLEL_THRESHOLD`] primitives |

use super::bvh::{Bvh, BvhNode, NodePair};
use crate::math::Bounds3;
use glam::Vec3;
use std::sync::atomic::{AtomicBool, Ordering};

pub const BINS: usize = 16;
pub const MAX_LEAF: usize = 8;
pub const TRAVERSAL_COST: f32 = 2.0;
pub const SAH_MAX_DEPTH: u32 = 64;
pub const PARALLEL_THRESHOLD: usize = 8192;

#[derive(Clone, Copy, Debug)]
struct Prim {
    min: Vec3,
    max: Vec3,
    c: Vec3,
    index: u32,
}

/// The binary tree as built, before it is flattened ([`Bvh`]) or collapsed into 4-wide
/// nodes ([`super::bvh_wide::WideBvh`]). A node's bounds are exactly the union of its
/// children's.
pub(super) enum Node {
    Leaf {
        b: Bounds3,
        first: u32,
        count: u32,
    },
    Inner {
        b: Bounds3,
        axis: u8,
        kids: Box<(Node, Node)>,
        size: u32,
    },
}

impl Node {
    /// Bounds of the subtree.
    pub(super) fn bounds(&self) -> &Bounds3 {
        match self {
            Node::Leaf { b, .. } | Node::Inner { b, .. } => b,
        }
    }

    /// Number of nodes in the subtree.
    pub(super) fn size(&self) -> u32 {
        match self {
            Node::Leaf { .. } => 1,
            Node::Inner { size, .. } => *size,
        }
    }
}

impl Bvh {
    /// Builds a BVH over primitives `0..bounds.len()`.
    ///
    /// | parameter | meaning |
    /// |-----------|---------|
    /// | `bounds` | bounds of each primitive; primitives with empty or non-finite bounds are left out |
    /// | `centroids` | the point each primitive is sorted by (usually the bounds centre); missing entries use the bounds centre |
    pub fn build(bounds: &[Bounds3], centroids: &[Vec3]) -> Bvh {
        Self::build_cancellable(bounds, centroids, None).unwrap_or_default()
    }

    /// As [`Bvh::build`], giving up (`None`) soon after `cancel` is set.
    pub fn build_cancellable(
        bounds: &[Bounds3],
        centroids: &[Vec3],
        cancel: Option<&AtomicBool>,
    ) -> Option<Bvh> {
        let Some((root, prims)) = build_tree(bounds, centroids, cancel)? else {
            return Some(Bvh::default());
        };
        let mut pairs = Vec::with_capacity(root.size() as usize / 2 + 1);
        pairs.push(NodePair::default());
        flatten(&root, &mut pairs, 0);
        Some(Bvh { pairs, prims })
    }
}

/// Builds the binary tree over primitives `0..bounds.len()` (parameters as [`Bvh::build`]).
/// Returns `None` when cancelled, `Some(None)` when no primitive has usable bounds, else the
/// root and the primitive indices in leaf order.
pub(super) fn build_tree(
    bounds: &[Bounds3],
    centroids: &[Vec3],
    cancel: Option<&AtomicBool>,
) -> Option<Option<(Node, Vec<u32>)>> {
    let mut prims: Vec<Prim> = bounds
        .iter()
        .enumerate()
        .filter(|(_, b)| !b.is_empty() && b.min.is_finite() && b.max.is_finite())
        .map(|(i, b)| {
            let c = centroids
                .get(i)
                .copied()
                .filter(|c| c.is_finite())
                .unwrap_or_else(|| b.center());
            Prim {
                min: b.min,
                max: b.max,
                c,
                index: i as u32,
            }
        })
        .collect();
    if prims.is_empty() {
        return Some(None);
    }
    let root = build_rec(&mut prims, 0, 0, cancel);
    if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
        return None;
    }
    Some(Some((root, prims.iter().map(|p| p.index).collect())))
}

/// Writes `n` as node `at` and, for an interior node, appends its children as a pair and
/// recurses into them (depth-first order of pairs).
fn flatten(n: &Node, out: &mut Vec<NodePair>, at: usize) {
    let node = match n {
        Node::Leaf { b, first, count } => BvhNode {
            min: b.min,
            max: b.max,
            offset: *first,
            count: *count as u16,
            axis: 0,
            pad: 0,
        },
        Node::Inner { b, axis, .. } => BvhNode {
            min: b.min,
            max: b.max,
            offset: out.len() as u32,
            count: 0,
            axis: *axis,
            pad: 0,
        },
    };
    if let Some(p) = out.get_mut(at >> 1) {
        p.0[at & 1] = node;
    }
    if let Node::Inner { kids, .. } = n {
        let pair = out.len();
        out.push(NodePair::default());
        flatten(&kids.0, out, 2 * pair);
        flatten(&kids.1, out, 2 * pair + 1);
    }
}

#[derive(Clone, Copy)]
struct Bin {
    b: Bounds3,
    n: u32,
}

impl Default for Bin {
    fn default() -> Self {
        Bin {
            b: Bounds3::EMPTY,
            n: 0,
        }
    }
}

#[inline]
fn bin_of(c: f32, lo: f32, scale: f32) -> usize {
    let f = (c - lo) * scale;
    // Casting saturates (NaN to 0); clamp the top end.
    (f as usize).min(BINS - 1)
}

/// Best SAH split: (axis, last bin of the left side, cost relative to the node's area).
fn best_split(prims: &[Prim], cb: &Bounds3, node_area: f32) -> Option<(usize, usize, f32)> {
    let ext = cb.max - cb.min;
    let mut scale = [0.0f32; 3];
    for a in 0..3 {
        if ext[a] > 0.0 {
            scale[a] = BINS as f32 / ext[a];
            if !scale[a].is_finite() {
                scale[a] = 0.0;
            }
        }
    }
    let mut bins = [[Bin::default(); BINS]; 3];
    for p in prims {
        let pb = Bounds3 {
            min: p.min,
            max: p.max,
        };
        for a in 0..3 {
            if scale[a] > 0.0 {
                let bin = &mut bins[a][bin_of(p.c[a], cb.min[a], scale[a])];
                bin.b = bin.b.union(&pb);
                bin.n += 1;
            }
        }
    }
    let mut best: Option<(usize, usize, f32)> = None;
    for a in 0..3 {
        if scale[a] == 0.0 {
            continue;
        }
        let bins = &bins[a];
        // Right-to-left sweep of areas times counts.
        let mut right = [0.0f32; BINS];
        let mut acc = Bounds3::EMPTY;
        let mut n = 0u32;
        for i in (1..BINS).rev() {
            acc = acc.union(&bins[i].b);
            n += bins[i].n;
            right[i] = if n > 0 {
                acc.surface_area() * n as f32
            } else {
                f32::INFINITY
            };
        }
        let mut acc = Bounds3::EMPTY;
        let mut n = 0u32;
        for i in 0..BINS - 1 {
            acc = acc.union(&bins[i].b);
            n += bins[i].n;
            if n == 0 {
                continue;
            }
            let cost = acc.surface_area() * n as f32 + right[i + 1];
            if cost.is_finite() && best.map_or(true, |(_, _, c)| cost < c) {
                best = Some((a, i, cost));
            }
        }
    }
    best.map(|(a, i, c)| {
        let rel = if node_area > 0.0 { c / node_area } else { 0.0 };
        (a, i, TRAVERSAL_COST + rel)
    })
}

/// Partitions so that prims with `pred` come first; returns how many do.
fn partition(prims: &mut [Prim], pred: impl Fn(&Prim) -> bool) -> usize {
    let mut i = 0;
    let mut j = prims.len();
    loop {
        while i < j && pred(&prims[i]) {
            i += 1;
        }
        while i < j && !pred(&prims[j - 1]) {
            j -= 1;
        }
        if i >= j {
            return i;
        }
        prims.swap(i, j - 1);
        i += 1;
        j -= 1;
    }
}

fn build_rec(prims: &mut [Prim], first: u32, depth: u32, cancel: Option<&AtomicBool>) -> Node {
    let mut b = Bounds3::EMPTY;
    let mut cb = Bounds3::EMPTY;
    for p in prims.iter() {
        b.min = b.min.min(p.min);
        b.max = b.max.max(p.max);
        cb.extend(p.c);
    }
    let n = prims.len();
    let leaf = Node::Leaf {
        b,
        first,
        count: n as u32,
    };
    if n <= 1 {
        return leaf;
    }
    // Cancelled: stop splitting (the caller throws the tree away).
    if n > PARALLEL_THRESHOLD && cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
        return leaf;
    }
    let split = if depth < SAH_MAX_DEPTH {
        best_split(prims, &cb, b.surface_area())
    } else {
        None
    };
    let (axis, mid) = match split {
        Some((axis, bin, cost)) => {
            if n <= MAX_LEAF && cost >= n as f32 {
                return leaf;
            }
            let ext = cb.max[axis] - cb.min[axis];
            let scale = BINS as f32 / ext;
            let lo = cb.min[axis];
            let m = partition(prims, |p| bin_of(p.c[axis], lo, scale) <= bin);
            if m == 0 || m == n {
                (axis, n / 2)
            } else {
                (axis, m)
            }
        }
        None => {
            if n <= MAX_LEAF {
                return leaf;
            }
            (b.max_extent_axis(), n / 2)
        }
    };
    let (l, r) = prims.split_at_mut(mid);
    let (left, right) = if n > PARALLEL_THRESHOLD {
        rayon::join(
            || build_rec(l, first, depth + 1, cancel),
            || build_rec(r, first + mid as u32, depth + 1, cancel),
        )
    } else {
        (
            build_rec(l, first, depth + 1, cancel),
            build_rec(r, first + mid as u32, depth + 1, cancel),
        )
    };
    let size = 1 + left.size() + right.size();
    Node::Inner {
        b,
        axis: axis as u8,
        kids: Box::new((left, right)),
        size,
    }
}

#[cfg(test)]
#[path = "bvh_tests.rs"]
mod tests;
