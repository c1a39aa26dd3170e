//! Ray-scene intersection: rays, triangle meshes and instances, a watertight
//! ray-triangle test, a binned-SAH BVH folded into 4-wide nodes with SIMD box tests, the
//! two-level acceleration structure, and robust ray spawning from surface interactions
//! (pbrt-v4 §6.8).

mod accel;
mod bvh;
mod bvh_build;
mod bvh_simd;
mod bvh_wide;
mod bvh_wide_build;
mod float;
mod huge_pages;
mod interaction;
mod mesh;
mod ray;
pub mod shapes;
mod tangents;
mod triangle;

pub use accel::{Accel, Hit};
pub use bvh::{BoxRay, Bvh, BvhNode, NodePair};
pub use bvh_wide::{WideBvh, WideNode};
pub use float::{gamma, next_float_down, next_float_up, MACHINE_EPSILON};
pub use interaction::{
    offset_ray_origin, transform_point_error, RayPath, Scatter, SurfaceInteraction, SHADOW_EPSILON,
};
pub use mesh::{
    attribute_key, AttributeValues, Instance, MeshGeom, MAX_ATTRIBUTES, MAX_NAMED_ATTRIBUTES,
};
pub use ray::Ray;
pub use tangents::{
    vertex_tangents, TANGENT_ATTRIBUTE, TANGENT_KEY, TANGENT_NORMAL_ATTRIBUTE, TANGENT_NORMAL_KEY,
};
pub use triangle::{intersect_triangle, TriHit, TriRay};
