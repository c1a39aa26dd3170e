//! The first pass: photons leave the lights and are propagated with Russian roulette
//! (Jensen 2001, chapter 5 and §6.3), and stored at non-specular surfaces.
//!
//! Determinism: photons are traced in batches of `BATCH` paths; batch b draws from its own
//! random stream (seed, map, b), and batches are concatenated in order. Rounds of batches run
//! until the map holds its target number of photons (Jensen shoots until N are stored) or the
//! emission cap is reached. The result does not depend on the thread count.

mod interactions;
mod rounds;

use super::map::{
    MapKind, PhotonMap, PhotonTree, Select, FLAG_CAUSTIC_PATH, FLAG_FIRST_HIT, FLAG_FROM_MEDIUM,
    FLAG_SUBSURFACE_EXIT, GROUP_SHIFT,
};
use super::{encode_direction, Photon, PhotonF32, PhotonRecord};
use crate::geometry::{Ray, RayPath, Scatter};
use crate::lights::{LeSample, Light, Target};
use crate::materials::bsdf::{Component, LobeFlags};
use crate::math::{is_finite3, Spectrum};
use crate::media::MediumStack;
use crate::sampling::Rng;
use crate::scene::shading::{Crossing, MAX_TRANSPARENT};
use crate::scene::Scene;
use glam::Vec3;
use interactions::{free_flight, specular_component, walk_below, Flight};
use rounds::build_map_of;
use std::sync::atomic::AtomicBool;

/// Photon paths per batch.
pub const BATCH: u64 = 2048;

const _: () = assert!(std::mem::size_of::<RawPhoton>() == 40);

/// Where an irradiance point goes: a traced photon's position and its surface normal (as
/// `encode_direction` bytes), and whether it is a subsurface exit (then the point holds the
/// exits' exitance, not irradiance).
type IrradianceSite = (Vec3, (u8, u8), bool);

/// The stored record of a traced photon, its power as traced (the map's power scale divides
/// it by the paths emitted as it is read): `None` when the record's constructor rejects the
/// position, the direction or the power.
#[inline]
fn record_of<P: PhotonRecord>(r: &RawPhoton) -> Option<P> {
    if !r.p.is_finite() {
        return None;
    }
    let dir = super::photon::encode_travel_direction(r.d).ok()?;
    let mut ph = P::from_parts(r.p, r.power, dir).ok()?;
    ph.set_flags(r.flags as u16 | (r.group as u16) << GROUP_SHIFT);
    Some(ph)
}

/// A photon before normalisation by the number emitted (40 bytes).
#[derive(Clone, Copy)]
struct RawPhoton {
    p: Vec3,
    power: Spectrum,
    d: Vec3,
    /// The surface normal on the side the photon arrived from (quantised as a direction).
    n: (u8, u8),
    /// The map's `FLAG_*` bits: first hit, from a medium, caustic path (every earlier
    /// interaction a specular surface bounce: light -> specular+ -> here).
    flags: u8,
    /// The light group of the light that emitted it (`Scene::light_group`).
    group: u8,
}

pub struct TraceParams<'a> {
    pub kind: MapKind,
    /// Photons to store.
    pub target: usize,
    /// Emission cap, in photon paths.
    pub max_emitted: u64,
    pub max_bounces: u32,
    pub seed: u64,
    /// Specular objects to aim caustic photons at; empty = emit everywhere.
    pub targets: &'a [Target],
    pub cancel: Option<&'a AtomicBool>,
    /// Store the photons' power as `f32` ([`PhotonF32`], 28 bytes) instead of RGBE
    /// ([`Photon`], 20 bytes).
    pub f32_power: bool,
    /// Precompute irradiance at every [`super::irradiance::STRIDE`]-th photon from its `k`
    /// nearest photons within the squared radius, counting those the `Select` takes (global
    /// maps, for final gathering).
    pub irradiance: Option<(usize, f32, Select)>,
}

/// The `FLAG_*` bits of a raw photon: first hit, from a medium, caustic path.
fn raw_flags(first: bool, from_medium: bool, caustic: bool) -> u8 {
    let bit = |b: bool, f: u16| if b { f as u8 } else { 0 };
    bit(first, FLAG_FIRST_HIT)
        | bit(from_medium, FLAG_FROM_MEDIUM)
        | bit(caustic, FLAG_CAUSTIC_PATH)
}

/// Mean of a colour, the probability used for Russian roulette.
#[inline]
fn mean(c: Spectrum) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

