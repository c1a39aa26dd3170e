//! The random walk below a subsurface material (`materials::subsurface`), as Cycles' Random
//! Walk: in through a GGX interface, scattering in a homogeneous medium, out at the first
//! surface of the same object it meets. The eye's `subsurface` term (`render::terms::
//! subsurface`) walks from a camera path's entry; photon tracing walks a photon the other way
//! ([`photon_walk`]).

use crate::geometry::{Ray, SurfaceInteraction};
use crate::materials::bsdf::Bsdf;
use crate::materials::diffuse::Lambert;
use crate::materials::lobe::Lobe;
use crate::materials::microfacet::Ggx;
use crate::materials::subsurface::{Subsurface, MAX_BOUNCES, SIMILARITY_LEVEL};
use crate::math::{Frame, Spectrum};
use crate::media::phase::HenyeyGreenstein;
use crate::sampling::warp::square_to_cosine_hemisphere;
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::Vec3;

/// Walks below this weight are dropped (Cycles' `VOLUME_THROUGHPUT_EPSILON`).
const THROUGHPUT_EPSILON: f32 = 1e-6;

/// Where a walk left the material: the exit (its `wo` pointing out, as if seen from
/// outside), the white Lambertian surface there, and the walk's weight.
pub struct Exit {
    pub si: SurfaceInteraction,
    pub bsdf: Bsdf,
    pub weight: Spectrum,
    /// Scattering events inside.
    pub events: u32,
}

/// The direction a camera path enters the material at `si` in (`n` the shading normal on the
/// side of `si.wo`), as Cycles' `subsurface_entry_bounce`: through a GGX interface of alpha
/// `roughness^2` (Skin: roughness 1, and a diffuse entry half of the time) and the
/// subsurface IOR, with weight 1 (the lobe's weight already holds its share of the light).
fn entry_direction(
    si: &SurfaceInteraction,
    n: Vec3,
    ss: &Subsurface,
    roughness: f32,
    rng: &mut Rng,
) -> Option<Vec3> {
    let frame = Frame::from_normal(n);
    let mut u = rng.vec2();
    let alpha = if ss.skin {
        if u.x < 0.5 {
            u.x *= 2.0;
            let d = square_to_cosine_hemisphere(u);
            return Some(frame.to_world(Vec3::new(d.x, d.y, -d.z)));
        }
        u.x = 2.0 * (u.x - 0.5);
        1.0
    } else {
        roughness * roughness
    };
    let wi = frame.to_local(si.wo);
    if wi.z <= 0.0 {
        return None;
    }
    let h = Ggx::new(alpha).sample_visible(wi, u);
    let neta = 1.0 / ss.ior;
    let cos_hi = h.dot(wi);
    let arg = 1.0 - neta * neta * (1.0 - cos_hi * cos_hi);
    let dnp = arg.max(0.0).sqrt().max(1e-7);
    let nk = neta * cos_hi - dnp;
    let d = frame.to_world(-neta * wi + nk * h);
    d.try_normalize()
}

/// One walk below the surface `si` (a hit on instance `si.instance`) towards the camera
/// direction `si.wo`, or `None` when it found no exit (absorbed, lost after
/// [`MAX_BOUNCES`] events, or an entry below the horizon).
pub fn walk(
    scene: &Scene,
    si: &SurfaceInteraction,
    ss: &Subsurface,
    roughness: f32,
    rng: &mut Rng,
) -> Option<Exit> {
    let (ng, n) = outward_normals(si);
    let d = entry_direction(si, n, ss, roughness, rng)?;
    walk_from(scene, si, ng, d, ss, rng)
}

/// A photon's walk below the surface `si` it arrived at (`si.wo` towards where it came from):
/// the adjoint of the camera path's white Lambertian exit, it enters along a cosine-weighted
/// direction, whatever it arrived from, and walks as a camera path does. Where it leaves,
/// the exit's Lambertian surface sends it on (`Exit::bsdf`).
pub fn photon_walk(
    scene: &Scene,
    si: &SurfaceInteraction,
    ss: &Subsurface,
    rng: &mut Rng,
) -> Option<Exit> {
    let (ng, n) = outward_normals(si);
    let c = square_to_cosine_hemisphere(rng.vec2());
    let d = Frame::from_normal(n).to_world(Vec3::new(c.x, c.y, -c.z));
    walk_from(scene, si, ng, d, ss, rng)
}

