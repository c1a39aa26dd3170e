//! Lattice coordinates of 1 to 4 dimensions for the Voronoi texture: cells, their hashed
//! feature points and colours, and the distance metrics.

use super::{Params, VoronoiMetric};
use crate::materials::graph::tex::hash::{
    hash_float_to_float, hash_float_to_vec3, hash_ivec2_to_vec2, hash_ivec2_to_vec3,
    hash_ivec3_to_vec3, hash_ivec4_to_vec3, hash_ivec4_to_vec4,
};
use glam::{IVec2, IVec3, IVec4, Vec2, Vec3, Vec4};
use std::ops::{Add, Div, Mul, Sub};

/// A lattice coordinate of 1 to 4 dimensions.
pub(super) trait Point:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Sub<f32, Output = Self>
    + Mul<f32, Output = Self>
    + Div<f32, Output = Self>
{
    const DIM: u32;
    fn floor(self) -> Self;
    fn splat(v: f32) -> Self;
    /// Offset number `index` of the `(2r+1)^DIM` cells around the origin,
    /// first component varying fastest.
    fn cell(index: i32, r: i32) -> Self;
    /// Jitter of the feature point of cell `cell + offset` (`cell` is the
    /// floored coordinate, `offset` a small integral offset).
    fn hash_point(cell: Self, offset: Self) -> Self;
    /// Colour of cell `cell + offset`.
    fn hash_color(cell: Self, offset: Self) -> Vec3;
    fn metric_distance(self, other: Self, metric: VoronoiMetric, exponent: f32) -> f32;
    /// A monotonic function of `metric_distance`, cheaper to compute.
    fn metric_bound(self, other: Self, metric: VoronoiMetric, exponent: f32) -> f32;
    fn euclidean(self, other: Self) -> f32;
    /// A monotonic function of `euclidean`, cheaper to compute.
    fn euclidean_bound(self, other: Self) -> f32;
    fn dot(self, other: Self) -> f32;
    fn normalize(self) -> Self;
    fn position(self) -> Vec4;

    fn cells(r: i32) -> i32 {
        (2 * r + 1).pow(Self::DIM)
    }

    /// Distance to the closest cell edge (Inigo Quilez's two-pass method).
    fn distance_to_edge(p: &Params, coord: Self) -> f32 {
        let cell_position = coord.floor();
        let local = coord - cell_position;
        let to_point = |i| {
            let off = Self::cell(i, 1);
            off + Self::hash_point(cell_position, off) * p.randomness - local
        };
        let mut to_closest = Self::splat(0.0);
        let mut min_distance = f32::MAX;
        for i in 0..Self::cells(1) {
            let v = to_point(i);
            let d = v.dot(v);
            if d < min_distance {
                min_distance = d;
                to_closest = v;
            }
        }
        let mut min_distance = f32::MAX;
        for i in 0..Self::cells(1) {
            let v = to_point(i);
            let perpendicular = v - to_closest;
            if perpendicular.dot(perpendicular) > 0.0001 {
                let d = ((to_closest + v) / 2.0).dot(perpendicular.normalize());
                min_distance = min_distance.min(d);
            }
        }
        min_distance
    }
}

impl Point for f32 {
    const DIM: u32 = 1;
    fn floor(self) -> Self {
        f32::floor(self)
    }
    fn splat(v: f32) -> Self {
        v
    }
    fn cell(index: i32, r: i32) -> Self {
        (index - r) as f32
    }
    fn hash_point(cell: Self, offset: Self) -> Self {
        hash_float_to_float(cell + offset)
    }
    fn hash_color(cell: Self, offset: Self) -> Vec3 {
        hash_float_to_vec3(cell + offset)
    }
    fn metric_distance(self, other: Self, _: VoronoiMetric, _: f32) -> f32 {
        (other - self).abs()
    }
    fn metric_bound(self, other: Self, _: VoronoiMetric, _: f32) -> f32 {
        (other - self).abs()
    }
    fn euclidean(self, other: Self) -> f32 {
        (other - self).abs()
    }
    fn euclidean_bound(self, other: Self) -> f32 {
        (other - self).abs()
    }
    fn dot(self, other: Self) -> f32 {
        self * other
    }
    fn normalize(self) -> Self {
        self / self.abs()
    }
    fn position(self) -> Vec4 {
        Vec4::new(0.0, 0.0, 0.0, self)
    }
    fn distance_to_edge(p: &Params, coord: Self) -> f32 {
        let cell_position = coord.floor();
        let local = coord - cell_position;
        let mid = hash_float_to_float(cell_position) * p.randomness;
        let left = -1.0 + hash_float_to_float(cell_position - 1.0) * p.randomness;
        let right = 1.0 + hash_float_to_float(cell_position + 1.0) * p.randomness;
        let to_left = ((mid + left) / 2.0 - local).abs();
        let to_right = ((mid + right) / 2.0 - local).abs();
        to_left.min(to_right)
    }
}

