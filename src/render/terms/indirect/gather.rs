//! Final-gathering rays of the `indirect` term: a hemisphere gather with its gradients (the
//! irradiance cache's records and uncached points), a gather of the glossy lobes, and what a
//! gather ray takes where it lands.

use crate::geometry::{Ray, RayPath, Scatter, SurfaceInteraction};
use crate::materials::bsdf::{Bsdf, LobeFlags};
use crate::math::{Frame, Spectrum, PI};
use crate::media::MediumStack;
use crate::photon::map::{
    EstimateFilter, GroupShare, Select, FLAG_FIRST_HIT, FLAG_SUBSURFACE_EXIT,
};
use crate::photon::KnnScratch;
use crate::render::lightgroups::{scaled, Split};
use crate::render::photons::PhotonMaps;
use crate::render::terms::specular::{self, Follow};
use crate::sampling::Rng;
use crate::scene::shading::Crossing;
use crate::scene::{Scene, SceneHit};
use glam::Vec3;

/// Gather rays shorter than this many largest search radii take the full radiance estimate
/// at their hit rather than a precomputed irradiance point.
const NEAR_HIT_RADII: f32 = 1.0;

/// Specular bounces a gather ray may make before reaching a non-specular surface. Inside rough glass a
/// chain takes many bounces (its facets reflect internally beyond the smooth surface's total
/// internal reflection): a cap of 6 left the floor under a Roughness 0.3 glass sphere 2% dark
/// and the glass 3% dark against Cycles.
const GATHER_SPECULAR_DEPTH: u32 = 64;

/// How a gather hit takes the light its glossy lobes reflect from the global map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlossyAtHit {
    /// Always by their radiance estimate. Irradiance-cache records take this: Ward and
    /// Heckbert's gradients come from the rays' values, and a record's extrapolation is held
    /// at zero, so noisier rays would brighten the cache (measured: +6% on a ceiling lit only
    /// indirectly).
    Estimate,
    /// By Russian roulette with probability their share of the hit's reflection, weighted by
    /// its inverse: the same mean, at a fraction of the cost, for gathers averaged linearly.
    Roulette,
}

