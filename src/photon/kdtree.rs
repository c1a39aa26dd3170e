//! Left-balanced kd-tree over photon records, stored as an implicit heap.
//!
//! Jensen, *Realistic Image Synthesis Using Photon Mapping* (2001), §6.4 and
//! appendix B (`balance`, `balance_segment`, `locate_photons`):
//!
//! * The tree is a complete ("left-balanced") binary tree laid out as a heap:
//!   with 1-based numbering node `i` has children `2i` and `2i + 1`. Here the
//!   array is 0-based, so node `j` (= `i − 1`) has children `2j + 1` and
//!   `2j + 2`. No pointers and no index array are kept: the tree is exactly a
//!   `Vec<P>` (20 bytes per [`Photon`](super::Photon)); each record's flag
//!   stores its split axis in two bits.
//! * Because the shape is fixed by `n`, the depth is `⌊log₂ n⌋ + 1` whatever
//!   the point distribution (coincident, coplanar, collinear points
//!   included), so the recursive build has O(log n) depth and the queries a
//!   fixed-size stack.
//! * Each subset is split on the axis of largest extent of its bounding box,
//!   at the left-balanced median (the rank that gives the left subtree the
//!   size of the left sub-heap), found with `select_nth_unstable_by`
//!   (expected and worst-case O(len)), so the build is O(n log n). The two
//!   halves are built in parallel above [`PARALLEL_BUILD_THRESHOLD`]. The
//!   build works in place, in the photons' own `Vec` (`kdtree_balance`).
//! * Records equal to the median on the split axis may end up on either
//!   side; the queries descend into the far side whenever the squared
//!   distance to the splitting plane is ≤ the current search radius, which
//!   keeps them exact in the presence of ties.

use glam::Vec3;
use std::sync::atomic::{AtomicBool, Ordering};

pub use super::kdtree_balance::PARALLEL_BUILD_THRESHOLD;
use super::kdtree_balance::{balance_in_order, in_order_to_heap};
#[cfg(test)]
use super::kdtree_balance::{left_balanced_median, subtree_size};
use super::photon::KdRecord;
#[cfg(test)]
use super::photon::LEAF_AXIS;

/// Size of the fixed traversal stack. A left-balanced tree over `n < 2^32`
/// records has depth ≤ 32, and the stack never holds more than one entry per
/// level, so 64 is ample.
pub const MAX_TREE_DEPTH: usize = 64;

/// Subtrees spanning at most this many levels (≤ 2^SCAN_LEVELS − 1 photons,
/// stored as `SCAN_LEVELS` contiguous runs of the heap array) are scanned
/// linearly by the queries instead of being traversed node by node: fewer
/// unpredictable branches and sequential memory access. Must be ≥ 2 so that
/// every traversed node has both children.
pub const SCAN_LEVELS: u32 = 4;
const _: () = assert!(SCAN_LEVELS >= 2);

/// One result of a k-nearest query: index into [`PhotonKdTree::photons`]
/// and squared distance to the query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Neighbor {
    /// Index of the photon in [`PhotonKdTree::photons`].
    pub index: u32,
    /// Squared distance from the query point.
    pub dist2: f32,
}

/// Reusable storage for [`PhotonKdTree::knn`]: the candidate buffer (up to
/// `2k` entries). It grows to the largest `k` used and is then reused, so
/// the queries do not allocate.
#[derive(Clone, Debug, Default)]
pub struct KnnScratch {
    heap: Vec<Neighbor>,
}

impl KnnScratch {
    /// Empty scratch; grows on first use.
    pub fn new() -> Self {
        Self::default()
    }

    /// Scratch pre-sized for queries with up to `k` neighbours.
    pub fn with_capacity(k: usize) -> Self {
        KnnScratch {
            heap: Vec::with_capacity(2 * k),
        }
    }
}

