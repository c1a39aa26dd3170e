//! One emissive triangle of a mesh whose material emits (Blender mesh lights).
//! Emits from both faces, as Cycles' emission shader; radiance comes from the material at the
//! interpolated UV, so textured emission works.

use super::{LightCtx, LightSample};
use crate::math::{Spectrum, PI};
use crate::sampling::warp;
use glam::{Vec2, Vec3};

#[derive(Clone, Debug)]
pub struct TriangleLight {
    pub v: [Vec3; 3],
    pub uv: [Vec2; 3],
    pub n: Vec3,
    pub area: f32,
    pub material: u32,
    pub instance: u32,
    pub prim: u32,
}

impl TriangleLight {
    pub fn new(v: [Vec3; 3], uv: [Vec2; 3], material: u32, instance: u32, prim: u32) -> Self {
        let c = (v[1] - v[0]).cross(v[2] - v[0]);
        let len = c.length();
        let n = if len > 0.0 { c / len } else { Vec3::Z };
        TriangleLight {
            v,
            uv,
            n,
            area: 0.5 * len,
            material,
            instance,
            prim,
        }
    }

    /// Emitted radiance at the point `p` of UV `uv` (a shading graph's emission reads the
    /// point and its object).
    pub fn emission(&self, p: Vec3, uv: Vec2, ctx: &LightCtx) -> Spectrum {
        match ctx.materials.get(self.material as usize) {
            None => Spectrum::ZERO,
            Some(m @ crate::materials::Material::Graph(_)) => {
                let mut sp = crate::materials::graph::point::ShadingPoint::at(p, self.n, uv);
                sp.object = ctx
                    .objects
                    .get(self.instance as usize)
                    .copied()
                    .unwrap_or_default();
                m.emission_at(&sp, ctx.textures)
            }
            Some(m) => m.emission(uv, ctx.textures),
        }
    }

    pub fn sample_li(&self, p: Vec3, u: Vec2, ctx: &LightCtx) -> Option<LightSample> {
        if self.area <= 0.0 {
            return None;
        }
        let (b1, b2) = warp::square_to_uniform_triangle(u);
        let b0 = 1.0 - b1 - b2;
        let pl = self.v[0] * b0 + self.v[1] * b1 + self.v[2] * b2;
        let uv = self.uv[0] * b0 + self.uv[1] * b1 + self.uv[2] * b2;
        let to = pl - p;
        let d2 = to.length_squared();
        if !(d2 > 0.0) {
            return None;
        }
        let dist = d2.sqrt();
        let wi = to / dist;
        let cos_l = wi.dot(self.n);
        Some(LightSample {
            wi,
            li: self.emission(pl, uv, ctx),
            pdf: warp::area_to_solid_angle(1.0 / self.area, d2, cos_l),
            dist,
            p: pl,
            n: self.n,
            delta: false,
        })
    }

    pub fn pdf_li(&self, p: Vec3, p_light: Vec3, n_light: Vec3) -> f32 {
        let to = p_light - p;
        let d2 = to.length_squared();
        if d2 <= 0.0 || self.area <= 0.0 {
            return 0.0;
        }
        warp::area_to_solid_angle(1.0 / self.area, d2, (to / d2.sqrt()).dot(n_light))
    }

    /// Power of both faces, with the emission at the centroid's UV; for a shading graph's
    /// emission (which may vary over the triangle), its mean at the corners, the edges'
    /// midpoints and the centroid.
    pub fn power(&self, ctx: &LightCtx) -> Spectrum {
        let at = |b: [f32; 3]| {
            let p = self.v[0] * b[0] + self.v[1] * b[1] + self.v[2] * b[2];
            let uv = self.uv[0] * b[0] + self.uv[1] * b[1] + self.uv[2] * b[2];
            self.emission(p, uv, ctx)
        };
        let le = match ctx.materials.get(self.material as usize) {
            Some(crate::materials::Material::Graph(_)) => {
                const B: [[f32; 3]; 7] = [
                    [1.0, 0.0, 0.0],
                    [0.0, 1.0, 0.0],
                    [0.0, 0.0, 1.0],
                    [0.5, 0.5, 0.0],
                    [0.0, 0.5, 0.5],
                    [0.5, 0.0, 0.5],
                    [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
                ];
                B.iter().map(|b| at(*b)).sum::<Spectrum>() / B.len() as f32
            }
            _ => {
                let uv = (self.uv[0] + self.uv[1] + self.uv[2]) / 3.0;
                let c = (self.v[0] + self.v[1] + self.v[2]) / 3.0;
                self.emission(c, uv, ctx)
            }
        };
        le * (2.0 * PI * self.area)
    }
}