macro_rules! vector_point {
    ($t:ty, $it:ty, $dim:tt, $hash_point:expr, $hash_color:expr, $pos:expr, $cell:expr) => {
        impl Point for $t {
            const DIM: u32 = $dim;
            fn floor(self) -> Self {
                <$t>::floor(self)
            }
            fn splat(v: f32) -> Self {
                <$t>::splat(v)
            }
            fn cell(index: i32, r: i32) -> Self {
                let n = 2 * r + 1;
                let c = |k: u32| ((index / n.pow(k)) % n - r) as f32;
                $cell(&c)
            }
            fn hash_point(cell: Self, offset: Self) -> Self {
                $hash_point(integer_cell::<$it, $dim>(
                    cell.to_array(),
                    offset.to_array(),
                ))
            }
            fn hash_color(cell: Self, offset: Self) -> Vec3 {
                $hash_color(integer_cell::<$it, $dim>(
                    cell.to_array(),
                    offset.to_array(),
                ))
            }
            fn metric_distance(self, other: Self, metric: VoronoiMetric, exponent: f32) -> f32 {
                let d = (self - other).abs();
                match metric {
                    VoronoiMetric::Euclidean => self.distance(other),
                    VoronoiMetric::Manhattan => d.element_sum(),
                    VoronoiMetric::Chebychev => d.max_element(),
                    VoronoiMetric::Minkowski => d
                        .to_array()
                        .iter()
                        .map(|c| c.powf(exponent))
                        .sum::<f32>()
                        .powf(1.0 / exponent),
                }
            }
            fn metric_bound(self, other: Self, metric: VoronoiMetric, exponent: f32) -> f32 {
                match metric {
                    VoronoiMetric::Euclidean => self.distance_squared(other),
                    VoronoiMetric::Minkowski => (self - other)
                        .abs()
                        .to_array()
                        .iter()
                        .map(|c| c.powf(exponent))
                        .sum::<f32>(),
                    m => self.metric_distance(other, m, exponent),
                }
            }
            fn euclidean(self, other: Self) -> f32 {
                self.distance(other)
            }
            fn euclidean_bound(self, other: Self) -> f32 {
                self.distance_squared(other)
            }
            fn dot(self, other: Self) -> f32 {
                <$t>::dot(self, other)
            }
            fn normalize(self) -> Self {
                self / self.length()
            }
            fn position(self) -> Vec4 {
                $pos(self)
            }
        }
    };
}

/// The integer cell `cell + offset` of floored coordinates `cell`.
#[inline]
fn integer_cell<I: From<[i32; N]>, const N: usize>(cell: [f32; N], offset: [f32; N]) -> I {
    I::from(std::array::from_fn(|k| {
        (cell[k] as i32).wrapping_add(offset[k] as i32)
    }))
}

vector_point!(
    Vec2,
    IVec2,
    2,
    hash_ivec2_to_vec2,
    hash_ivec2_to_vec3,
    |v: Vec2| Vec4::new(v.x, v.y, 0.0, 0.0),
    |c: &dyn Fn(u32) -> f32| Vec2::new(c(0), c(1))
);
vector_point!(
    Vec3,
    IVec3,
    3,
    hash_ivec3_to_vec3,
    hash_ivec3_to_vec3,
    |v: Vec3| v.extend(0.0),
    |c: &dyn Fn(u32) -> f32| Vec3::new(c(0), c(1), c(2))
);
vector_point!(
    Vec4,
    IVec4,
    4,
    hash_ivec4_to_vec4,
    hash_ivec4_to_vec3,
    |v: Vec4| v,
    |c: &dyn Fn(u32) -> f32| Vec4::new(c(0), c(1), c(2), c(3))
);
