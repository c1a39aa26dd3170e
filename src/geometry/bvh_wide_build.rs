//! Construction of a [`WideBvh`]: the binned SAH binary tree of [`super::bvh_build`], folded
//! two levels at a time into 4-wide nodes (layout in [`super::bvh_wide`]). The wide tree is
//! a function of the binary tree alone, so it too does not depend on the thread count.

use super::bvh_build::{build_tree, Node};
use super::bvh_wide::{WideBvh, WideNode, EMPTY_LANE, INTERIOR};
use super::huge_pages;
use crate::math::Bounds3;
use glam::Vec3;
use std::sync::atomic::AtomicBool;

impl WideBvh {
    /// Builds a 4-wide BVH over primitives `0..bounds.len()`; parameters as
    /// [`super::Bvh::build`], and the leaves are the binary BVH's.
    pub fn build(bounds: &[Bounds3], centroids: &[Vec3]) -> WideBvh {
        Self::build_cancellable(bounds, centroids, None).unwrap_or_default()
    }

    /// As [`WideBvh::build`], giving up (`None`) soon after `cancel` is set.
    pub fn build_cancellable(
        bounds: &[Bounds3],
        centroids: &[Vec3],
        cancel: Option<&AtomicBool>,
    ) -> Option<WideBvh> {
        let Some((root, prims)) = build_tree(bounds, centroids, cancel)? else {
            return Some(WideBvh::default());
        };
        let mut out = WideBvh {
            nodes: Vec::new(),
            prims,
            root: *root.bounds(),
            root_leaf: 0,
        };
        match &root {
            Node::Leaf { count, .. } => out.root_leaf = *count,
            Node::Inner { size, .. } => {
                out.nodes.reserve(*size as usize / 2 + 1);
                huge_pages::advise(&mut out.nodes);
                fold(&root, &mut out.nodes);
            }
        }
        Some(out)
    }
}

/// Appends the wide node of the interior binary node `n` and, depth first, those below it.
/// Returns its index.
fn fold(n: &Node, out: &mut Vec<WideNode>) -> u32 {
    let at = out.len();
    out.push(WideNode::default());
    let mut w = WideNode::default();
    if let Node::Inner { kids, .. } = n {
        for (g, half) in [&kids.0, &kids.1].into_iter().enumerate() {
            match half {
                Node::Leaf { .. } => set_lane(&mut w, 2 * g, half, out),
                Node::Inner { kids: gk, .. } => {
                    set_lane(&mut w, 2 * g, &gk.0, out);
                    set_lane(&mut w, 2 * g + 1, &gk.1, out);
                }
            }
        }
    }
    if let Some(slot) = out.get_mut(at) {
        *slot = w;
    }
    at as u32
}

/// Writes binary node `c` into lane `s` of `w`, folding its subtree when it is interior.
fn set_lane(w: &mut WideNode, s: usize, c: &Node, out: &mut Vec<WideNode>) {
    let b = c.bounds();
    for a in 0..3 {
        w.b[a][s] = b.min[a];
        w.b[a + 3][s] = b.max[a];
    }
    match c {
        Node::Leaf { first, count, .. } => {
            w.child[s] = *first;
            w.count[s] = *count;
            debug_assert!(*count != INTERIOR && *count != EMPTY_LANE);
        }
        Node::Inner { .. } => {
            w.child[s] = fold(c, out);
            w.count[s] = INTERIOR;
        }
    }
}
