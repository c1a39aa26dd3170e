//! The BSDF at a surface hit, as every pass shades it.

use super::Scene;
use crate::geometry::SurfaceInteraction;
use crate::materials::bsdf::{Bsdf, LobeFlags};
use crate::materials::Material;
use crate::math::Frame;

impl Scene {
    /// The BSDF of `mat` at a hit, with opaque surfaces shaded on the side the ray came from
    /// (two-sided, as Blender shades: `si`'s normals are flipped to that side);
    /// transmissive surfaces keep their orientation (inside vs outside).
    pub fn shading_bsdf(&self, mat: &Material, si: &mut SurfaceInteraction) -> Bsdf {
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
}