/// A left-balanced kd-tree of photon records in heap order (see the module
/// documentation).
#[derive(Clone, Debug)]
pub struct PhotonKdTree<P> {
    nodes: Vec<P>,
}

impl<P> Default for PhotonKdTree<P> {
    fn default() -> Self {
        PhotonKdTree { nodes: Vec::new() }
    }
}

#[inline(always)]
fn dist2(q: &[f32; 3], p: &[f32; 3]) -> f32 {
    let dx = q[0] - p[0];
    let dy = q[1] - p[1];
    let dz = q[2] - p[2];
    dx * dx + dy * dy + dz * dz
}

/// Squared distance from the query to a subtree's cell, from the query's offsets to the
/// cell's nearest splitting plane along each axis (0 where none lies between them; Arya and
/// Mount's incremental distance). Summed in the order of [`dist2`]: every offset is at most
/// the matching coordinate difference of every photon in the cell, and rounding is monotonic,
/// so this never exceeds a photon's own computed `dist2` and pruning on it is exact.
#[inline(always)]
fn cell_dist2(off: &[f32; 3]) -> f32 {
    off[0] * off[0] + off[1] * off[1] + off[2] * off[2]
}

/// Keeps the `k` nearest of `buf` (at positions `0..k`, the k-th nearest
/// at `k − 1`) and drops the rest. Linear time.
#[inline]
fn select_k(buf: &mut Vec<Neighbor>, k: usize) {
    buf.select_nth_unstable_by(k - 1, |a, b| a.dist2.total_cmp(&b.dist2));
    buf.truncate(k);
}

#[inline]
fn farthest_dist2(buf: &[Neighbor]) -> f32 {
    buf.iter().fold(0.0f32, |m, nb| m.max(nb.dist2))
}

impl<P: KdRecord> PhotonKdTree<P> {
    /// Builds the left-balanced tree from `photons`, in place: the tree is
    /// the same `Vec`, reordered into heap order (see `kdtree_balance`), so
    /// the build holds no second copy of the photons (one bit per photon
    /// besides). O(n log n); parallel above [`PARALLEL_BUILD_THRESHOLD`].
    ///
    /// Every record's split-axis bits are overwritten; the other flag bits
    /// are preserved.
    ///
    /// # Panics
    /// If there are more than `u32::MAX` photons (indices are `u32`).
    pub fn build(photons: Vec<P>) -> Self {
        let mut nodes = photons;
        assert!(
            nodes.len() <= u32::MAX as usize,
            "photon kd-tree holds at most u32::MAX photons"
        );
        balance_in_order(&mut nodes, None);
        in_order_to_heap(&mut nodes);
        nodes.shrink_to_fit();
        PhotonKdTree { nodes }
    }

    /// As [`PhotonKdTree::build`], giving up (`None`) soon after `cancel` is set: subsets
    /// of at least [`PARALLEL_BUILD_THRESHOLD`] records read it. The tree, when built, is
    /// the same.
    pub fn build_cancellable(photons: Vec<P>, cancel: &AtomicBool) -> Option<Self> {
        let mut nodes = photons;
        assert!(
            nodes.len() <= u32::MAX as usize,
            "photon kd-tree holds at most u32::MAX photons"
        );
        let aborted = AtomicBool::new(false);
        balance_in_order(&mut nodes, Some((cancel, &aborted)));
        if aborted.load(Ordering::Relaxed) {
            return None;
        }
        in_order_to_heap(&mut nodes);
        nodes.shrink_to_fit();
        Some(PhotonKdTree { nodes })
    }

    /// A tree of records already in heap order with their split axes set, as
    /// [`PhotonKdTree::photons`] gives them (a saved tree read back).
    pub fn from_heap(nodes: Vec<P>) -> Self {
        PhotonKdTree { nodes }
    }

    /// Number of photons.
    #[inline]
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// True when the tree holds no photon.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The photons in heap order (index `j` has children `2j+1`, `2j+2`).
    #[inline]
    pub fn photons(&self) -> &[P] {
        &self.nodes
    }