/// Traces one photon path, appending what it stores. In a medium, a free-flight distance is
/// drawn with the channel-mean extinction and the per-channel ratio corrects the power; at a
/// collision the photon scatters (Henyey-Greenstein) with probability equal to the mean
/// albedo, else it is absorbed (Jensen 2001, §10.3).
#[allow(clippy::too_many_arguments)]
fn trace_path(
    scene: &Scene,
    le: LeSample,
    scale: f32,
    start: MediumStack,
    (kind, group): (MapKind, u8),
    max_bounces: u32,
    rng: &mut Rng,
    out: &mut Vec<RawPhoton>,
) {
    let mut power = le.weight * scale;
    let mut ray = Ray {
        o: le.o,
        d: le.d,
        t_max: f32::INFINITY,
    };
    let mut stack = start;
    let mut interactions = 0u32;
    let mut specular_bounces = 0u32;
    let mut crossings = 0u32;
    let mut transparent_hits = 0u32;
    let mut last_scatter = false;
    // Distance travelled before the first interaction, against the light's `min_travel`.
    let mut travelled = 0.0f32;
    while interactions < max_bounces && crossings < 4 * max_bounces + 16 {
        let hit = scene.accel.intersect(&ray);
        let dir_len = ray.d.length();
        let dist = hit.as_ref().map_or(f32::INFINITY, |h| h.t * dir_len);
        // A photon that would first interact before its light's `min_travel` does not exist
        // in the light's emission (the soft-falloff disk): drop it.
        let too_near = |t: f32| interactions == 0 && travelled + t < le.min_travel;
        if let Some(m) = stack.current(scene.world_medium) {
            let med = &scene.media[m as usize];
            let d = ray.d / dir_len;
            match free_flight(med, ray.o, d, dist, rng) {
                Flight::Collide { t, weight } => {
                    if too_near(t) {
                        break;
                    }
                    // Scatter with probability P = mean expected throughput, else absorbed.
                    let p = mean(weight).min(1.0);
                    if kind == MapKind::Caustic || !(p > 0.0) || rng.f32() >= p {
                        break;
                    }
                    let new_power = power * weight / p;
                    if !is_finite3(new_power) || new_power.max_element() <= 0.0 {
                        break;
                    }
                    power = new_power;
                    let x = ray.o + d * t;
                    if kind == MapKind::Volume && interactions > 0 {
                        out.push(RawPhoton {
                            p: x,
                            power,
                            d,
                            n: (0, 0),
                            flags: FLAG_FROM_MEDIUM as u8,
                            group,
                        });
                    }
                    interactions += 1;
                    last_scatter = true;
                    let (wi, _) = med.phase().sample(-d, rng.vec2());
                    ray = Ray {
                        o: x,
                        d: wi,
                        t_max: f32::INFINITY,
                    };
                    continue;
                }
                Flight::Pass { weight } => {
                    if !dist.is_finite() {
                        break;
                    }
                    power *= weight;
                }
            }
        }
        let Some(hit) = hit else { break };
        let mut si = scene.accel.interaction(&ray, &hit);
        // Photons shade a surface as the diffuse bounce of a camera hit sees it (the photon
        // maps answer for such bounces), whatever their own bounces were.
        si.path = RayPath::CAMERA_RAY
            .scattered(Scatter::Diffuse, false)
            .crossed_n(transparent_hits);
        let Some(mat) = scene.materials.get(si.material as usize) else {
            break;
        };
        match scene.crossing(mat, &si, || rng.f32()) {
            Crossing::Pass(w) => {
                // An invisible boundary or a transparent surface: the photon goes on.
                if !mat.is_null() {
                    transparent_hits += 1;
                    if transparent_hits > MAX_TRANSPARENT {
                        break;
                    }
                }
                power *= w;
                scene.update_stack(&mut stack, &si, ray.d);
                ray = si.spawn_ray(ray.d);
                crossings += 1;
                travelled += dist;
                continue;
            }
            Crossing::Stop(w) => power *= w,
        }
        if too_near(dist) {
            break;
        }
        let bsdf = scene.shading_bsdf(mat, &mut si);
        let passes = bsdf.passes_through();
        if bsdf.has_non_delta() && !passes {
            let n = encode_direction(if si.ng.dot(si.wo) >= 0.0 {
                si.ng
            } else {
                -si.ng
            });
            match kind {
                MapKind::Global => out.push(RawPhoton {
                    p: si.p,
                    power,
                    d: ray.d,
                    n,
                    flags: raw_flags(
                        interactions == 0,
                        last_scatter,
                        interactions > 0 && specular_bounces == interactions,
                    ),
                    group,
                }),
                MapKind::Caustic => {
                    // Light -> specular+ -> here: a caustic photon. Its path goes on only
                    // through a delta or near-specular lobe of this surface (Russian roulette
                    // below), which makes the path after it a caustic path too.
                    if specular_bounces == interactions && interactions > 0 {
                        out.push(RawPhoton {
                            p: si.p,
                            power,
                            d: ray.d,
                            n,
                            flags: FLAG_CAUSTIC_PATH as u8,
                            group,
                        });
                    }
                    if bsdf.flags() & (LobeFlags::SPECULAR | LobeFlags::NEAR_SPECULAR) == 0 {
                        break;
                    }
                }
                MapKind::Volume => {}
            }
        }
        // Russian roulette (Jensen 2001, §6.3): diffuse with probability P_d, specular
        // reflection with P_s, transmission with P_t, else absorbed; the surviving photon's
        // power is scaled per channel by the component's reflectance over its probability.
        let (d, s, t) = bsdf.rr_reflectivities(si.wo);
        let (pd, ps, pt) = (mean(d), mean(s), mean(t));
        let q = rng.f32();
        let (component, p) = if q < pd {
            (Component::Diffuse, pd)
        } else if q < pd + ps {
            specular_component(&bsdf, si.wo, ps, rng)
        } else if q < pd + ps + pt {
            (Component::Transmission, pt)
        } else {
            break;
        };
        if kind == MapKind::Caustic && component == Component::Diffuse {
            break;
        }
        // A subsurface material's lobe takes its share of the diffuse photons below the
        // surface: they leave where their walk ends.
        let (mut p, mut rest) = (p, None);
        if component == Component::Diffuse {
            if let Some(ss) = mat.subsurface().filter(|_| bsdf.has_subsurface()) {
                let f = bsdf.subsurface_share(si.wo);
                if rng.f32() < f {
                    let Some(exit) = walk_below(scene, &si, ss, rng) else {
                        break;
                    };
                    let stored = power * exit.walk / (p * f);
                    let new_power = stored * exit.weight;
                    if kind == MapKind::Global && is_finite3(stored) && stored.max_element() > 0.0 {
                        // The light leaving the surface there, before the lobe's weight
                        // towards a viewer: for final-gathering rays that land on it.
                        out.push(RawPhoton {
                            p: exit.p,
                            power: stored,
                            d: -exit.n,
                            n: encode_direction(exit.n),
                            flags: FLAG_SUBSURFACE_EXIT as u8,
                            group,
                        });
                    }
                    if !is_finite3(new_power) || new_power.max_element() <= 0.0 {
                        break;
                    }
                    power = new_power;
                    interactions += 1;
                    last_scatter = false;
                    ray = exit.ray;
                    continue;
                }
                p *= 1.0 - f;
                rest = Some(bsdf.without_subsurface());
            }
        }
        let u_lobe = rng.f32();
        let u = rng.vec2();
        let Some(bs) = rest
            .as_ref()
            .unwrap_or(&bsdf)
            .sample_component(si.wo, component, u_lobe, u)
        else {
            break;
        };
        let new_power = power * bs.importance_weight() / p;
        if !is_finite3(new_power) || new_power.max_element() <= 0.0 {
            break;
        }
        power = new_power;
        if bs.is_delta() || passes || component == Component::NearSpecular {
            specular_bounces += 1;
        } else if kind == MapKind::Caustic {
            break;
        }
        if bs.flags & LobeFlags::TRANSMISSION != 0 {
            scene.update_stack(&mut stack, &si, bs.wi);
        }
        interactions += 1;
        last_scatter = false;
        ray = si.spawn_ray(bs.wi);
    }
}

