//! The photon map: compact photon records and the left-balanced kd-tree that
//! stores them.
//!
//! This follows the photon map data structure of H. W. Jensen, *Realistic
//! Image Synthesis Using Photon Mapping* (2001), §6.4 and appendix B, and the
//! SIGGRAPH course notes *A Practical Guide to Global Illumination using
//! Photon Maps* (2000):
//!
//! * [`Photon`] is the 20-byte record (position, RGBE power, quantised
//!   incoming direction, split-axis flag); [`PhotonF32`] keeps the power in
//!   full `f32` precision for accuracy/memory comparisons. Both implement
//!   [`PhotonRecord`].
//! * [`PhotonKdTree`] is a left-balanced kd-tree stored as an implicit heap
//!   (`Vec<P>` and nothing else) with k-nearest-neighbour
//!   ([`PhotonKdTree::knn`]) and radius ([`PhotonKdTree::for_each_in_radius`])
//!   queries.

mod append;
pub mod irradiance;
pub mod kdtree;
mod kdtree_balance;
pub mod map;
#[allow(clippy::module_inception)]
pub mod photon;
pub mod trace;
pub mod volume_points;

pub use kdtree::{
    KnnScratch, Neighbor, PhotonKdTree, MAX_TREE_DEPTH, PARALLEL_BUILD_THRESHOLD, SCAN_LEVELS,
};
pub use photon::{
    decode_direction, direction_tables, encode_direction, encode_travel_direction, rgbe_decode,
    rgbe_encode, DirectionTables, KdRecord, Photon, PhotonF32, PhotonRecord, AXIS_MASK,
    DIRECTION_ERROR_BOUND, LEAF_AXIS, RGBE_MAX,
};

/// Errors raised when creating photon records.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum PhotonError {
    /// A power channel is negative, NaN or infinite.
    #[error("invalid photon power {0:?}: channels must be finite and non-negative")]
    InvalidPower([f32; 3]),
    /// A position coordinate is NaN or infinite.
    #[error("invalid photon position {0:?}: coordinates must be finite")]
    InvalidPosition([f32; 3]),
    /// The direction is zero-length, NaN or infinite and cannot be normalised.
    #[error("invalid photon direction {0:?}: must be finite and non-zero")]
    InvalidDirection([f32; 3]),
}