/// Radiance arriving at the gather point along `ray`, a ray of kind `path`, from the global
/// map, and the distance to the first surface (infinite when the ray escapes); each light
/// group's share goes to `split`.
#[allow(clippy::too_many_arguments)]
pub fn gather_radiance(
    scene: &Scene,
    maps: &PhotonMaps,
    mut ray: Ray,
    mut path: RayPath,
    glossy: GlossyAtHit,
    stack: &MediumStack,
    rng: &mut Rng,
    scratch: &mut KnnScratch,
    mut split: Option<&mut Split>,
) -> (Spectrum, f32) {
    let mut stack = *stack;
    let Some(global) = &maps.global else {
        return (Spectrum::ZERO, f32::INFINITY);
    };
    let mut beta = Spectrum::ONE;
    let mut acc = Spectrum::ZERO;
    let mut first_t = f32::INFINITY;
    for depth in 0..=GATHER_SPECULAR_DEPTH {
        // Through media (and their invisible boundaries) the gathered light is attenuated;
        // light scattered into the gather ray by the medium is not counted here.
        let (hit, tr) = if scene.has_media() {
            scene.intersect_through(&ray, &mut stack)
        } else {
            (scene.intersect(&ray), Spectrum::ONE)
        };
        beta *= tr;
        let SceneHit::Surface(mut si) = hit else {
            break;
        };
        si.path = path;
        if depth == 0 {
            first_t = si.t * ray.d.length();
        }
        let Some(mat) = scene.materials.get(si.material as usize) else {
            break;
        };
        match scene.crossing(mat, &si, || rng.f32()) {
            Crossing::Pass(w) => {
                // A transparent surface (each counts as one of the chain's vertices).
                path = path.crossed();
                beta *= w;
                scene.update_stack(&mut stack, &si, ray.d);
                ray = si.spawn_ray(ray.d);
                continue;
            }
            Crossing::Stop(w) => beta *= w,
        }
        let bsdf = scene.shading_bsdf(mat, &mut si);
        let passes = bsdf.passes_through();
        // A subsurface lobe: the light leaving it is that of the photons whose walks below
        // the material ended here.
        let entry = bsdf.subsurface_entry(si.wo);
        if let (Some((w, _)), Some(_)) = (entry, mat.subsurface()) {
            let b = beta * w;
            let mut sp = scaled(&mut split, b);
            acc += b * subsurface_exitance(scene, global, &si, maps, scratch, sp.as_mut());
        }
        if bsdf.has_non_delta() && !passes {
            // The estimate answers for the lobes it can resolve; near-specular ones are
            // followed below, as the photon pass treats them.
            let est = if entry.is_some() {
                bsdf.without_subsurface()
            } else {
                bsdf
            };
            let est = if est.flags() & LobeFlags::NEAR_SPECULAR != 0 {
                est.without_near_specular()
            } else {
                est
            };
            if est.has_non_delta() {
                // Short rays (corners, contact) take the full estimate: there the
                // irradiance changes within a point's reach.
                let near = si.t * ray.d.length() < NEAR_HIT_RADII * maps.global_r2.sqrt();
                let hit = GatherHit {
                    si: &si,
                    bsdf: &est,
                    stack: &stack,
                    near,
                    glossy,
                };
                let mut sp = scaled(&mut split, beta);
                acc += beta * hit_radiance(scene, global, &hit, maps, rng, scratch, sp.as_mut());
            }
        }
        // The specular and near-specular part of the surface, sampled alone (the rest is
        // covered by the estimate above).
        let Some(bs) = specular::next_bounce(&bsdf, si.wo, Follow::NearSpecular, rng) else {
            break;
        };
        beta *= bs.weight;
        if beta.max_element() < 1e-4 {
            break;
        }
        path = bs.next_path(path);
        ray = si.spawn_ray(bs.wi);
    }
    (acc, first_t)
}

/// A gather ray's first non-specular hit.
struct GatherHit<'a> {
    si: &'a SurfaceInteraction,
    /// Its BSDF without the near-specular lobes, which the gather ray follows instead.
    bsdf: &'a Bsdf,
    stack: &'a MediumStack,
    /// Closer to the gather point than a search radius (corners, contact).
    near: bool,
    glossy: GlossyAtHit,
}

/// The photons a gather hit's estimate takes: all but the first hits, whose light (straight
/// from an emitter) the hit takes by next-event estimation instead.
const GATHER_PHOTONS: Select = Select::without(FLAG_FIRST_HIT);

