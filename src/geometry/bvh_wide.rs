//! 4-wide BVH: the binary SAH tree of [`super::bvh_build`] with every other level folded
//! away, so that one 128-byte node holds the boxes of a binary node's four grandchildren
//! and one four-lane slab test ([`super::bvh_simd`]) replaces three binary box tests.
//!
//! # Layout
//!
//! A [`WideNode`] stands for a binary interior node `N` with children `A` and `B`. Lanes 0
//! and 1 hold `A`'s children and lanes 2 and 3 `B`'s; a child that is a leaf takes lane 0
//! (or 2) alone and leaves lane 1 (or 3) empty. The boxes are stored as six rows of four
//! (`min x, min y, min z, max x, max y, max z`), then the four child references and the
//! four leaf sizes: 96 + 16 + 16 bytes, two cache lines aligned to 128 bytes. Nodes are in
//! depth-first order, lane 0's subtree first; [`WideBvh::prims`] lists the primitives in
//! leaf order, so a leaf is a range of it.
//!
//! # Traversal order
//!
//! The walk visits leaves in exactly the order of the binary walk ([`super::Bvh::traverse`]):
//! the four lanes are tested at once; when both halves have lanes hit, the boxes of `A`
//! and `B` (the unions of lanes 0–1 and 2–3, two shuffles per row) are tested with the same
//! arithmetic, the nearer half is entered first and the farther is pushed with its entry
//! distance; inside a half, its two lanes are ordered the same way. Each lane's and each
//! half's entry distance and hit decision are bit for bit the scalar test's, the stack
//! holds the binary walk's entries (except halves that cannot lead to a leaf), and the
//! same `t_max` checks are made when popping, so the same leaves are tested with the same
//! `t_max`, and closest hits, ties included, are bit-identical to the binary BVH's (the
//! tests compare the two walks leaf by leaf).
//!
//! While a node is visited, the nodes and leaves its hit lanes lead to are prefetched.
//!
//! Both walks can return a hit an ulp or two farther than the closest one: a triangle in
//! the plane of its box's face can be hit slightly before the box's computed entry
//! distance, and the box is then skipped once a hit that near has been found elsewhere.

use super::bvh::{hit_bounds, BoxRay, STACK_DEPTH};
use super::bvh_simd::{pair_unions, prefetch, rows, WideRay};
use crate::math::Bounds3;
use glam::Vec3;
use std::mem::MaybeUninit;

/// `WideNode::count` of a lane that is an interior node.
pub const INTERIOR: u32 = 0;
/// `WideNode::count` of an empty lane (its box is empty).
pub const EMPTY_LANE: u32 = u32::MAX;

/// One node of a [`WideBvh`], 128 bytes.
///
/// | field | meaning |
/// |-------|---------|
/// | `b` | lane boxes as rows: `b[0..3]` minima in x, y, z, `b[3..6]` maxima; an empty lane has `+∞` minima and `−∞` maxima |
/// | `child` | interior lane: index of its node in [`WideBvh::nodes`]; leaf lane: first entry in [`WideBvh::prims`] |
/// | `count` | [`INTERIOR`], the number of primitives of a leaf, or [`EMPTY_LANE`] |
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(128))]
pub struct WideNode {
    pub b: [[f32; 4]; 6],
    pub child: [u32; 4],
    pub count: [u32; 4],
}

const _: () = assert!(std::mem::size_of::<WideNode>() == 128);

impl Default for WideNode {
    fn default() -> Self {
        WideNode {
            b: [
                [f32::INFINITY; 4],
                [f32::INFINITY; 4],
                [f32::INFINITY; 4],
                [f32::NEG_INFINITY; 4],
                [f32::NEG_INFINITY; 4],
                [f32::NEG_INFINITY; 4],
            ],
            child: [0; 4],
            count: [EMPTY_LANE; 4],
        }
    }
}

impl WideNode {
    /// Bounds of lane `i`.
    #[inline]
    pub fn lane_bounds(&self, i: usize) -> Bounds3 {
        Bounds3 {
            min: Vec3::new(self.b[0][i], self.b[1][i], self.b[2][i]),
            max: Vec3::new(self.b[3][i], self.b[4][i], self.b[5][i]),
        }
    }

    /// Whether the half `g` (0: lanes 0–1, 1: lanes 2–3) is a single leaf.
    #[inline(always)]
    fn half_is_leaf(&self, g: usize) -> bool {
        self.count[2 * g + 1] == EMPTY_LANE
    }
}

/// A 4-wide BVH (see the module documentation for the layout).
///
/// | field | meaning |
/// |-------|---------|
/// | `nodes` | wide nodes, the root first; empty when the root is a leaf |
/// | `prims` | primitive indices in leaf order |
/// | `root` | bounds of everything ([`Bounds3::EMPTY`] when empty) |
/// | `root_leaf` | number of primitives when the whole tree is one leaf, else 0 |
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WideBvh {
    pub nodes: Vec<WideNode>,
    pub prims: Vec<u32>,
    pub root: Bounds3,
    pub root_leaf: u32,
}

