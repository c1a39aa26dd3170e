//! `volume`: light scattered towards the eye by participating media, by ray marching with a
//! jittered step (Jensen 2001, §10.4; Jensen & Christensen 1998). At each step the in-scattered
//! radiance is single scattering from the lights by next-event estimation, with transmittance
//! along the shadow ray, plus multiple scattering (and volume caustics) from the volume photon
//! map: sum_p p(wo, wi_p) Phi_p / (4/3 pi r^3).
//!
//! Each step of length D starting at distance t0 contributes
//! T(t0) * integral_0^D exp(-sigma_t s) L_s(t0 + s) ds, estimated with one point drawn from the
//! exponential inside the step. This is exact for constant L_s, so dense media converge to
//! their dark answer instead of a step-size artefact, and thin media to vacuum. The number of
//! steps is bounded, and the march stops where the transmittance is below 1e-4.

use crate::geometry::Ray;
use crate::math::Spectrum;
use crate::media::MediumStack;
use crate::photon::map::GroupShare;
use crate::photon::KnnScratch;
use crate::render::lightgroups::{scaled, Split};
use crate::render::photons::PhotonMaps;
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::Vec3;

/// Steps at most per medium segment.
pub const MAX_STEPS: u32 = 256;
/// Transmittance below which a march stops.
const T_CUTOFF: f32 = 1e-4;

/// Ray-marching parameters.
#[derive(Clone, Copy, Debug)]
pub struct MarchSettings {
    /// Step length in scene units.
    pub step: f32,
    /// Photons per volume radiance estimate, and the largest squared radius.
    pub gather: usize,
    pub max_r2: f32,
}

/// The default ray-marching step, as a fraction of the scene's bounding radius.
pub const DEFAULT_STEP_FRACTION: f32 = 1.0 / 64.0;

impl MarchSettings {
    /// The march of a render: its step (`volume_step`, or [`DEFAULT_STEP_FRACTION`] of the
    /// scene's radius) and gather count, and `max_r2` of its photon maps.
    pub fn for_render(s: &crate::render::RenderSettings, scene: &Scene, max_r2: f32) -> Self {
        MarchSettings {
            step: s
                .volume_step
                .unwrap_or(scene.radius * DEFAULT_STEP_FRACTION),
            gather: s.gather,
            max_r2,
        }
    }
}

#[inline]
fn mean(c: Spectrum) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

/// (1 - exp(-s x)) / s without 0/0: x when s x is tiny.
#[inline]
fn one_minus_exp_over(s: f32, x: f32) -> f32 {
    let sx = s as f64 * x as f64;
    if sx < 1e-6 {
        x * (1.0 - 0.5 * sx as f32)
    } else {
        (-(-sx).exp_m1() / s as f64) as f32
    }
}

/// exp(-sigma_t d) per channel, formed in f64 so huge optical depths give 0, not NaN.
#[inline]
fn exp_neg(sigma_t: Spectrum, d: f32) -> Spectrum {
    let f = |s: f32| (-(s as f64) * d as f64).exp() as f32;
    Spectrum::new(f(sigma_t.x), f(sigma_t.y), f(sigma_t.z))
}

/// What a march found: the light scattered towards the ray's origin, the transmittance over
/// the segment, and the steps and volume-map lookups it took.
pub struct March {
    pub radiance: Spectrum,
    pub transmittance: Spectrum,
    pub steps: u64,
    pub volume_lookups: u64,
    /// Of the lookups, those a precomputed point answered.
    pub volume_point_reads: u64,
}