    /// The photon a [`Neighbor`] refers to.
    #[inline]
    pub fn get(&self, index: u32) -> &P {
        &self.nodes[index as usize]
    }

    /// Gives the heap-ordered photons back.
    pub fn into_photons(self) -> Vec<P> {
        self.nodes
    }

    /// Depth of the tree: `⌊log₂ n⌋ + 1` (0 when empty).
    pub fn depth(&self) -> usize {
        (usize::BITS - self.nodes.len().leading_zeros()) as usize
    }

    /// Heap memory held by the tree: `len · size_of::<P>()` (the `Vec` is
    /// allocated with exact capacity).
    pub fn memory_bytes(&self) -> usize {
        self.nodes.capacity() * std::mem::size_of::<P>()
    }

    /// First heap index whose subtree spans at most [`SCAN_LEVELS`] levels:
    /// node `j` qualifies when its first descendant `SCAN_LEVELS` levels
    /// down, `(j + 1)·2^SCAN_LEVELS − 1`, is past the end.
    #[inline]
    fn scan_start(&self) -> usize {
        (self.nodes.len() + 1).div_ceil(1 << SCAN_LEVELS) - 1
    }

    /// The `k` photons nearest to `p` within squared distance `max_dist2`
    /// (inclusive), as Jensen's `locate_photons` (2001, appendix B) but
    /// with a select-based candidate buffer in place of the max-heap (see
    /// below), traversed iteratively with a fixed stack; the
    /// bottom [`SCAN_LEVELS`] levels of each subtree are scanned linearly.
    ///
    /// Returns a slice of `scratch`: at most `k` entries, in no particular
    /// order, except that when exactly `k` entries are returned
    /// `result[0].dist2` is the largest (the squared radius of the density
    /// estimate). Among photons at equal distance the choice is
    /// unspecified. `k == 0`, an empty tree, or a negative/NaN `max_dist2`
    /// give an empty result; `max_dist2 = ∞` means unbounded.
    pub fn knn<'s>(
        &self,
        p: Vec3,
        k: usize,
        max_dist2: f32,
        scratch: &'s mut KnnScratch,
    ) -> &'s [Neighbor] {
        let heap = &mut scratch.heap;
        heap.clear();
        let nodes = &self.nodes[..];
        let n = nodes.len();
        if k == 0 || n == 0 || max_dist2.is_nan() || max_dist2 < 0.0 {
            return heap;
        }
        let k = k.min(n);
        heap.reserve(2 * k);
        let q = p.to_array();
        let scan_start = self.scan_start();
        let mut max_d2 = max_dist2;
        // Far children wait on the stack with the offsets of the query from their cell
        // along each axis and the squared distance to the cell (`cell_dist2`).
        let mut stack = [(0u32, 0f32, [0f32; 3]); MAX_TREE_DEPTH];
        let mut sp = 0usize;
        let mut node = 0usize;
        let mut off = [0f32; 3];

        // Candidate insertion. Instead of a binary max-heap (Jensen's
        // `locate_photons`), candidates are appended to a buffer of up to 2k
        // entries; when it fills, a linear-time selection keeps the k nearest
        // and the search radius shrinks to the k-th distance. This is O(1)
        // amortised per candidate rather than O(log k), with the same
        // pruning bound at the time of each selection. The first time k
        // candidates are held, the radius also shrinks to their maximum.
        #[inline(always)]
        fn insert(buf: &mut Vec<Neighbor>, k: usize, max_d2: &mut f32, nb: Neighbor) {
            buf.push(nb);
            if buf.len() == k {
                *max_d2 = farthest_dist2(buf).min(*max_d2);
            } else if buf.len() == 2 * k {
                select_k(buf, k);
                *max_d2 = buf[k - 1].dist2;
            }
        }

        'search: loop {
            loop {
                if node >= scan_start {
                    // Small subtree: its levels are contiguous runs of the
                    // heap array; check every photon without pruning.
                    let (mut lo, mut width) = (node, 1usize);
                    while lo < n {
                        let hi = (lo + width).min(n);
                        for (i, ph) in nodes[lo..hi].iter().enumerate() {
                            let d2 = dist2(&q, ph.pos());
                            if d2 <= max_d2 {
                                let index = (lo + i) as u32;
                                insert(heap, k, &mut max_d2, Neighbor { index, dist2: d2 });
                            }
                        }
                        lo = 2 * lo + 1;
                        width *= 2;
                    }
                    break;
                }
                // Interior node with both children present (node < scan_start
                // implies at least SCAN_LEVELS ≥ 2 levels below it).
                let ph = &nodes[node];
                let pos = ph.pos();
                prefetch(nodes, 4 * node + 3);
                let d2 = dist2(&q, pos);
                if d2 <= max_d2 {
                    let index = node as u32;
                    insert(heap, k, &mut max_d2, Neighbor { index, dist2: d2 });
                }
                let axis = ph.axis() as usize;
                let delta = q[axis] - pos[axis];
                let go_right = (delta >= 0.0) as usize;
                let left = 2 * node + 1;
                let mut far_off = off;
                far_off[axis] = delta;
                let dd = cell_dist2(&far_off);
                if dd <= max_d2 {
                    stack[sp] = ((left + 1 - go_right) as u32, dd, far_off);
                    sp += 1;
                }
                node = left + go_right;
            }
            // Resume at the deepest pending far child still in range.
            loop {
                if sp == 0 {
                    break 'search;
                }
                sp -= 1;
                let (far, dd, far_off) = stack[sp];
                if dd <= max_d2 {
                    node = far as usize;
                    off = far_off;
                    break;
                }
            }
        }
        if heap.len() > k {
            select_k(heap, k);
        }
        if heap.len() == k {
            // Farthest first: `result[0].dist2` is the estimate's radius².
            let far = (0..k).fold(0, |m, i| if heap[i].dist2 > heap[m].dist2 { i } else { m });
            heap.swap(0, far);
        }
        heap
    }

    /// Calls `visitor(photon, dist2)` for every photon within squared
    /// distance `r2` (inclusive) of `p`, in traversal order. `r2 = ∞` visits
    /// everything; a negative or NaN `r2` visits nothing.
    pub fn for_each_in_radius(&self, p: Vec3, r2: f32, mut visitor: impl FnMut(&P, f32)) {
        let nodes = &self.nodes[..];
        let n = nodes.len();
        if n == 0 || r2.is_nan() || r2 < 0.0 {
            return;
        }
        let q = p.to_array();
        let scan_start = self.scan_start();
        let mut stack = [(0u32, [0f32; 3]); MAX_TREE_DEPTH];
        let mut sp = 0usize;
        let mut node = 0usize;
        let mut off = [0f32; 3];
        loop {
            loop {
                if node >= scan_start {
                    let (mut lo, mut width) = (node, 1usize);
                    while lo < n {
                        let hi = (lo + width).min(n);
                        for ph in &nodes[lo..hi] {
                            let d2 = dist2(&q, ph.pos());
                            if d2 <= r2 {
                                visitor(ph, d2);
                            }
                        }
                        lo = 2 * lo + 1;
                        width *= 2;
                    }
                    break;
                }
                let ph = &nodes[node];
                let pos = ph.pos();
                prefetch(nodes, 4 * node + 3);
                let d2 = dist2(&q, pos);
                if d2 <= r2 {
                    visitor(ph, d2);
                }
                let axis = ph.axis() as usize;
                let delta = q[axis] - pos[axis];
                let go_right = (delta >= 0.0) as usize;
                let left = 2 * node + 1;
                // The radius is fixed, so pruned children are never pushed.
                let mut far_off = off;
                far_off[axis] = delta;
                if cell_dist2(&far_off) <= r2 {
                    stack[sp] = ((left + 1 - go_right) as u32, far_off);
                    sp += 1;
                }
                node = left + go_right;
            }
            if sp == 0 {
                return;
            }
            sp -= 1;
            (node, off) = (stack[sp].0 as usize, stack[sp].1);
        }
    }
}