/// A traversal stack entry: what to visit, packed with a 3-bit tag.
///
/// | tag | meaning |
/// |-----|---------|
/// | 0–3 | the leaf in lane `tag` of node `index` |
/// | 4, 5 | half `tag − 4` of node `index` |
/// | 7 | node `index` |
#[derive(Clone, Copy)]
struct Item(u32);

const NODE_TAG: u32 = 7;

impl Item {
    #[inline(always)]
    fn node(i: u32) -> Item {
        Item((i << 3) | NODE_TAG)
    }
    #[inline(always)]
    fn half(i: u32, g: usize) -> Item {
        Item((i << 3) | (4 + g as u32))
    }
    #[inline(always)]
    fn lane(i: u32, s: usize) -> Item {
        Item((i << 3) | s as u32)
    }
}

impl WideBvh {
    /// True when the hierarchy holds no primitive.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.prims.is_empty()
    }

    /// Bounds of the root (empty for an empty hierarchy).
    pub fn bounds(&self) -> Bounds3 {
        if self.is_empty() {
            Bounds3::EMPTY
        } else {
            self.root
        }
    }

    /// Bytes held by the nodes and the primitive list.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<WideNode>() + self.prims.len() * 4
    }

    /// Walks the leaves hit by a ray, nearer subtree first, in the order of the binary walk
    /// (see the module documentation): farther subtrees are pushed with their entry
    /// distance and skipped when popped if a closer hit was found meanwhile.
    ///
    /// | parameter | meaning |
    /// |-----------|---------|
    /// | `r` | per-ray box-test constants |
    /// | `t_max` | current search distance; `leaf` shrinks it when it finds a closer hit |
    /// | `leaf` | called as `leaf(first, count, &mut t_max)` for each leaf hit, with the range of [`WideBvh::prims`] it holds; returns `true` to stop the walk (any-hit queries) |
    ///
    /// Returns `true` when `leaf` stopped the walk.
    #[inline(always)]
    pub fn traverse<F>(&self, r: &BoxRay, t_max: &mut f32, leaf: F) -> bool
    where
        F: FnMut(usize, usize, &mut f32) -> bool,
    {
        self.traverse_with_hint(r, t_max, |_, _| {}, leaf)
    }

    /// As [`WideBvh::traverse`], calling `hint(first, count)` as soon as a leaf's box is
    /// found hit, before the leaf is visited (or skipped, if a closer hit is found first),
    /// so that the caller can prefetch the leaf's data. Interior nodes pushed for later are
    /// prefetched the same way.
    #[inline(always)]
    pub fn traverse_with_hint<H, F>(
        &self,
        r: &BoxRay,
        t_max: &mut f32,
        hint: H,
        mut leaf: F,
    ) -> bool
    where
        H: Fn(usize, usize),
        F: FnMut(usize, usize, &mut f32) -> bool,
    {
        if self.is_empty() || hit_bounds(self.root.min, self.root.max, r, *t_max) == f32::INFINITY {
            return false;
        }
        if self.root_leaf > 0 {
            return leaf(0, self.root_leaf as usize, t_max);
        }
        let wr = WideRay::new(r);
        // Left uninitialised: the walk runs once per ray and BLAS, and zeroing 1 KiB each
        // time is measurable. Entries below `sp` are initialised.
        let mut stack = [const { MaybeUninit::<(Item, f32)>::uninit() }; STACK_DEPTH];
        let mut sp = 0usize;
        macro_rules! push {
            ($it:expr, $t:expr) => {
                if sp < STACK_DEPTH {
                    stack[sp] = MaybeUninit::new(($it, $t));
                    sp += 1;
                }
            };
        }
        let mut cur = Item::node(0);
        loop {
            let index = cur.0 >> 3;
            let tag = cur.0 & 7;
            let Some(n) = self.nodes.get(index as usize) else {
                return false;
            };
            // The half (binary node) to enter next, with its lanes' entry distances and hits.
            let mut enter: Option<(usize, [f32; 4], u32)> = None;
            if tag == NODE_TAG {
                let b = rows(&n.b);
                let (lt, lmask) = wr.test(&b, *t_max);
                // A half none of whose lanes is hit leads to no leaf (a lane's box lies
                // inside its half's, and the test is monotone in the box and in `t_max`).
                // When only one half has lanes hit, its box test would let it through, and
                // its entry distance (at most its hit lanes') is within `t_max`, the binary
                // walk enters it, now or right after the other half: the halves' boxes need
                // not be tested. Otherwise they are, and the binary walk is followed step by
                // step.
                let lts = lt.to_array();
                let one = match lmask & 0b1111 {
                    0 => None,
                    m if m & 0b1100 == 0 => Some(0),
                    m if m & 0b0011 == 0 => Some(1),
                    _ => None,
                };
                let within =
                    |g: usize| (2 * g..2 * g + 2).any(|s| lmask >> s & 1 == 1 && lts[s] <= *t_max);
                let g = match one {
                    Some(g) if within(g) => Some(g),
                    _ if lmask == 0 => None,
                    _ => {
                        let (gt, gmask) = wr.test(&pair_unions(&b), *t_max);
                        match gmask & 3 {
                            3 => {
                                let gt = gt.to_array();
                                let (near, far) = if gt[1] < gt[0] { (1, 0) } else { (0, 1) };
                                push!(Item::half(index, far), gt[far]);
                                Some(near)
                            }
                            1 => Some(0),
                            2 => Some(1),
                            _ => None,
                        }
                    }
                };
                if let Some(g) = g {
                    // Prefetch what the hit lanes lead to.
                    let mut m = lmask;
                    while m != 0 {
                        let s = m.trailing_zeros() as usize;
                        m &= m - 1;
                        if n.count[s] == INTERIOR {
                            prefetch(&self.nodes, n.child[s] as usize, 1);
                        } else if n.count[s] != EMPTY_LANE {
                            hint(n.child[s] as usize, n.count[s] as usize);
                        }
                    }
                    enter = Some((g, lts, lmask));
                }
            } else if tag >= 4 {
                let g = (tag - 4) as usize;
                if n.half_is_leaf(g) {
                    enter = Some((g, [0.0; 4], 0));
                } else {
                    let (lt, lmask) = wr.test(&rows(&n.b), *t_max);
                    enter = Some((g, lt.to_array(), lmask));
                }
            } else {
                let s = tag as usize;
                if leaf(n.child[s] as usize, n.count[s] as usize, t_max) {
                    return true;
                }
            }
            // Enter the half: a leaf is visited at once; an interior node's hit children
            // are taken nearer first.
            let mut next = None;
            if let Some((g, lt, lmask)) = enter {
                let (s0, s1) = (2 * g, 2 * g + 1);
                let lane = if n.half_is_leaf(g) {
                    Some(s0)
                } else {
                    match (lmask >> s0) & 3 {
                        3 => {
                            let (near, far) = if lt[s1] < lt[s0] { (s1, s0) } else { (s0, s1) };
                            let it = if n.count[far] == INTERIOR {
                                prefetch(&self.nodes, n.child[far] as usize, 1);
                                Item::node(n.child[far])
                            } else {
                                hint(n.child[far] as usize, n.count[far] as usize);
                                Item::lane(index, far)
                            };
                            push!(it, lt[far]);
                            Some(near)
                        }
                        1 => Some(s0),
                        2 => Some(s1),
                        _ => None,
                    }
                };
                if let Some(s) = lane {
                    if n.count[s] == INTERIOR {
                        next = Some(Item::node(n.child[s]));
                    } else if leaf(n.child[s] as usize, n.count[s] as usize, t_max) {
                        return true;
                    }
                }
            }
            if let Some(it) = next {
                cur = it;
                continue;
            }
            // Pop the next subtree that may still hold a closer hit.
            loop {
                if sp == 0 {
                    return false;
                }
                sp -= 1;
                // SAFETY: entries below the old `sp` were written by `push!`.
                let (it, t) = unsafe { stack[sp].assume_init() };
                if t <= *t_max {
                    cur = it;
                    break;
                }
            }
        }
    }

    /// Walks the leaves whose bounds overlap the box `q`, calling `leaf(first, count)` with
    /// the range of [`WideBvh::prims`] each holds until it returns `true`. Returns whether it did.
    pub fn any_overlapping<F>(&self, q: &Bounds3, mut leaf: F) -> bool
    where
        F: FnMut(usize, usize) -> bool,
    {
        if self.is_empty() || !self.root.overlaps(q) {
            return false;
        }
        if self.root_leaf > 0 {
            return leaf(0, self.root_leaf as usize);
        }
        // Up to three siblings are pushed per level.
        let mut stack = [0u32; 2 * STACK_DEPTH];
        let mut sp = 1usize;
        while sp > 0 {
            sp -= 1;
            let Some(n) = self.nodes.get(stack[sp] as usize) else {
                continue;
            };
            for s in 0..4 {
                if n.count[s] == EMPTY_LANE || !n.lane_bounds(s).overlaps(q) {
                    continue;
                }
                if n.count[s] != INTERIOR {
                    if leaf(n.child[s] as usize, n.count[s] as usize) {
                        return true;
                    }
                } else if sp < 2 * STACK_DEPTH {
                    stack[sp] = n.child[s];
                    sp += 1;
                }
            }
        }
        false
    }
}

#[cfg(test)]
#[path = "bvh_wide_tests.rs"]
mod tests;