/// Light scattered towards `-dir` along `[0, dist)` from `o` inside `medium`, and the
/// transmittance over the segment. Each light group's share of the light goes to `split`.
#[allow(clippy::too_many_arguments)]
pub fn march(
    scene: &Scene,
    maps: &PhotonMaps,
    medium: u32,
    stack: &MediumStack,
    o: Vec3,
    dir: Vec3,
    dist: f32,
    s: &MarchSettings,
    rng: &mut Rng,
    scratch: &mut KnnScratch,
    mut split: Option<&mut Split>,
) -> March {
    let med = &scene.media[medium as usize];
    let done = |radiance, transmittance, steps, volume_lookups, volume_point_reads| March {
        radiance,
        transmittance,
        steps,
        volume_lookups,
        volume_point_reads,
    };
    // An unbounded segment (world fog, ray escaping): beyond the scene's bounding sphere no
    // light source but those at infinity remains; march to the far side of the sphere.
    let oc = o - scene.center;
    let b = oc.dot(dir);
    let c = oc.length_squared() - scene.radius * scene.radius;
    let exit = -b + (b * b - c).max(0.0).sqrt();
    let seg = if dist.is_finite() {
        dist
    } else {
        exit.max(0.0)
    };
    let t_total = if dist.is_finite() {
        med.transmittance_along(o, dir, dist)
    } else {
        Spectrum::ZERO
    };
    if seg <= 0.0 {
        return done(Spectrum::ZERO, t_total, 0, 0, 0);
    }
    // In a homogeneous medium only the part of the segment with transmittance above the
    // cut-off matters; a grid's march stops when the accumulated transmittance falls below it.
    let useful = match med {
        crate::media::Medium::Homogeneous(h) if h.sigma_t.min_element() > 0.0 => {
            seg.min(-T_CUTOFF.ln() / h.sigma_t.min_element())
        }
        _ => seg,
    };
    let n = ((useful / s.step.max(1e-12)).ceil() as u32).clamp(1, MAX_STEPS);
    let step = useful / n as f32;
    let phase = med.phase();
    let wo = -dir;
    let mut l = Spectrum::ZERO;
    let mut t_start = Spectrum::ONE;
    let (mut steps, mut lookups, mut point_reads) = (0u64, 0u64, 0u64);
    // The volume map's group shares at a step, before its reachable fraction is known.
    let mut shares = vec![Spectrum::ZERO; split.as_ref().map_or(0, |sp| sp.len())];
    for i in 0..n {
        if t_start.max_element() < T_CUTOFF {
            break;
        }
        let t0 = i as f32 * step;
        // Extinction of this step, taken at its middle (constant for homogeneous media).
        let (_, sigma_t) = med.coefficients_at(o + dir * (t0 + 0.5 * step));
        let st_avg = mean(sigma_t);
        // A point in the step, with density proportional to exp(-st_avg s).
        let u = rng.f32();
        let (s_in, inv_pdf) = if st_avg * step < 1e-4 {
            (u * step, step)
        } else {
            let norm = one_minus_exp_over(st_avg, step);
            let s_in = -((1.0 - u * (1.0 - (-st_avg * step).exp())).max(1e-30)).ln() / st_avg;
            (s_in.min(step), norm * (st_avg * s_in).exp())
        };
        let x = o + dir * (t0 + s_in);
        let (sigma_s, _) = med.coefficients_at(x);
        let weight = t_start * exp_neg(sigma_t, s_in) * inv_pdf;
        let mut inscatter = Spectrum::ZERO;
        if sigma_s.max_element() > 0.0 {
            let mut sp = scaled(&mut split, weight * sigma_s);
            inscatter += sigma_s * single_scattering(scene, stack, x, wo, &phase, rng, sp.as_mut());
        }
        if let Some(vm) = &maps.volume {
            shares.iter_mut().for_each(|v| *v = Spectrum::ZERO);
            let mut share = |g: usize, v: Spectrum| {
                if let Some(a) = shares.get_mut(g) {
                    *a += v;
                }
            };
            let share: Option<GroupShare> = split.is_some().then_some(&mut share);
            // In an isotropic medium the nearest precomputed point answers where one reaches.
            // Points hold the total only, so a render split by light group reads the map.
            let points = maps
                .volume_points
                .as_ref()
                .filter(|_| phase.g == 0.0 && share.is_none());
            if let Some(l_vol) = points.and_then(|vp| vp.lookup(x, scratch)) {
                inscatter += l_vol;
                point_reads += 1;
            } else if let Some((l_vol, r2)) =
                vm.volume_radiance(x, wo, &phase, s.gather, s.max_r2, scratch, share)
            {
                let reach = reachable_fraction(scene, x, r2.sqrt(), rng);
                inscatter += l_vol / reach;
                if let Some(sp) = split.as_mut() {
                    for (g, v) in shares.iter().enumerate() {
                        sp.add(g, weight * *v / reach);
                    }
                }
            }
            lookups += 1;
        }
        steps += 1;
        l += weight * inscatter;
        t_start *= exp_neg(sigma_t, step);
    }
    done(l, t_total, steps, lookups, point_reads)
}

