//! Balancing a photon array into the left-balanced kd-tree heap, in place.
//!
//! Jensen, *Realistic Image Synthesis Using Photon Mapping* (2001), appendix
//! B (`balance`, `balance_segment`), in two steps that hold no second copy of
//! the photons:
//!
//! 1. **Selection, in place** ([`balance_in_order`]). Each subset is split on
//!    the axis of largest extent of its bounding box at the left-balanced
//!    median, the rank that gives the left subtree the size of the left
//!    sub-heap, found with `select_nth_unstable_by` (O(len)). The median stays
//!    where the selection leaves it, between its two halves, which are then
//!    balanced the same way (in parallel above [`PARALLEL_BUILD_THRESHOLD`]).
//!    When the recursion ends the array holds the tree in *in-order* (the
//!    left subtree, the node, the right subtree, recursively), with every
//!    record's split axis set.
//! 2. **In-order to heap order, in place** ([`in_order_to_heap`]). The
//!    in-order position of every heap node has a closed form
//!    ([`in_order_position`]), so the array is permuted by following the
//!    permutation's cycles, with one bit per photon to mark the records
//!    already placed (1/160 of the 20-byte records).
//!
//! The selections are the same, on the same subsets in the same order, as
//! when the medians were copied out into a second heap array, so the tree is
//! the same record for record.

use std::sync::atomic::{AtomicBool, Ordering};

use glam::Vec3A;

use super::kdtree::prefetch;
use super::photon::{KdRecord, LEAF_AXIS};

/// Subsets at least this large balance their two halves with `rayon::join`.
pub const PARALLEL_BUILD_THRESHOLD: usize = 50_000;

/// Rank (0-based) of the left-balanced median in a subset of `len ≥ 1`
/// records: the number of nodes in the left sub-heap of a complete binary
/// tree of `len` nodes. Jensen 2001, appendix B, `balance_segment`.
#[inline]
pub(crate) fn left_balanced_median(len: usize) -> usize {
    debug_assert!(len >= 1);
    let mut median = 1usize;
    while 4 * median <= len {
        median += median;
    }
    if 3 * median <= len {
        2 * median - 1
    } else {
        len - median
    }
}

/// Number of heap nodes in the subtree rooted at `node` of a heap of `n`.
#[cfg(test)]
pub(crate) fn subtree_size(node: usize, n: usize) -> usize {
    let (mut lo, mut hi, mut count) = (node, node, 0);
    while lo < n {
        count += hi.min(n - 1) - lo + 1;
        lo = 2 * lo + 1;
        hi = 2 * hi + 2;
    }
    count
}

/// In-order position of heap node `j` (0-based) in a left-balanced tree of
/// `n > j` nodes.
///
/// With 1-based `i = j + 1` at depth `d = ⌊log₂ i⌋`, `i = 2^d + c`, and the
/// deepest level `h = ⌊log₂ n⌋` holding `last = n − (2^h − 1)` nodes: in the
/// perfect tree of depth `h` the node sits at `p = (2c + 1)·2^(h−d) − 1`,
/// after `⌈p/2⌉` slots of the deepest level (the even positions), of which
/// all but the first `last` are absent. So the position is
/// `p − max(0, ⌈p/2⌉ − last)`.
#[inline(always)]
pub(crate) fn in_order_position(j: usize, n: usize) -> usize {
    let i = j + 1;
    let d = usize::BITS - 1 - i.leading_zeros();
    let h = usize::BITS - 1 - n.leading_zeros();
    let c = i - (1usize << d);
    let last = n - ((1usize << h) - 1);
    let p = ((2 * c + 1) << (h - d)) - 1;
    p - (p.div_ceil(2)).saturating_sub(last)
}

#[inline]
fn widest_axis<P: KdRecord>(seg: &[P]) -> usize {
    let first = Vec3A::from_array(*seg[0].pos());
    let (lo, hi) = seg[1..].iter().fold((first, first), |(lo, hi), p| {
        let v = Vec3A::from_array(*p.pos());
        (lo.min(v), hi.max(v))
    });
    let e = hi - lo;
    if e.x >= e.y && e.x >= e.z {
        0
    } else if e.y >= e.z {
        1
    } else {
        2
    }
}

/// Positions are finite by construction (the record constructors reject
/// NaN and infinities), so plain comparisons give a total order.
#[inline(always)]
fn coord_less(a: f32, b: f32) -> std::cmp::Ordering {
    if a < b {
        std::cmp::Ordering::Less
    } else if a > b {
        std::cmp::Ordering::Greater
    } else {
        std::cmp::Ordering::Equal
    }
}

