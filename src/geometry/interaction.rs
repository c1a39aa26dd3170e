//! Surface interactions and robust spawning of rays from them (pbrt-v4 §6.8.6,
//! "Robust Spawned Ray Origins").

use super::float::{gamma, next_float_down, next_float_up};
use super::ray::Ray;
use glam::{Mat4, Vec2, Vec3};

/// pbrt-v4's `ShadowEpsilon`: shadow rays stop this fraction short of their target.
pub const SHADOW_EPSILON: f32 = 0.0001;

/// Local geometry at a ray hit, in world space.
///
/// | field | meaning |
/// |-------|---------|
/// | `p` | hit point, from the barycentrics and the instance transform |
/// | `p_error` | conservative absolute error bound of `p`, per axis |
/// | `ng` | unit geometric normal, from the winding `(p1 − p0) × (p2 − p0)`; flipped when the instance transform swaps handedness, so it follows the world-space winding |
/// | `ns` | unit shading normal: interpolated vertex normals when the mesh has them, else `ng` |
/// | `uv` | interpolated texture coordinates, or the barycentrics `(b1, b2)` |
/// | `dpdu` | ∂p/∂u in world space (a tangent perpendicular to `ng` when the uv mapping is degenerate) |
/// | `wo` | unit direction back along the incoming ray, `−d/|d|` |
/// | `material`, `instance`, `prim`, `t` | material index of the triangle, and the hit record |
/// | `bary` | the hit's barycentrics `(b1, b2)` in its triangle |
/// | `ray_length` | the length of the ray segment that reached the hit, `t |d|` |
/// | `path` | the kind of ray that reached it (set by the pass that traced it; none by default) |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceInteraction {
    pub p: Vec3,
    pub p_error: Vec3,
    pub ng: Vec3,
    pub ns: Vec3,
    pub uv: Vec2,
    pub dpdu: Vec3,
    pub wo: Vec3,
    pub material: u32,
    pub instance: u32,
    pub prim: u32,
    pub t: f32,
    pub bary: Vec2,
    pub ray_length: f32,
    pub path: RayPath,
}

/// The kind of ray that reached a surface and the bounces behind it, as Cycles' Light Path
/// node reads them: `flags` of [`RayPath::CAMERA`] ... [`RayPath::VOLUME_SCATTER`], and the
/// depths (bounces of each kind so far). All zero for light sampled on an emitter, as Cycles
/// evaluates emission for its lights.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayPath {
    pub flags: u8,
    pub depth: u8,
    pub diffuse_depth: u8,
    pub glossy_depth: u8,
    pub transmission_depth: u8,
    pub transparent_depth: u8,
}

/// How a ray left a surface, for [`RayPath::scattered`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scatter {
    Diffuse,
    Glossy,
    /// A delta lobe (a mirror, smooth glass): Cycles' singular rays, which are also glossy.
    Singular,
}

impl RayPath {
    pub const CAMERA: u8 = 1;
    pub const SHADOW: u8 = 2;
    pub const DIFFUSE: u8 = 4;
    pub const GLOSSY: u8 = 8;
    pub const SINGULAR: u8 = 16;
    pub const REFLECT: u8 = 32;
    pub const TRANSMIT: u8 = 64;
    pub const VOLUME_SCATTER: u8 = 128;

    /// A ray from the camera.
    pub const CAMERA_RAY: RayPath = RayPath {
        flags: RayPath::CAMERA,
        depth: 0,
        diffuse_depth: 0,
        glossy_depth: 0,
        transmission_depth: 0,
        transparent_depth: 0,
    };

    /// A shadow ray (Cycles shades the surfaces a shadow ray crosses with this flag alone).
    pub const SHADOW_RAY: RayPath = RayPath {
        flags: RayPath::SHADOW,
        ..RayPath::CAMERA_RAY
    };

    /// The ray that leaves a surface reached by `self`, scattered as `how`, reflected or
    /// transmitted.
    pub fn scattered(self, how: Scatter, transmit: bool) -> RayPath {
        let up = |d: u8| d.saturating_add(1);
        let mut p = RayPath {
            flags: if transmit {
                RayPath::TRANSMIT
            } else {
                RayPath::REFLECT
            },
            depth: up(self.depth),
            ..self
        };
        match how {
            Scatter::Diffuse => {
                p.flags |= RayPath::DIFFUSE;
                p.diffuse_depth = up(p.diffuse_depth);
            }
            Scatter::Glossy | Scatter::Singular => {
                p.flags |= RayPath::GLOSSY;
                if how == Scatter::Singular {
                    p.flags |= RayPath::SINGULAR;
                }
                p.glossy_depth = up(p.glossy_depth);
            }
        }
        if transmit {
            p.transmission_depth = up(p.transmission_depth);
        }
        p
    }