/// Hints the cache to load `nodes[i]` (no-op when out of range or not on
/// x86-64).
#[inline(always)]
pub(super) fn prefetch<P>(nodes: &[P], i: usize) {
    #[cfg(target_arch = "x86_64")]
    if i < nodes.len() {
        // SAFETY: prefetching is a hint with no memory effects, and the
        // address is in bounds.
        unsafe {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            _mm_prefetch::<_MM_HINT_T0>(nodes.as_ptr().add(i) as *const i8);
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (nodes, i);
}

impl<P: KdRecord> FromIterator<P> for PhotonKdTree<P> {
    fn from_iter<I: IntoIterator<Item = P>>(iter: I) -> Self {
        Self::build(iter.into_iter().collect())
    }
}

#[cfg(test)]
mod tests {
    use super::super::photon::{Photon, PhotonF32};
    use super::*;

    struct Rng(u64);
    impl Rng {
        fn next_u64(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }
        fn f32(&mut self) -> f32 {
            (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
        }
        fn below(&mut self, n: u64) -> u64 {
            self.next_u64() % n
        }
        fn vec3(&mut self) -> Vec3 {
            Vec3::new(self.f32(), self.f32(), self.f32())
        }
    }

    fn make<P: KdRecord>(
        pts: &[Vec3],
        ctor: fn(Vec3, Vec3, Vec3) -> Result<P, crate::photon::PhotonError>,
    ) -> Vec<P> {
        pts.iter()
            .enumerate()
            .map(|(i, &p)| ctor(p, Vec3::splat(i as f32 + 1.0), Vec3::new(0.2, 0.3, -1.0)).unwrap())
            .collect()
    }

    /// Checks the heap shape and the split invariant: every record in the
    /// left subtree is ≤ the node on its axis, every record in the right ≥.
    fn check_invariants<P: KdRecord>(tree: &PhotonKdTree<P>) {
        let nodes = tree.photons();
        let n = nodes.len();
        for (j, p) in nodes.iter().enumerate() {
            let leaf = 2 * j + 1 >= n;
            assert_eq!(p.axis() == LEAF_AXIS, leaf, "axis flag at {j}");
            if leaf {
                continue;
            }
            let a = p.axis() as usize;
            let v = p.pos()[a];
            let mut stack = vec![(2 * j + 1, true)];
            if 2 * j + 2 < n {
                stack.push((2 * j + 2, false));
            }
            while let Some((c, is_left)) = stack.pop() {
                let w = nodes[c].pos()[a];
                if is_left {
                    assert!(w <= v, "left {w} > {v}");
                } else {
                    assert!(w >= v, "right {w} < {v}");
                }
                for cc in [2 * c + 1, 2 * c + 2] {
                    if cc < n {
                        stack.push((cc, is_left));
                    }
                }
            }
        }
    }

    fn brute_knn<P: KdRecord>(pts: &[P], q: Vec3, k: usize, max_d2: f32) -> Vec<f32> {
        let qa = q.to_array();
        let mut d: Vec<f32> = pts
            .iter()
            .map(|p| dist2(&qa, p.pos()))
            .filter(|&d| d <= max_d2)
            .collect();
        d.sort_by(f32::total_cmp);
        d.truncate(k);
        d
    }

    fn compare<P: KdRecord + std::fmt::Debug>(
        pts: &[P],
        queries: &[Vec3],
        ks: &[usize],
        r2s: &[f32],
    ) {
        let tree = PhotonKdTree::build(pts.to_vec());
        assert_eq!(tree.len(), pts.len());
        check_invariants(&tree);
        let mut scratch = KnnScratch::new();
        for &q in queries {
            for &r2 in r2s {
                for &k in ks {
                    let res = tree.knn(q, k, r2, &mut scratch);
                    let mut got: Vec<f32> = res.iter().map(|nb| nb.dist2).collect();
                    for nb in res {
                        let d = dist2(&q.to_array(), tree.get(nb.index).pos());
                        assert_eq!(d, nb.dist2);
                    }
                    if res.len() == k && k > 0 {
                        let m = got.iter().copied().fold(f32::MIN, f32::max);
                        assert_eq!(res[0].dist2, m, "root is the farthest");
                    }
                    got.sort_by(f32::total_cmp);
                    assert_eq!(got, brute_knn(pts, q, k, r2), "knn q={q} k={k} r2={r2}");
                }
                let mut got = Vec::new();
                tree.for_each_in_radius(q, r2, |p, d2| {
                    assert_eq!(dist2(&q.to_array(), p.pos()), d2);
                    got.push((d2, p.pos().map(f32::to_bits)));
                });
                got.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                let qa = q.to_array();
                let mut want: Vec<_> = pts
                    .iter()
                    .map(|p| (dist2(&qa, p.pos()), p.pos().map(f32::to_bits)))
                    .filter(|x| x.0 <= r2)
                    .collect();
                want.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                assert_eq!(got, want, "radius q={q} r2={r2}");
            }
        }
    }

    fn both(pts: &[Vec3], queries: &[Vec3], ks: &[usize], r2s: &[f32]) {
        compare(&make(pts, Photon::new), queries, ks, r2s);
        compare(&make(pts, PhotonF32::new), queries, ks, r2s);
    }

    const KS: &[usize] = &[0, 1, 2, 7, 50, 100, 5000];
    const R2S: &[f32] = &[0.0, 0.001, 0.01, 0.05, f32::INFINITY];

    #[test]
    fn left_balanced_median_matches_heap_shape() {
        let large = (11..34).flat_map(|b| {
            let p = 1usize << b;
            [p - 1, p, p + 1, p + p / 2, p + p / 4 - 1, 3 * (p / 4) + 7]
        });
        for len in (1..5000).chain(large) {
            let m = left_balanced_median(len);
            assert_eq!(m, subtree_size(1, len), "len {len}");
        }
    }

    #[test]
    fn empty_and_tiny() {
        let mut s = KnnScratch::new();
        let t: PhotonKdTree<Photon> = PhotonKdTree::build(Vec::new());
        assert!(t.is_empty());
        assert_eq!(t.depth(), 0);
        assert!(t.knn(Vec3::ZERO, 10, f32::INFINITY, &mut s).is_empty());
        let mut count = 0;
        t.for_each_in_radius(Vec3::ZERO, f32::INFINITY, |_, _| count += 1);
        assert_eq!(count, 0);

        let one = make(&[Vec3::new(1.0, 2.0, 3.0)], Photon::new);
        let t = PhotonKdTree::build(one);
        assert_eq!(t.depth(), 1);
        assert_eq!(t.photons()[0].axis(), LEAF_AXIS);
        assert!(t.knn(Vec3::ZERO, 0, f32::INFINITY, &mut s).is_empty());
        assert_eq!(t.knn(Vec3::ZERO, 5, f32::INFINITY, &mut s).len(), 1);
        assert_eq!(t.knn(Vec3::ZERO, 5, 14.0, &mut s).len(), 1);
        assert!(t.knn(Vec3::ZERO, 5, 13.9, &mut s).is_empty());
        assert!(t.knn(Vec3::ZERO, 5, -1.0, &mut s).is_empty());
        assert!(t.knn(Vec3::ZERO, 5, f32::NAN, &mut s).is_empty());
        assert_eq!(t.knn(Vec3::new(1.0, 2.0, 3.0), 5, 0.0, &mut s).len(), 1);
        let mut count = 0;
        t.for_each_in_radius(Vec3::new(1.0, 2.0, 3.0), 0.0, |_, _| count += 1);
        t.for_each_in_radius(Vec3::ZERO, f32::NAN, |_, _| count += 100);
        assert_eq!(count, 1);
        for n in 2..40 {
            let mut rng = Rng(n as u64 + 1);
            let pts: Vec<Vec3> = (0..n).map(|_| rng.vec3()).collect();
            let qs: Vec<Vec3> = (0..5).map(|_| rng.vec3()).collect();
            both(&pts, &qs, KS, R2S);
        }
    }

    #[test]
    fn random_uniform() {
        let mut rng = Rng(7);
        let pts: Vec<Vec3> = (0..20_000).map(|_| rng.vec3()).collect();
        let qs: Vec<Vec3> = (0..30)
            .map(|_| rng.vec3() * 1.2 - Vec3::splat(0.1))
            .collect();
        both(&pts, &qs, KS, R2S);
    }

    #[test]
    fn clustered() {
        let mut rng = Rng(11);
        let centres: Vec<Vec3> = (0..8).map(|_| rng.vec3()).collect();
        let pts: Vec<Vec3> = (0..20_000)
            .map(|_| {
                let c = centres[rng.below(8) as usize];
                c + (rng.vec3() - Vec3::splat(0.5)) * 0.01
            })
            .collect();
        let mut qs = centres.clone();
        qs.extend((0..10).map(|_| rng.vec3()));
        both(&pts, &qs, KS, &[0.0, 1e-5, 1e-4, 0.01, f32::INFINITY]);
    }

    #[test]
    fn coplanar_floor() {
        let mut rng = Rng(3);
        let pts: Vec<Vec3> = (0..20_000)
            .map(|_| Vec3::new(rng.f32() * 10.0, 0.25, rng.f32() * 10.0))
            .collect();
        let qs: Vec<Vec3> = (0..20)
            .map(|_| {
                Vec3::new(
                    rng.f32() * 10.0,
                    0.25 + (rng.f32() - 0.5) * 0.1,
                    rng.f32() * 10.0,
                )
            })
            .collect();
        both(&pts, &qs, KS, &[0.0, 0.01, 0.1, 1.0, f32::INFINITY]);
    }

    #[test]
    fn integer_grid_ties() {
        // A lattice: many photons at exactly equal distances from lattice
        // and half-lattice queries, and equal coordinates on every axis.
        let mut pts = Vec::new();
        for x in 0..12 {
            for y in 0..12 {
                for z in 0..12 {
                    pts.push(Vec3::new(x as f32, y as f32, z as f32));
                }
            }
        }
        let qs = [
            Vec3::new(5.0, 5.0, 5.0),
            Vec3::new(5.5, 5.5, 5.5),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(5.5, 3.0, 11.0),
            Vec3::new(-1.0, 6.0, 6.0),
        ];
        both(
            &pts,
            &qs,
            &[1, 6, 7, 19, 27, 33, 100],
            &[0.0, 1.0, 2.0, 3.0, 4.0, 25.0],
        );
    }

    #[test]
    fn coincident_collinear_duplicates() {
        let coincident = vec![Vec3::new(1.0, -2.0, 0.5); 3000];
        let qs = [
            Vec3::new(1.0, -2.0, 0.5),
            Vec3::new(1.0, -2.0, 0.6),
            Vec3::ZERO,
        ];
        both(
            &coincident,
            &qs,
            &[0, 1, 50, 3000, 4000],
            &[0.0, 0.01, f32::INFINITY],
        );

        let mut rng = Rng(5);
        let collinear: Vec<Vec3> = (0..5000)
            .map(|_| Vec3::new(1.0, 2.0, 3.0) + Vec3::new(0.3, -0.2, 0.9) * rng.f32())
            .collect();
        let qs: Vec<Vec3> = (0..10)
            .map(|_| Vec3::new(1.0, 2.0, 3.0) + rng.vec3())
            .collect();
        both(&collinear, &qs, KS, R2S);

        // Axis-aligned line: extent 0 on two axes.
        let line: Vec<Vec3> = (0..3000)
            .map(|i| Vec3::new(0.0, (i % 97) as f32, 0.0))
            .collect();
        both(
            &line,
            &[Vec3::new(0.0, 10.0, 0.0), Vec3::new(1.0, 50.5, 0.0)],
            KS,
            &[0.0, 1.0, 4.0, f32::INFINITY],
        );

        // Heavy duplicates: 40 distinct sites, each 100 times.
        let sites: Vec<Vec3> = (0..40).map(|_| rng.vec3()).collect();
        let dups: Vec<Vec3> = (0..4000).map(|i| sites[i % 40]).collect();
        let mut qs = sites[..5].to_vec();
        qs.push(Vec3::splat(0.5));
        both(&dups, &qs, &[1, 99, 100, 101, 250, 4000], R2S);
    }

    #[test]
    fn large_degenerate_builds_stay_fast() {
        // Parallel build path (above the threshold) on coincident and
        // coplanar inputs; depth is fixed by the heap shape.
        let n = 300_000;
        let t = PhotonKdTree::build(make(&vec![Vec3::ONE; n], Photon::new));
        assert_eq!(t.depth(), 19);
        check_invariants(&t);
        let mut s = KnnScratch::new();
        let res = t.knn(Vec3::ONE, 50, 1.0, &mut s);
        assert_eq!(res.len(), 50);
        assert!(res.iter().all(|nb| nb.dist2 == 0.0));
        let mut rng = Rng(9);
        let floor: Vec<Vec3> = (0..n)
            .map(|_| Vec3::new(rng.f32(), rng.f32(), 0.0))
            .collect();
        compare(
            &make(&floor, Photon::new),
            &[Vec3::new(0.5, 0.5, 0.0), Vec3::new(0.1, 0.9, 0.01)],
            &[1, 50, 200],
            &[1e-4, 1e-3],
        );
    }

    #[test]
    fn memory_is_exactly_the_records() {
        let mut rng = Rng(1);
        let pts: Vec<Vec3> = (0..1000).map(|_| rng.vec3()).collect();
        let t = PhotonKdTree::build(make(&pts, Photon::new));
        assert_eq!(t.memory_bytes(), 1000 * 20);
        assert_eq!(
            std::mem::size_of::<PhotonKdTree<Photon>>(),
            std::mem::size_of::<Vec<Photon>>()
        );
        let t = PhotonKdTree::build(make(&pts, PhotonF32::new));
        assert_eq!(t.memory_bytes(), 1000 * 28);
    }

    #[test]
    fn build_preserves_records_and_user_flags() {
        let mut rng = Rng(2);
        let pts: Vec<Vec3> = (0..70_000).map(|_| rng.vec3()).collect();
        let mut photons = make(&pts, Photon::new);
        for (i, p) in photons.iter_mut().enumerate() {
            p.set_user_flags((i % 3) as u16);
        }
        let mut before: Vec<(u32, u32, u32, [u8; 4], u16)> = photons
            .iter()
            .map(|p| {
                let [x, y, z] = p.pos().map(f32::to_bits);
                (x, y, z, p.rgbe(), p.user_flags())
            })
            .collect();
        let t = PhotonKdTree::build(photons);
        let mut after: Vec<_> = t
            .photons()
            .iter()
            .map(|p| {
                let [x, y, z] = p.pos().map(f32::to_bits);
                (x, y, z, p.rgbe(), p.user_flags())
            })
            .collect();
        before.sort_unstable();
        after.sort_unstable();
        assert_eq!(before, after);
        check_invariants(&t);
    }
}