/// `select_nth_unstable_by` on one coordinate, monomorphised per axis.
#[inline]
fn select_on_axis<P: KdRecord>(seg: &mut [P], m: usize, axis: usize) {
    match axis {
        0 => seg.select_nth_unstable_by(m, |a, b| coord_less(a.pos()[0], b.pos()[0])),
        1 => seg.select_nth_unstable_by(m, |a, b| coord_less(a.pos()[1], b.pos()[1])),
        _ => seg.select_nth_unstable_by(m, |a, b| coord_less(a.pos()[2], b.pos()[2])),
    };
}

/// Step 1: arranges `seg` as its left-balanced tree in in-order, every
/// record's split axis set ([`LEAF_AXIS`] on leaves). Jensen 2001, appendix
/// B, `balance_segment`, with selection in place of his `median_split`.
///
/// With a `cancel` flag, subsets of at least [`PARALLEL_BUILD_THRESHOLD`]
/// records read it and, once it is set, return at once after setting
/// `aborted` (the array is then a permutation of the input, of no use).
pub(crate) fn balance_in_order<P: KdRecord>(
    seg: &mut [P],
    cancel: Option<(&AtomicBool, &AtomicBool)>,
) {
    let len = seg.len();
    if len == 0 {
        return;
    }
    if let Some((flag, aborted)) = cancel {
        if len >= PARALLEL_BUILD_THRESHOLD && flag.load(Ordering::Relaxed) {
            aborted.store(true, Ordering::Relaxed);
            return;
        }
    }
    if len == 1 {
        // A one-record subset always lands on a heap leaf.
        seg[0].set_axis(LEAF_AXIS);
        return;
    }
    let axis = widest_axis(seg);
    let m = left_balanced_median(len);
    select_on_axis(seg, m, axis);
    seg[m].set_axis(axis as u8);
    let (left, rest) = seg.split_at_mut(m);
    let right = &mut rest[1..];
    if len >= PARALLEL_BUILD_THRESHOLD {
        rayon::join(
            || balance_in_order(left, cancel),
            || balance_in_order(right, cancel),
        );
    } else {
        balance_in_order(left, cancel);
        balance_in_order(right, cancel);
    }
}

/// How many cycle steps ahead the permutation prefetches its source record:
/// the next sources are known from arithmetic alone, so their cache misses
/// can overlap.
const PREFETCH_AHEAD: usize = 8;

/// Step 2: permutes a tree stored in in-order into heap order (node `j` at
/// index `j`, children `2j + 1` and `2j + 2`), in place: heap slot `j`
/// takes the record at [`in_order_position`]`(j)`. Follows each cycle of
/// the permutation once; a bit per slot marks the slots already filled.
pub(crate) fn in_order_to_heap<P: Copy>(a: &mut [P]) {
    let n = a.len();
    let mut placed = vec![0u64; n.div_ceil(64)];
    let is_placed = |placed: &[u64], j: usize| placed[j / 64] >> (j % 64) & 1 == 1;
    for start in 0..n {
        if is_placed(&placed, start) {
            continue;
        }
        let src = in_order_position(start, n);
        placed[start / 64] |= 1 << (start % 64);
        if src == start {
            continue;
        }
        let first = a[start];
        let (mut cur, mut src) = (start, src);
        let mut ahead = src;
        for _ in 0..PREFETCH_AHEAD {
            ahead = in_order_position(ahead, n);
        }
        // Each slot in the cycle takes its source's record; the last takes
        // the record first lifted out of `start`.
        while src != start {
            prefetch(a, ahead);
            ahead = in_order_position(ahead, n);
            a[cur] = a[src];
            placed[src / 64] |= 1 << (src % 64);
            cur = src;
            src = in_order_position(cur, n);
        }
        a[cur] = first;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The in-order position of every node, by walking the tree.
    fn in_order_by_walk(n: usize) -> Vec<usize> {
        fn walk(j: usize, n: usize, next: &mut usize, pos: &mut [usize]) {
            if j >= n {
                return;
            }
            walk(2 * j + 1, n, next, pos);
            pos[j] = *next;
            *next += 1;
            walk(2 * j + 2, n, next, pos);
        }
        let mut pos = vec![0; n];
        walk(0, n, &mut 0, &mut pos);
        pos
    }

    #[test]
    fn in_order_position_matches_a_walk() {
        for n in (1..1200).chain([4095, 4096, 4097, 6000, 65_535, 65_536, 100_003]) {
            let want = in_order_by_walk(n);
            for (j, &w) in want.iter().enumerate() {
                assert_eq!(in_order_position(j, n), w, "n {n} j {j}");
            }
        }
    }

    #[test]
    fn permutation_puts_each_in_order_record_on_its_heap_slot() {
        for n in (0..300).chain([1023, 1024, 1025, 77_777]) {
            let mut a: Vec<usize> = (0..n).collect();
            in_order_to_heap(&mut a);
            for (j, &v) in a.iter().enumerate() {
                assert_eq!(v, in_order_position(j, n), "n {n} j {j}");
            }
        }
    }
}
