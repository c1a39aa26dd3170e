//! `emission`: emitters and the background seen directly. Through a specular chain the same
//! radiance lands in `specular` instead.

use crate::geometry::SurfaceInteraction;
use crate::math::Spectrum;
use crate::scene::Scene;

/// Radiance emitted by the surface towards the ray's origin (both faces emit, as in Cycles).
pub fn surface_emission(scene: &Scene, si: &SurfaceInteraction) -> Spectrum {
    match scene.materials.get(si.material as usize) {
        Some(m) if m.is_emissive() => m.emission(si.uv, &scene.textures),
        _ => Spectrum::ZERO,
    }
}

/// Radiance of everything at infinity along an escaping ray.
pub fn background(scene: &Scene, d: glam::Vec3) -> Spectrum {
    scene.background(d)
}
