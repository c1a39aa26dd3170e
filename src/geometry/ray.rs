//! Rays.

use glam::Vec3;

/// A ray `o + t·d` for `0 < t < t_max`.
///
/// | field | meaning |
/// |-------|---------|
/// | `o` | origin (world space unless stated otherwise) |
/// | `d` | direction, not necessarily unit length; `t` is measured in units of `d` |
/// | `t_max` | exclusive upper bound on the hit distance; `f32::INFINITY` for unbounded rays |
///
/// There is no `t_min`: rays leaving a surface avoid self-intersection by offsetting their
/// origin past the rounding-error box of the hit point (see [`super::offset_ray_origin`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub o: Vec3,
    pub d: Vec3,
    pub t_max: f32,
}

impl Ray {
    /// Unbounded ray.
    #[inline]
    pub fn new(o: Vec3, d: Vec3) -> Self {
        Ray {
            o,
            d,
            t_max: f32::INFINITY,
        }
    }

    /// Ray bounded by `t_max`.
    #[inline]
    pub fn with_t_max(o: Vec3, d: Vec3, t_max: f32) -> Self {
        Ray { o, d, t_max }
    }

    /// Point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.o + self.d * t
    }
}
