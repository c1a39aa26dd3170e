//! The BSDF at a surface hit, as every pass shades it, and whether a ray passes through the
//! surface instead (invisible boundaries, Transparent BSDF, Alpha).

use super::Scene;
use crate::geometry::SurfaceInteraction;
use crate::materials::bsdf::{Bsdf, LobeFlags};
use crate::materials::graph::point::ShadingPoint;
use crate::materials::graph::Want;
use crate::materials::Material;
use crate::math::{Frame, Spectrum};

/// Most transparent surfaces a path passes (Cycles' Transparent max bounces default).
pub const MAX_TRANSPARENT: u32 = 8;

/// What a ray does at a surface: it stops there (its throughput times the weight), or it
/// passes straight through (times the weight).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Crossing {
    Stop(f32),
    Pass(Spectrum),
}

impl Scene {
    /// The shading point of a hit, normals turned towards the ray as Cycles shades.
    pub fn shading_point(&self, si: &SurfaceInteraction) -> ShadingPoint {
        let backfacing = si.ng.dot(si.wo) < 0.0;
        let s = if backfacing { -1.0 } else { 1.0 };
        ShadingPoint {
            p: si.p,
            n: si.ns * s,
            ng: si.ng * s,
            uv: si.uv,
            dpdu: si.dpdu,
            dpdv: self.accel.dpdv(si),
            wo: si.wo,
            backfacing,
            object: self
                .objects
                .get(si.instance as usize)
                .copied()
                .unwrap_or_default(),
            attributes: if self.accel.has_attributes() {
                self.accel.attributes(si)
            } else {
                Default::default()
            },
            path: si.path,
            ray_length: si.ray_length,
        }
    }

    /// The BSDF of `mat` at a hit, with opaque surfaces shaded on the side the ray came from
    /// (two-sided, as Blender shades: `si`'s normals are flipped to that side);
    /// transmissive surfaces keep their orientation (inside vs outside).
    pub fn shading_bsdf(&self, mat: &Material, si: &mut SurfaceInteraction) -> Bsdf {
        if let Material::Graph(g) = mat {
            let sp = self.shading_point(si);
            let bsdf = g.shade(&sp, &self.textures, Want::All).bsdf;
            // The graph's shading normal (Bump, Normal Map) is the one every estimate's cosine
            // reads; it faces the ray.
            let n = bsdf.frame().n;
            if bsdf.flags() & LobeFlags::TRANSMISSION == 0 && sp.backfacing {
                si.ng = -si.ng;
                si.ns = n;
            } else {
                si.ns = if sp.backfacing { -n } else { n };
            }
            return bsdf;
        }
        let bsdf = mat.bsdf(
            Frame::from_normal_tangent(si.ns, si.dpdu),
            si.uv,
            &self.textures,
        );
        if bsdf.flags() & LobeFlags::TRANSMISSION == 0 && si.ng.dot(si.wo) < 0.0 {
            si.ng = -si.ng;
            si.ns = -si.ns;
            return mat.bsdf(
                Frame::from_normal_tangent(si.ns, si.dpdu),
                si.uv,
                &self.textures,
            );
        }
        bsdf
    }

    /// The weight of light passing straight through `mat` at a hit: one for an invisible
    /// boundary, the transparency of a graph, zero for every other surface.
    pub fn transparency(&self, mat: &Material, si: &SurfaceInteraction) -> Spectrum {
        match mat {
            Material::Null { .. } => Spectrum::ONE,
            Material::Graph(g) if g.can_pass() => {
                let t = g
                    .shade(&self.shading_point(si), &self.textures, Want::Light)
                    .transparency;
                t.clamp(Spectrum::ZERO, Spectrum::ONE)
            }
            _ => Spectrum::ZERO,
        }
    }

    /// Whether a ray at `si` passes through `mat` or stops there: with a probability equal
    /// to the mean transparency it passes (`u` is drawn only for partly transparent
    /// surfaces), weighted so that the estimate stays unbiased.
    pub fn crossing(
        &self,
        mat: &Material,
        si: &SurfaceInteraction,
        u: impl FnOnce() -> f32,
    ) -> Crossing {
        match mat {
            Material::Null { .. } => Crossing::Pass(Spectrum::ONE),
            Material::Graph(g) if g.can_pass() => {
                let t = self.transparency(mat, si);
                let p = (t.x + t.y + t.z) / 3.0;
                if !(p > 0.0) {
                    Crossing::Stop(1.0)
                } else if p >= 1.0 {
                    Crossing::Pass(t)
                } else if u() < p {
                    Crossing::Pass(t / p)
                } else {
                    Crossing::Stop(1.0 / (1.0 - p))
                }
            }
            _ => Crossing::Stop(1.0),
        }
    }

    /// The summed weight of the Holdout closures of `mat` at a hit (zero unless its graph
    /// has one).
    pub fn holdout(&self, mat: &Material, si: &SurfaceInteraction) -> f32 {
        match mat {
            Material::Graph(g) if g.holds_out() => {
                g.shade(&self.shading_point(si), &self.textures, Want::Light)
                    .holdout
            }
            _ => 0.0,
        }
    }

    /// Emitted radiance of the surface at a hit, towards the ray's origin.
    pub fn emission_at(&self, mat: &Material, si: &SurfaceInteraction) -> Spectrum {
        match mat {
            Material::Graph(g) => {
                g.shade(&self.shading_point(si), &self.textures, Want::Light)
                    .emission
            }
            m => m.emission(si.uv, &self.textures),
        }
    }
}