/// Traces batch `b`: `BATCH` photon paths.
fn trace_batch(scene: &Scene, params: &TraceParams, b: u64) -> Vec<RawPhoton> {
    let mut rng = Rng::derive(params.seed, 0x5048_4F54 ^ params.kind as u64, b);
    let ctx = scene.light_ctx();
    let mut out = Vec::new();
    for _ in 0..BATCH {
        let Some((li, pmf, _)) = scene.light_sampler.sample(rng.f32()) else {
            break;
        };
        let light: &Light = &scene.lights[li];
        let (u_pos, u_dir, u_sel) = (rng.vec2(), rng.vec2(), rng.f32());
        let le = if params.targets.is_empty() {
            light.sample_le(u_pos, u_dir, &ctx)
        } else {
            light.sample_le_towards(u_pos, u_dir, u_sel, params.targets, &ctx)
        };
        if let Some(le) = le {
            if is_finite3(le.weight) && le.weight.max_element() > 0.0 {
                let start = scene.light_stacks.get(li).copied().unwrap_or_default();
                let group = scene.light_group.get(li).copied().unwrap_or(0);
                trace_path(
                    scene,
                    le,
                    1.0 / pmf,
                    start,
                    (params.kind, group),
                    params.max_bounces,
                    &mut rng,
                    &mut out,
                );
            }
        }
    }
    out
}

/// Shoots photons until `params.target` are stored or the cap is reached, and builds the map.
/// Returns `None` when cancelled; the cancel flag is read before every batch and within the
/// kd-tree build.
///
/// Memory: when a round is done each batch's photons become their stored records (20 bytes,
/// or 28 with `f32` power), their power as traced: the division by the paths emitted, known
/// only when tracing stops, is the map's power scale, applied as the photons are read
/// ([`PhotonTree`]). The irradiance points are taken at the same time (16 bytes per point, one
/// per `irradiance::STRIDE` photons). Each round's records are appended to one array, in
/// parallel, and the round's batches freed; once tracing stops the kd-tree is balanced in that
/// array, in place. So the photon pass holds the records and the points' sites (20 + 16 / 4
/// bytes a photon), less than the finished map with its irradiance points (20 + 20 / 4), plus
/// one round in flight.
pub fn build_map(scene: &Scene, params: &TraceParams) -> Option<PhotonMap> {
    if params.f32_power {
        build_map_of::<PhotonF32>(scene, params, PhotonTree::F32)
    } else {
        build_map_of::<Photon>(scene, params, PhotonTree::Rgbe)
    }
}