    /// The same ray after passing straight through a transparent surface.
    pub fn crossed(self) -> RayPath {
        self.crossed_n(1)
    }

    /// The same ray after passing `n` transparent surfaces.
    pub fn crossed_n(self, n: u32) -> RayPath {
        RayPath {
            transparent_depth: self.transparent_depth.saturating_add(n.min(255) as u8),
            ..self
        }
    }

    pub fn is(&self, flag: u8) -> bool {
        self.flags & flag != 0
    }
}

/// Offsets a point off a surface so that a ray leaving it in direction `w` cannot
/// re-intersect that surface (pbrt-v4 `OffsetRayOrigin`).
///
/// | parameter | meaning |
/// |-----------|---------|
/// | `p` | computed surface point |
/// | `p_error` | its absolute error bound per axis |
/// | `n` | geometric normal (any length, usually unit) |
/// | `w` | direction the new ray will take |
///
/// The point moves along `n` by `dot(|n|, p_error)`, to the side `w` points to, and each
/// moved coordinate is then rounded one more ulp away from the surface.
#[inline]
pub fn offset_ray_origin(p: Vec3, p_error: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    let d = n.abs().dot(p_error);
    let mut offset = d * n;
    if w.dot(n) < 0.0 {
        offset = -offset;
    }
    let mut po = p + offset;
    for i in 0..3 {
        if offset[i] > 0.0 {
            po[i] = next_float_up(po[i]);
        } else if offset[i] < 0.0 {
            po[i] = next_float_down(po[i]);
        }
    }
    po
}

/// Absolute error of `m · p` for an affine `m`, when `p` already carries error `p_error`
/// (pbrt-v4 `Transform::operator()(Point3fi)`, §6.8.5).
#[inline]
pub fn transform_point_error(m: &Mat4, p: Vec3, p_error: Vec3) -> Vec3 {
    let c0 = m.x_axis.truncate().abs();
    let c1 = m.y_axis.truncate().abs();
    let c2 = m.z_axis.truncate().abs();
    let t = m.w_axis.truncate().abs();
    let a = p.abs();
    let g3 = gamma(3);
    let exact = g3 * (c0 * a.x + c1 * a.y + c2 * a.z + t);
    if p_error == Vec3::ZERO {
        exact
    } else {
        (g3 + 1.0) * (c0 * p_error.x + c1 * p_error.y + c2 * p_error.z) + exact
    }
}

impl SurfaceInteraction {
    /// Ray leaving the surface in direction `dir` (any length), unbounded.
    #[inline]
    pub fn spawn_ray(&self, dir: Vec3) -> Ray {
        Ray::new(offset_ray_origin(self.p, self.p_error, self.ng, dir), dir)
    }

    /// Shadow ray towards the point `target`: `d = target − o`, `t_max = 1 − SHADOW_EPSILON`.
    #[inline]
    pub fn spawn_ray_to(&self, target: Vec3) -> Ray {
        let o = offset_ray_origin(self.p, self.p_error, self.ng, target - self.p);
        Ray::with_t_max(o, target - o, 1.0 - SHADOW_EPSILON)
    }

    /// Shadow ray towards another surface point, offsetting both ends off their surfaces.
    ///
    /// | parameter | meaning |
    /// |-----------|---------|
    /// | `other_p` | the other point |
    /// | `other_p_error` | its error bound |
    /// | `other_n` | its geometric normal |
    #[inline]
    pub fn spawn_ray_to_interaction(
        &self,
        other_p: Vec3,
        other_p_error: Vec3,
        other_n: Vec3,
    ) -> Ray {
        let from = offset_ray_origin(self.p, self.p_error, self.ng, other_p - self.p);
        let to = offset_ray_origin(other_p, other_p_error, other_n, from - other_p);
        Ray::with_t_max(from, to - from, 1.0 - SHADOW_EPSILON)
    }
}