/// Directions of [`reachable_fraction`]'s estimate, one per stratum of the sphere.
const SUPPORT_RAYS: u32 = 8;
/// The smallest fraction it returns: a cube's corner (an eighth of the sphere) is the tightest
/// place a medium usually has.
const MIN_SUPPORT: f32 = 0.125;

/// The part of the sphere of radius `r` around `x` that photons in the medium reach: the
/// volume within `r` seen from `x` before any surface (a medium's boundary, an object in it),
/// over the sphere's, by `SUPPORT_RAYS` stratified directions:
/// mean_j (min(d_j, r) / r)^3, with `d_j` the distance to the first surface along direction j
/// (exact for regions star-shaped around `x`, as directions grow). A density estimate of a
/// sphere cut by a boundary counts photons of the part inside only; dividing by this removes
/// the darkening within one radius of a medium's walls, floor and objects. Deep inside, every
/// ray runs its full length and the fraction is exactly 1.
pub fn reachable_fraction(scene: &Scene, x: Vec3, r: f32, rng: &mut Rng) -> f32 {
    reachable_fraction_with(scene, x, r, rng, SUPPORT_RAYS)
}

/// [`reachable_fraction`] with `rays` directions (even), for estimates made once and read
/// many times.
pub fn reachable_fraction_with(scene: &Scene, x: Vec3, r: f32, rng: &mut Rng, rays: u32) -> f32 {
    // With no surface within r every ray below runs its full length: the fraction is 1.
    if !(r > 0.0) || !scene.accel.any_surface_near(x, r) {
        return 1.0;
    }
    let (nu, nv) = (2u32, (rays / 2).max(1));
    let mut sum = 0.0;
    for j in 0..nu * nv {
        let (a, b) = (j % nu, j / nu);
        let u = glam::Vec2::new(
            (a as f32 + rng.f32()) / nu as f32,
            (b as f32 + rng.f32()) / nv as f32,
        );
        let d = crate::sampling::warp::square_to_uniform_sphere(u);
        let ray = Ray { o: x, d, t_max: r };
        let t = scene.accel.intersect(&ray).map_or(r, |h| h.t.min(r));
        let q = t / r;
        sum += q * q * q;
    }
    (sum / (nu * nv) as f32).max(MIN_SUPPORT)
}