/// The geometric and shading normals at `si`, both on the side of `si.wo` (outside).
fn outward_normals(si: &SurfaceInteraction) -> (Vec3, Vec3) {
    let ng = if si.ng.dot(si.wo) < 0.0 {
        -si.ng
    } else {
        si.ng
    };
    let n = if si.ns.dot(ng) < 0.0 { -si.ns } else { si.ns };
    (ng, n)
}

/// The walk from `si` along `d`, which points below the surface of geometric normal `ng`
/// (on the side the path arrived from).
fn walk_from(
    scene: &Scene,
    si: &SurfaceInteraction,
    ng: Vec3,
    mut d: Vec3,
    ss: &Subsurface,
    rng: &mut Rng,
) -> Option<Exit> {
    if d.dot(ng) >= 0.0 {
        return None;
    }
    let mut weight = ss.start;
    let mut ray = si.spawn_ray(d);
    let (sigma_t0, sigma_s0) = (ss.sigma_t, ss.sigma_t * ss.alpha);
    // The similar isotropic medium beyond `SIMILARITY_LEVEL` events.
    let sigma_s_star = sigma_s0 * (1.0 - ss.g);
    let sigma_t_star = sigma_t0 - sigma_s0 + sigma_s_star;
    for bounce in 0..MAX_BOUNCES {
        let (sigma_t, sigma_s, g) = if bounce <= SIMILARITY_LEVEL {
            (sigma_t0, sigma_s0, ss.g)
        } else {
            (sigma_t_star, sigma_s_star, 0.0)
        };
        if bounce > 0 {
            d = HenyeyGreenstein::new(g).sample(-d, rng.vec2()).0;
            ray = Ray::new(ray.o, d);
        }
        // A channel in proportion to weight x albedo; the balance heuristic over the three.
        let w = (weight * ss.alpha).abs();
        let sum = w.x + w.y + w.z;
        let channel_pdf = if sum > 0.0 {
            w / sum
        } else {
            Spectrum::splat(1.0 / 3.0)
        };
        let u = rng.f32();
        let c = if u < channel_pdf.x {
            0
        } else if u < channel_pdf.x + channel_pdf.y {
            1
        } else {
            2
        };
        let mut t = -(1.0 - rng.f32()).ln() / sigma_t[c];
        ray.t_max = t;
        // The first segment leaves the surface the walk entered by (its origin is offset
        // past that surface's error); the others start inside, where a crossing at any
        // distance counts.
        let hit = if bounce == 0 {
            scene.accel.intersect_instance(&ray, si.instance)
        } else {
            scene
                .accel
                .intersect_instance_from_volume(&ray, si.instance)
        };
        if let Some(h) = &hit {
            t = h.t;
        }
        let tr = Spectrum::new(
            (-sigma_t.x * t).exp(),
            (-sigma_t.y * t).exp(),
            (-sigma_t.z * t).exp(),
        );
        let pdf = if hit.is_some() { tr } else { sigma_t * tr };
        let denom = channel_pdf.dot(pdf);
        if !(denom > 0.0) {
            return None;
        }
        weight *= if hit.is_some() { tr } else { sigma_s * tr } / denom;
        if let Some(h) = hit {
            let mut exit = scene.accel.interaction(&ray, &h);
            // Seen from outside: `wo` leaves through the surface.
            exit.wo = d;
            let out = if exit.ng.dot(d) < 0.0 {
                -exit.ng
            } else {
                exit.ng
            };
            exit.ng = out;
            if exit.ns.dot(out) < 0.0 {
                exit.ns = -exit.ns;
            }
            let mut bsdf = Bsdf::new(Frame::from_normal_tangent(exit.ns, exit.dpdu));
            bsdf.add(
                1.0,
                Lobe::Lambert(Lambert {
                    albedo: Spectrum::ONE,
                }),
            );
            return weight.is_finite().then_some(Exit {
                si: exit,
                bsdf,
                weight,
                events: bounce,
            });
        }
        if weight.max_element() < THROUGHPUT_EPSILON {
            return None;
        }
        ray.o += d * t;
    }
    None
}
