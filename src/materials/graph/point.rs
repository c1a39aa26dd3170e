//! What the nodes read at a shading point.

use crate::geometry::{AttributeValues, RayPath};
use glam::{Mat4, Vec2, Vec3};

/// The object a shading point lies on, as the coordinate nodes see it.
///
/// | field | meaning |
/// |---|---|
/// | `to_object` | world -> object space (Object coordinates) |
/// | `gen_offset`, `gen_scale` | Generated = (object position - offset) x scale: the object's texture space, by default its mesh's bounding box mapped to [0, 1]^3 (Blender's auto texture space) |
/// | `random` | Object Info's Random: a hash of the object's name in [0, 1) |
/// | `index` | Object Info's Object Index (the pass index) |
/// | `location` | the object's origin in world space |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectCoords {
    pub to_object: Mat4,
    pub gen_offset: Vec3,
    pub gen_scale: Vec3,
    pub random: f32,
    pub index: f32,
    pub location: Vec3,
}

impl Default for ObjectCoords {
    fn default() -> Self {
        ObjectCoords {
            to_object: Mat4::IDENTITY,
            gen_offset: Vec3::ZERO,
            gen_scale: Vec3::ONE,
            random: 0.0,
            index: 0.0,
            location: Vec3::ZERO,
        }
    }
}

impl ObjectCoords {
    /// Blender's automatic texture space of a mesh with bounds [`lo`, `hi`] (object space):
    /// centre and half size, a flat axis given size 1 as Blender does.
    pub fn texture_space(lo: Vec3, hi: Vec3) -> (Vec3, Vec3) {
        if !(lo.cmple(hi).all()) {
            return (Vec3::ZERO, Vec3::ONE);
        }
        let loc = 0.5 * (lo + hi);
        let mut size = 0.5 * (hi - lo);
        for i in 0..3 {
            if size[i] == 0.0 {
                size[i] = 1.0;
            } else if size[i] < 1e-5 {
                size[i] = 1e-5;
            }
        }
        (loc, size)
    }

    /// Coordinates for texture space (`loc`, `size`): generated = (p - (loc - size)) / (2 size).
    pub fn with_texture_space(mut self, loc: Vec3, size: Vec3) -> Self {
        self.gen_offset = loc - size;
        self.gen_scale = Vec3::ONE / (2.0 * size);
        self
    }

    #[inline]
    pub fn object_point(&self, p: Vec3) -> Vec3 {
        self.to_object.transform_point3(p)
    }

    #[inline]
    pub fn generated(&self, p: Vec3) -> Vec3 {
        (self.object_point(p) - self.gen_offset) * self.gen_scale
    }
}

/// A shading point: the hit's geometry, with the normals facing the incoming ray as Cycles
/// shades (`backfacing` says whether they were flipped).
///
/// | field | meaning |
/// |---|---|
/// | `p` | world position |
/// | `n`, `ng` | shading and geometric normal, on the side of `wo` |
/// | `uv` | the mesh's texture coordinates |
/// | `dpdu`, `dpdv` | world-space derivatives of `p` along u and v (zero when unknown) |
/// | `wo` | unit direction towards the ray's origin (Cycles' I) |
/// | `object` | the object's coordinate systems |
/// | `attributes` | the mesh's named attributes at the point |
/// | `path`, `ray_length` | the kind of ray that reached the point and its segment's length (the Light Path node) |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingPoint {
    pub p: Vec3,
    pub n: Vec3,
    pub ng: Vec3,
    pub uv: Vec2,
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    pub wo: Vec3,
    pub backfacing: bool,
    pub object: ObjectCoords,
    pub attributes: AttributeValues,
    pub path: RayPath,
    pub ray_length: f32,
}

impl ShadingPoint {
    /// A point at `p` with normal `n` seen along it (for emitters sampled by position).
    pub fn at(p: Vec3, n: Vec3, uv: Vec2) -> Self {
        ShadingPoint {
            p,
            n,
            ng: n,
            uv,
            dpdu: Vec3::ZERO,
            dpdv: Vec3::ZERO,
            wo: n,
            backfacing: false,
            object: ObjectCoords::default(),
            attributes: AttributeValues::default(),
            path: RayPath::default(),
            ray_length: 0.0,
        }
    }

    /// The change of `uv` for a small move `dp` in the tangent plane (zero without
    /// derivatives).
    pub fn duv(&self, dp: Vec3) -> Vec2 {
        // Solve dp = du dpdu + dv dpdv in the least-squares sense.
        let (a, b) = (self.dpdu, self.dpdv);
        let (aa, ab, bb) = (a.dot(a), a.dot(b), b.dot(b));
        let det = aa * bb - ab * ab;
        if !(det.abs() > 1e-30) || !det.is_finite() {
            return Vec2::ZERO;
        }
        let (pa, pb) = (dp.dot(a), dp.dot(b));
        Vec2::new((pa * bb - pb * ab) / det, (pb * aa - pa * ab) / det)
    }
}