/// Radiance leaving a gather ray's hit towards the gather point. The light reaching the hit
/// straight from emitters is estimated exactly, by next-event estimation (`direct`): the
/// global map's first-hit photons, whose density estimate blurs shadow boundaries and
/// carries light from lit surfaces into the shadowed corners beside them (measured in
/// Blender's corpus: a sun's shadow on a courtyard floor 10-20% bright by the wall), are
/// left out. The rest, light that bounced at least once, comes from the global map: on an
/// opaque surface its diffuse lobes read the nearest precomputed irradiance point
/// (Christensen 1999, over the same photons), times their response, and its glossy lobes
/// take the radiance estimate of the photons themselves; elsewhere, and where no point
/// matches, the full radiance estimate with the BSDF (Jensen 2001, eq. 7.6).
fn hit_radiance(
    scene: &Scene,
    global: &crate::photon::map::PhotonMap,
    hit: &GatherHit,
    maps: &PhotonMaps,
    rng: &mut Rng,
    scratch: &mut KnnScratch,
    mut split: Option<&mut Split>,
) -> Spectrum {
    let (si, bsdf) = (hit.si, hit.bsdf);
    let direct = crate::render::terms::direct::estimate(
        scene,
        si,
        bsdf,
        hit.stack,
        rng,
        split.as_deref_mut(),
    );
    let photons = |bsdf: &Bsdf, scratch: &mut KnnScratch, split: Option<&mut Split>| {
        let mut share = split.map(|sp| move |g: usize, v: Spectrum| sp.add(g, v));
        global.radiance(
            si.p,
            si.ng,
            si.wo,
            bsdf,
            maps.gather,
            maps.global_r2,
            EstimateFilter::Constant,
            GATHER_PHOTONS,
            scratch,
            share.as_mut().map(|f| f as GroupShare),
        )
    };
    if !hit.near && bsdf.flags() & LobeFlags::TRANSMISSION == 0 {
        if let Some((pt, fractions)) = global
            .irradiance
            .as_ref()
            .and_then(|m| m.lookup(si.p, si.ng, scratch))
        {
            let e = pt.irradiance();
            let mut l = bsdf
                .diffuse_response(si.wo)
                .map_or(Spectrum::ZERO, |r| r * e);
            if let Some(sp) = split.as_mut() {
                sp.add_fractions(l, fractions);
            }
            if bsdf.has_glossy() {
                // The glossy lobes see the photons' directions: a highlight of a lamp or of a
                // bright wall is not uniform light (reflecting E / pi instead measured 1.5%
                // too bright on a room of default Principled walls). Their estimate (k
                // photons, the BSDF at each) costs more than the rest of the hit, for a
                // small share of its light: see `GlossyAtHit`.
                let share = glossy_share(bsdf, si.wo, bsdf.diffuse_response(si.wo));
                let q = match hit.glossy {
                    GlossyAtHit::Estimate => 1.0,
                    GlossyAtHit::Roulette => share.max(MIN_GLOSSY_ESTIMATE_PROBABILITY),
                };
                if q >= 1.0 || rng.f32() < q {
                    let mut sp = scaled(&mut split, Spectrum::splat(1.0 / q));
                    l += photons(&bsdf.glossy_part(), scratch, sp.as_mut()) / q;
                }
            }
            return direct + l;
        }
    }
    direct + photons(bsdf, scratch, split)
}

/// Radiance leaving a subsurface material at a gather ray's hit `si`: the flux of the photons
/// that left the surface there at the end of their walks below it (`FLAG_SUBSURFACE_EXIT`),
/// per unit area, over pi (the exit is Lambertian), per unit of the lobe's weight towards the
/// viewer (the walks' weights are in the photons' power). A density estimate over many walks, where walking below the surface
/// at each gather hit gave each irradiance-cache record the noise of a few walks (blotches
/// of colour on walls lit through the material).
fn subsurface_exitance(
    scene: &Scene,
    global: &crate::photon::map::PhotonMap,
    si: &SurfaceInteraction,
    maps: &PhotonMaps,
    scratch: &mut KnnScratch,
    split: Option<&mut Split>,
) -> Spectrum {
    if let Some(m) = global.exitance.as_ref() {
        if let Some(e) = m.lookup_smooth(si.p, si.ng, scratch) {
            let l = e / PI;
            if let Some(sp) = split {
                if let Some((_, fractions)) = m.lookup(si.p, si.ng, scratch) {
                    sp.add_fractions(l, fractions);
                }
            }
            return l;
        }
    }
    let select = Select::with(FLAG_SUBSURFACE_EXIT);
    let e = match split {
        Some(sp) => {
            let mut groups = vec![Spectrum::ZERO; scene.light_groups.len()];
            let e = global.irradiance_estimate_split(
                si.p,
                si.ng,
                maps.gather,
                maps.global_r2,
                select,
                scratch,
                &mut groups,
            );
            for (g, v) in groups.into_iter().enumerate() {
                sp.add(g, v / PI);
            }
            e
        }
        None => {
            global.irradiance_estimate(si.p, si.ng, maps.gather, maps.global_r2, select, scratch)
        }
    };
    e.irradiance / PI
}

/// The least probability of a gather hit's glossy estimate: its weight stays at most 16.
const MIN_GLOSSY_ESTIMATE_PROBABILITY: f32 = 1.0 / 16.0;

