//! What happens to a photon along its path: its flight through a medium, its walk below a
//! subsurface material, and the part of a specular reflection it leaves by.

use super::mean;
use crate::geometry::{Ray, SurfaceInteraction};
use crate::materials::bsdf::{Bsdf, Component, LobeFlags};
use crate::materials::subsurface::Subsurface;
use crate::math::Spectrum;
use crate::media::Medium;
use crate::sampling::Rng;
use crate::scene::subsurface_walk as subsurface;
use crate::scene::Scene;
use glam::Vec3;

/// Where a photon's walk below a subsurface material ended.
pub(super) struct WalkExit {
    /// The walk's weight.
    pub(super) walk: Spectrum,
    /// The weight of the photon's way out: the subsurface lobe's weight towards the direction
    /// it leaves in, as a camera path looking back along it would enter with (Cycles' lobe
    /// weight is the viewer's), times the Lambertian sample's.
    pub(super) weight: Spectrum,
    /// The exit and the surface's outward geometric normal there.
    pub(super) p: Vec3,
    pub(super) n: Vec3,
    /// The ray the photon leaves along (the exit's white Lambertian surface, sampled).
    pub(super) ray: Ray,
}

/// A photon's walk below the subsurface material at `si`. The light arriving there enters
/// whole, as through the white Lambertian surface that ends a camera path's walk; the
/// lobe's weight applies where it leaves.
pub(super) fn walk_below(
    scene: &Scene,
    si: &SurfaceInteraction,
    ss: &Subsurface,
    rng: &mut Rng,
) -> Option<WalkExit> {
    let exit = subsurface::photon_walk(scene, si, ss, rng)?;
    let bs = exit
        .bsdf
        .sample_component(exit.si.wo, Component::Diffuse, rng.f32(), rng.vec2())?;
    if bs.wi.dot(exit.si.ng) <= 0.0 {
        return None;
    }
    let mat = scene.materials.get(exit.si.material as usize)?;
    let mut out = exit.si;
    out.wo = bs.wi;
    let (w, _) = scene.shading_bsdf(mat, &mut out).subsurface_entry(bs.wi)?;
    Some(WalkExit {
        walk: exit.weight,
        weight: w * bs.importance_weight(),
        p: exit.si.p,
        n: exit.si.ng,
        ray: exit.si.spawn_ray(bs.wi),
    })
}

/// Splits the specular-and-glossy reflection chosen with probability `p` into its
/// near-specular lobes and the rest, in proportion to their albedos at `wo`: a photon that
/// leaves by a near-specular lobe is on a caustic path, one that leaves by a broader lobe is
/// not. Returns the part and its probability.
pub(super) fn specular_component(bsdf: &Bsdf, wo: Vec3, p: f32, rng: &mut Rng) -> (Component, f32) {
    if bsdf.flags() & LobeFlags::NEAR_SPECULAR == 0 {
        return (Component::Specular, p);
    }
    let near = mean(bsdf.component_albedo(wo, Component::NearSpecular));
    let other = mean(bsdf.component_albedo(wo, Component::SpecularOther));
    let f = if near + other > 0.0 {
        near / (near + other)
    } else {
        1.0
    };
    if rng.f32() < f {
        (Component::NearSpecular, p * f)
    } else {
        (Component::SpecularOther, p * (1.0 - f))
    }
}

/// The outcome of a photon's flight through a medium up to the next surface at `dist`.
pub(super) enum Flight {
    /// A real collision at `t`; `weight` is the per-channel throughput of reaching and
    /// scattering there, relative to the density the distance was drawn with.
    Collide { t: f32, weight: Spectrum },
    /// No collision before the surface; `weight` corrects the per-channel transmittance.
    Pass { weight: Spectrum },
}

/// Free-flight sampling: homogeneous media draw the distance from the channel-mean extinction
/// and correct each channel by the ratio of densities; grids use delta tracking against their
/// maximum density (grey extinction, so no correction).
pub(super) fn free_flight(med: &Medium, o: Vec3, d: Vec3, dist: f32, rng: &mut Rng) -> Flight {
    match med {
        Medium::Homogeneous(h) => {
            let st = h.sigma_t;
            let st_avg = mean(st);
            if !(st_avg > 0.0) {
                return Flight::Pass {
                    weight: Spectrum::ONE,
                };
            }
            let t = -(1.0 - rng.f32()).ln() / st_avg;
            let rel = |s: f32, x: f32| (-(s - st_avg) * x).exp();
            if t < dist {
                let ratio = Spectrum::new(
                    st.x / st_avg * rel(st.x, t),
                    st.y / st_avg * rel(st.y, t),
                    st.z / st_avg * rel(st.z, t),
                );
                let albedo = Spectrum::new(
                    safe_div(h.sigma_s.x, st.x),
                    safe_div(h.sigma_s.y, st.y),
                    safe_div(h.sigma_s.z, st.z),
                );
                Flight::Collide {
                    t,
                    weight: ratio * albedo,
                }
            } else {
                Flight::Pass {
                    weight: Spectrum::new(rel(st.x, dist), rel(st.y, dist), rel(st.z, dist)),
                }
            }
        }
        Medium::Grid(g) => match g.sample_collision(o, d, dist, rng) {
            Some((t, _)) => {
                let st = g.sigma_t;
                let albedo = Spectrum::new(
                    safe_div(g.sigma_s.x, st),
                    safe_div(g.sigma_s.y, st),
                    safe_div(g.sigma_s.z, st),
                );
                Flight::Collide { t, weight: albedo }
            }
            None => Flight::Pass {
                weight: Spectrum::ONE,
            },
        },
    }
}

#[inline]
fn safe_div(a: f32, b: f32) -> f32 {
    if b > 0.0 {
        a / b
    } else {
        0.0
    }
}
