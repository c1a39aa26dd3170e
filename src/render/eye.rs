//! The eye pass: one camera path per sample, split into terms. The path follows perfectly
//! specular bounces; every other surface is the end of the path, where the estimators run.

use super::aov::{Term, TermMask};
use super::film::TermRadiance;
use super::terms::{direct, emission, specular};
use crate::geometry::Ray;
use crate::materials::bsdf::LobeFlags;
use crate::math::{is_finite3, Frame, Spectrum};
use crate::sampling::Rng;
use crate::scene::{Scene, SceneHit};

#[derive(Clone, Copy, Debug)]
pub struct EyeSettings {
    pub terms: TermMask,
    pub max_specular_depth: u32,
}

/// Radiance along `ray`, per term. Non-finite estimates are dropped (counted by the caller).
pub fn trace(scene: &Scene, mut ray: Ray, s: &EyeSettings, rng: &mut Rng) -> TermRadiance {
    let mut out = TermRadiance::default();
    let mut beta = Spectrum::ONE;
    let mut bounces = 0u32;
    let add = |out: &mut TermRadiance, term: Term, bounces: u32, l: Spectrum| {
        let t = specular::route(term, bounces);
        if s.terms.contains(t) && is_finite3(l) {
            out.add(t, l);
        }
    };
    loop {
        match scene.intersect(&ray) {
            SceneHit::Miss => {
                add(
                    &mut out,
                    Term::Emission,
                    bounces,
                    beta * emission::background(scene, ray.d),
                );
                break;
            }
            SceneHit::Light { index, p, .. } => {
                add(
                    &mut out,
                    Term::Emission,
                    bounces,
                    beta * scene.light_le(index, p, ray.d),
                );
                break;
            }
            SceneHit::Surface(mut si) => {
                let Some(mat) = scene.materials.get(si.material as usize) else {
                    break;
                };
                add(
                    &mut out,
                    Term::Emission,
                    bounces,
                    beta * emission::surface_emission(scene, &si),
                );
                // Opaque surfaces are two-sided: shade the side the ray came from.
                let frame0 = Frame::from_normal_tangent(si.ns, si.dpdu);
                let bsdf0 = mat.bsdf(frame0, si.uv, &scene.textures);
                if bsdf0.flags() & LobeFlags::TRANSMISSION == 0 && si.ng.dot(si.wo) < 0.0 {
                    si.ng = -si.ng;
                    si.ns = -si.ns;
                }
                let bsdf = if si.ns == frame0.n {
                    bsdf0
                } else {
                    mat.bsdf(
                        Frame::from_normal_tangent(si.ns, si.dpdu),
                        si.uv,
                        &scene.textures,
                    )
                };
                if bsdf.has_non_delta() && s.terms.contains(specular::route(Term::Direct, bounces))
                {
                    add(
                        &mut out,
                        Term::Direct,
                        bounces,
                        beta * direct::estimate(scene, &si, &bsdf, rng),
                    );
                }
                if bsdf.flags() & LobeFlags::SPECULAR == 0 || bounces >= s.max_specular_depth {
                    break;
                }
                let u_lobe = rng.f32();
                let u = rng.vec2();
                let Some(bs) = bsdf.sample(si.wo, u_lobe, u) else {
                    break;
                };
                if !bs.is_delta() {
                    break; // the non-delta part was estimated above
                }
                beta *= bs.weight;
                bounces += 1;
                match specular::continue_chain(beta, bounces, rng.f32()) {
                    Some(b) => beta = b,
                    None => break,
                }
                ray = si.spawn_ray(bs.wi);
            }
        }
    }
    out
}