/// The glossy lobes' share of the light a surface reflects: their albedo over that of the
/// glossy and diffuse lobes (`response`, the diffuse lobes' response, times pi), 1 when the
/// surface reflects nothing.
pub fn glossy_share(bsdf: &Bsdf, wo: Vec3, response: Option<Spectrum>) -> f32 {
    let glossy = crate::math::luminance(bsdf.glossy_albedo(wo));
    let diffuse = response.map_or(0.0, |r| crate::math::luminance(r) * PI);
    if glossy + diffuse > 0.0 {
        glossy / (glossy + diffuse)
    } else {
        1.0
    }
}

/// The irradiance that a gather hit's diffuse lobes read from a precomputed point: that of the
/// photons [`hit_radiance`] takes.
pub const IRRADIANCE_POINT_PHOTONS: Select = GATHER_PHOTONS;

/// Final gathering of the glossy lobes alone (the diffuse part is the irradiance cache's):
/// the reflected indirect radiance through them, by sampling them.
#[allow(clippy::too_many_arguments)]
pub fn gather_glossy(
    scene: &Scene,
    maps: &PhotonMaps,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    rays: u32,
    stack: &MediumStack,
    rng: &mut Rng,
    scratch: &mut KnnScratch,
    mut split: Option<&mut Split>,
) -> Spectrum {
    let mut sum = Spectrum::ZERO;
    for _ in 0..rays {
        let Some(bs) = bsdf.sample_glossy(si.wo, rng.f32(), rng.vec2()) else {
            continue;
        };
        let mut sp = scaled(&mut split, bs.weight / rays.max(1) as f32);
        let (l, _) = gather_radiance(
            scene,
            maps,
            si.spawn_ray(bs.wi),
            bs.next_path(si.path),
            GlossyAtHit::Roulette,
            stack,
            rng,
            scratch,
            sp.as_mut(),
        );
        sum += bs.weight * l;
    }
    sum / rays.max(1) as f32
}

/// A stratified hemisphere gather with the data Ward and Heckbert's gradients need.
pub struct HemisphereGather {
    pub irradiance: Spectrum,
    /// Harmonic mean distance to the surfaces seen.
    pub harmonic_distance: f32,
    /// Rotational and translational gradients, one vector per colour channel.
    pub grad_r: [Vec3; 3],
    pub grad_t: [Vec3; 3],
}

/// Strata of a gather with about `rays` rays: M in theta, N = pi M in phi (Ward 1988).
pub fn strata(rays: u32) -> (usize, usize) {
    let m = ((rays as f32 / PI).sqrt().round() as usize).max(2);
    let n = ((rays as f32 / m as f32).round() as usize).max(4);
    (m, n)
}