/// Radiance from the lights arriving at `x` in a medium and scattered towards `wo`, per unit
/// scattering coefficient: light sampling (`LightSampler::next_event`) with transmittance along
/// the shadow ray.
fn single_scattering(
    scene: &Scene,
    stack: &MediumStack,
    x: Vec3,
    wo: Vec3,
    phase: &crate::media::HenyeyGreenstein,
    rng: &mut Rng,
    mut split: Option<&mut Split>,
) -> Spectrum {
    let ctx = scene.light_ctx();
    let mut l = Spectrum::ZERO;
    scene.light_sampler.next_event(rng.f32(), |li, pmf| {
        let Some(ls) = scene.lights[li].sample_li(x, Vec3::ZERO, rng.vec2(), &ctx) else {
            return;
        };
        let p = phase.eval(wo, ls.wi);
        if !(p > 0.0) {
            return;
        }
        let shadow = if ls.dist.is_finite() {
            Ray {
                o: x,
                d: ls.p - x,
                t_max: 1.0 - crate::geometry::SHADOW_EPSILON,
            }
        } else {
            Ray {
                o: x,
                d: ls.wi,
                t_max: f32::INFINITY,
            }
        };
        let tr = scene.transmittance(&shadow, stack);
        let c = ls.li * tr * (p / (pmf * ls.pdf));
        l += c;
        if let Some(sp) = split.as_mut() {
            sp.add_light(scene, li as u32, c);
        }
    });
    l
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::PI;
    use crate::render::terms::testing;

    const SIGMA_S: f32 = 0.2;
    const SIGMA_A: f32 = 0.05;
    const G: f32 = 0.3;
    const LIGHT: Vec3 = Vec3::new(0.0, 0.0, 1.5);

    /// World fog over the floor, lit by a point light of `power` W at `LIGHT`.
    fn foggy(power: f32) -> Scene {
        testing::scene(serde_json::json!({
            "materials": [{"type": "diffuse", "name": "grey", "color": [0.5, 0.5, 0.5]}],
            "meshes": [testing::floor(0)],
            "lights": [{"type": "point", "name": "bulb", "position": LIGHT.to_array(),
                        "power": power}],
            "media": [{"name": "fog", "sigma_a": [SIGMA_A, SIGMA_A, SIGMA_A],
                       "sigma_s": [SIGMA_S, SIGMA_S, SIGMA_S],
                       "g": G}],
            "world_medium": 0,
        }))
    }

    fn no_maps() -> PhotonMaps {
        PhotonMaps {
            global: None,
            caustic: None,
            volume: None,
            volume_points: None,
            gather: 50,
            global_r2: 0.25,
            caustic_r2: 0.25,
        }
    }

    /// The march along x from (-2, 0, 1) over 4 units, averaged over `n` marches.
    fn along(sc: &Scene, n: u32) -> (f32, f32) {
        let s = MarchSettings {
            step: 0.05,
            gather: 50,
            max_r2: 0.25,
        };
        let (o, dir, dist) = (Vec3::new(-2.0, 0.0, 1.0), Vec3::X, 4.0);
        let mut rng = Rng::new(3, 0);
        let mut scratch = KnnScratch::default();
        let mut l = 0.0;
        let mut t = 0.0;
        for _ in 0..n {
            let m = march(
                sc,
                &no_maps(),
                0,
                &sc.camera_stack,
                o,
                dir,
                dist,
                &s,
                &mut rng,
                &mut scratch,
                None,
            );
            l += m.radiance.x;
            t = m.transmittance.x;
        }
        (l / n as f32, t)
    }

    /// Single scattering along the same ray by quadrature: the integral over t of
    /// T(t) sigma_s p(theta) I exp(-sigma_t r) / r², with r the distance to the light.
    fn single_scattering_quadrature(power: f32) -> f32 {
        let sigma_t = SIGMA_S + SIGMA_A;
        let i = power / (4.0 * PI);
        let hg = |c: f32| (1.0 - G * G) / (4.0 * PI * (1.0 + G * G - 2.0 * G * c).powf(1.5));
        let n = 20_000;
        let h = 4.0 / n as f32;
        (0..n)
            .map(|k| {
                let t = (k as f32 + 0.5) * h;
                let x = Vec3::new(-2.0 + t, 0.0, 1.0);
                let to_x = x - LIGHT;
                let r = to_x.length();
                // The light travels along to_x and is scattered towards the origin, along -X.
                let cos = (to_x / r).dot(-Vec3::X);
                (-sigma_t * t).exp() * SIGMA_S * hg(cos) * i * (-sigma_t * r).exp() / (r * r) * h
            })
            .sum()
    }

    #[test]
    fn the_transmittance_of_a_homogeneous_segment_is_beers_law() {
        let (_, t) = along(&foggy(10.0), 1);
        let expected = (-(SIGMA_S + SIGMA_A) * 4.0).exp();
        assert!((t / expected - 1.0).abs() < 1e-5, "{t} against {expected}");
    }

    #[test]
    fn single_scattering_from_a_point_light_matches_its_quadrature() {
        let power = 10.0;
        let expected = single_scattering_quadrature(power);
        let (got, _) = along(&foggy(power), 2000);
        assert!(
            (got / expected - 1.0).abs() < 0.005,
            "{got} against {expected}"
        );
        // A light 2% brighter is told apart.
        let (brighter, _) = along(&foggy(power * 1.02), 2000);
        assert!(
            brighter / expected - 1.0 > 0.012,
            "{brighter} against {expected}"
        );
    }

    #[test]
    fn a_medium_without_lights_or_photons_scatters_nothing() {
        let (l, _) = along(&foggy(0.0), 10);
        assert_eq!(l, 0.0);
    }
}