/// Irradiance at `si` by a stratified cosine-weighted gather over the hemisphere of `n`, with
/// the rotational and translational gradients of Ward and Heckbert (1992), in the form given
/// by Křivánek et al., "Practical Global Illumination with Irradiance Caching" (2009), §2.
/// Each light group's share of the irradiance goes to `split`.
#[allow(clippy::too_many_arguments)]
pub fn gather_hemisphere(
    scene: &Scene,
    maps: &PhotonMaps,
    si: &SurfaceInteraction,
    n: Vec3,
    rays: u32,
    stack: &MediumStack,
    rng: &mut Rng,
    scratch: &mut KnnScratch,
    mut split: Option<&mut Split>,
) -> HemisphereGather {
    let (m, nn) = strata(rays);
    let norm = PI / (m * nn) as f32;
    let mut split = scaled(&mut split, Spectrum::splat(norm));
    let frame = Frame::from_normal(n);
    let path = si.path.scattered(Scatter::Diffuse, n.dot(si.wo) < 0.0);
    let mut l = vec![Spectrum::ZERO; m * nn];
    let mut r = vec![f32::INFINITY; m * nn];
    let mut theta = vec![0.0f32; m * nn];
    for j in 0..m {
        for k in 0..nn {
            let u = rng.vec2();
            let sin2 = (j as f32 + u.x) / m as f32;
            let sin_t = sin2.sqrt();
            let cos_t = (1.0 - sin2).max(0.0).sqrt();
            let phi = 2.0 * PI * (k as f32 + u.y) / nn as f32;
            let local = Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
            let (li, t) = gather_radiance(
                scene,
                maps,
                si.spawn_ray(frame.to_world(local)),
                path,
                GlossyAtHit::Estimate,
                stack,
                rng,
                scratch,
                split.as_mut(),
            );
            l[j * nn + k] = li;
            r[j * nn + k] = t;
            theta[j * nn + k] = sin_t.asin();
        }
    }
    let irradiance: Spectrum = l.iter().copied().sum::<Spectrum>() * norm;
    let inv_sum: f32 = r
        .iter()
        .map(|&t| {
            if t.is_finite() && t > 0.0 {
                1.0 / t
            } else {
                0.0
            }
        })
        .sum();
    let harmonic_distance = if inv_sum > 0.0 {
        (m * nn) as f32 / inv_sum
    } else {
        f32::INFINITY
    };

    let dir = |phi: f32| frame.to_world(Vec3::new(phi.cos(), phi.sin(), 0.0));
    let mut grad_r = [Vec3::ZERO; 3];
    let mut grad_t = [Vec3::ZERO; 3];
    for k in 0..nn {
        let phi_c = 2.0 * PI * (k as f32 + 0.5) / nn as f32;
        let phi_minus = 2.0 * PI * k as f32 / nn as f32;
        let u_k = dir(phi_c);
        let v_k = dir(phi_c + 0.5 * PI);
        let v_minus = dir(phi_minus + 0.5 * PI);
        let km = (k + nn - 1) % nn;
        for j in 0..m {
            let idx = j * nn + k;
            // Rotational: -tan(theta) L along v_k.
            let tan_t = theta[idx].tan();
            for c in 0..3 {
                grad_r[c] += v_k * (-tan_t * l[idx][c] * norm);
            }
            let sin_minus = (j as f32 / m as f32).sqrt();
            let sin_plus = ((j + 1) as f32 / m as f32).sqrt();
            // Translational, change across the phi boundary k-1 | k.
            let rmin = r[idx].min(r[j * nn + km]);
            if rmin.is_finite() && rmin > 0.0 {
                let w = (sin_plus - sin_minus) / rmin;
                for c in 0..3 {
                    grad_t[c] += v_minus * (w * (l[idx][c] - l[j * nn + km][c]));
                }
            }
            // Translational, change across the theta boundary j-1 | j.
            if j > 0 {
                let up = (j - 1) * nn + k;
                let rmin = r[idx].min(r[up]);
                if rmin.is_finite() && rmin > 0.0 {
                    let cos2 = 1.0 - sin_minus * sin_minus;
                    let w = 2.0 * PI / nn as f32 * sin_minus * cos2 / rmin;
                    for c in 0..3 {
                        grad_t[c] += u_k * (w * (l[idx][c] - l[up][c]));
                    }
                }
            }
        }
    }
    HemisphereGather {
        irradiance,
        harmonic_distance,
        grad_r,
        grad_t,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::photons;
    use crate::render::terms::testing;
    use crate::render::RenderSettings;

    /// A floor and a wall of Blender's default Principled BSDF under a point light, and the
    /// global map of its light.
    fn room() -> (Scene, PhotonMaps) {
        let sc = testing::scene(serde_json::json!({
            "materials": [{"type": "principled", "name": "default",
                           "base_color": [0.8, 0.8, 0.8], "roughness": 0.5}],
            "meshes": [testing::floor(0), {
                "name": "wall", "material": 0,
                "positions": [[2, -10, 0], [2, 10, 0], [2, 10, 5], [2, -10, 5]],
                "indices": [[0, 1, 2], [0, 2, 3]],
            }],
            "lights": [{"type": "point", "name": "bulb", "position": [0, 0, 1.5],
                        "power": 100.0}],
        }));
        let s = RenderSettings {
            photons: 20_000,
            ..Default::default()
        };
        let (maps, _) = photons::build(&sc, &s, 5, [true, false, false], None);
        assert!(maps.global.is_some());
        (sc, maps)
    }

    #[test]
    fn the_roulette_on_a_hits_glossy_estimate_keeps_its_mean() {
        let (sc, maps) = room();
        let (si, _) = testing::hit_below(&sc, 0.5);
        // A gather ray from the floor towards the wall: the wall's glossy coat reflects the
        // floor's light back along it.
        let ray = si.spawn_ray(Vec3::new(1.0, 0.0, 0.4).normalize());
        let stack = sc.camera_stack;
        let mut rng = Rng::new(9, 0);
        let mut scratch = KnnScratch::default();
        let (estimate, _) = gather_radiance(
            &sc,
            &maps,
            ray,
            RayPath::default(),
            GlossyAtHit::Estimate,
            &stack,
            &mut rng,
            &mut scratch,
            None,
        );
        let (estimate_again, _) = gather_radiance(
            &sc,
            &maps,
            ray,
            RayPath::default(),
            GlossyAtHit::Estimate,
            &stack,
            &mut rng,
            &mut scratch,
            None,
        );
        let n = 20_000;
        let (mut sum, mut sum2, mut skipped) = (0.0f64, 0.0f64, 0);
        for _ in 0..n {
            let (l, _) = gather_radiance(
                &sc,
                &maps,
                ray,
                RayPath::default(),
                GlossyAtHit::Roulette,
                &stack,
                &mut rng,
                &mut scratch,
                None,
            );
            let y = l.y as f64;
            sum += y;
            sum2 += y * y;
            skipped += (y < estimate.y as f64) as u32;
        }
        let mean = sum / n as f64;
        let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        let e = estimate.y as f64;
        // The estimate is the same each time (a point light's direct light has no noise).
        assert_eq!(estimate, estimate_again);
        // Most hits leave the glossy estimate out...
        assert!(skipped > n / 2, "{skipped} of {n}");
        // ... and the mean is the estimate's: within 4 standard errors and 0.5%.
        assert!(
            (mean - e).abs() < 4.0 * se && (mean - e).abs() < 0.005 * e,
            "{mean} ± {se} against {e}"
        );
        // An error of 2% of the gathered light would be told apart.
        assert!(4.0 * se < 0.02 * e, "{se} against {e}");
    }

    #[test]
    fn the_glossy_share_of_lambert_is_0_and_of_metal_1() {
        let (sc, _) = room();
        let (si, bsdf) = testing::hit_below(&sc, 0.0);
        let share = glossy_share(&bsdf, si.wo, bsdf.diffuse_response(si.wo));
        // Blender's default Principled BSDF (specular 0.5, roughness 0.5) seen from above: a
        // coat reflecting about 4% over a base of 0.8.
        assert!(share > 0.02 && share < 0.1, "{share}");
        let lambert = testing::scene(serde_json::json!({
            "materials": [{"type": "diffuse", "name": "grey", "color": [0.5, 0.5, 0.5]}],
            "meshes": [testing::floor(0)],
        }));
        let (si, bsdf) = testing::hit_below(&lambert, 0.0);
        assert_eq!(
            glossy_share(&bsdf, si.wo, bsdf.diffuse_response(si.wo)),
            0.0
        );
        let metal = testing::scene(serde_json::json!({
            "materials": [{"type": "principled", "name": "metal", "metallic": 1.0,
                           "roughness": 0.4}],
            "meshes": [testing::floor(0)],
        }));
        let (si, bsdf) = testing::hit_below(&metal, 0.0);
        assert_eq!(
            glossy_share(&bsdf, si.wo, bsdf.diffuse_response(si.wo)),
            1.0
        );
    }
}
