//! Fills the irradiance cache before the camera pass, in deterministic rounds: pixel centres
//! on a grid of stride 32, 16, ..., 1; in each round, the first surface with a diffuse component seen through
//! each pixel (following perfect specular bounces, and through invisible medium boundaries) that the cache does not yet cover gets a
//! record, computed in parallel and inserted in pixel order. The camera pass then only reads
//! the cache, so the image is the same for any thread count.

use super::eye::EyeCtx;
use super::irradiance_cache::{IrradianceCache, Record};
use super::lightgroups::{fractions, Split};
use super::settings::RenderSettings;
use super::terms::indirect::gather_hemisphere;
use super::terms::specular::{self, Follow};
use crate::error::{Error, Result};
use crate::geometry::{Ray, RayPath, SurfaceInteraction};
use crate::math::Spectrum;
use crate::photon::KnnScratch;
use crate::sampling::Rng;
use crate::scene::shading::Crossing;
use crate::scene::SceneHit;
use glam::{Vec2, Vec3};
use rayon::prelude::*;

/// Record radii, in pixel footprints at the record's distance, scaled by 1/a (Křivánek et al.
/// 2009, §2.3: radii clamped in screen space).
const R_MIN_PIXELS: f32 = 1.5;
const R_MAX_PIXELS: f32 = 30.0;

/// Invisible medium boundaries a first-surface search crosses at most (as the camera pass).
const MAX_CROSSINGS: u32 = 64;

/// First point with a diffuse component seen through pixel (x, y), with its normal and the path length.
fn first_diffuse(
    ctx: &EyeCtx,
    x: usize,
    y: usize,
    rng: &mut Rng,
) -> Option<(SurfaceInteraction, Vec3, f32)> {
    let scene = ctx.scene;
    let cr = scene
        .camera
        .generate_ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), Vec2::splat(0.5));
    let mut ray = Ray {
        o: cr.o,
        d: cr.d,
        t_max: cr.t_max,
    };
    let mut length = 0.0;
    let (mut bounces, mut crossings) = (0, 0);
    // As the camera pass walks it (the Light Path node reads the same kinds of ray).
    let mut path = RayPath::CAMERA_RAY;
    while bounces <= ctx.settings.max_specular_depth {
        let SceneHit::Surface(mut si) = scene.intersect(&ray) else {
            return None;
        };
        si.path = path;
        length += si.t * ray.d.length();
        let mat = scene.materials.get(si.material as usize)?;
        if let Crossing::Pass(_) = scene.crossing(mat, &si, || rng.f32()) {
            // An invisible medium boundary or a transparent surface: the camera pass crosses
            // it, and so does the fill.
            crossings += 1;
            if crossings > MAX_CROSSINGS {
                return None;
            }
            if !mat.is_null() {
                path = path.crossed();
            }
            ray = si.spawn_ray(ray.d);
            continue;
        }
        bounces += 1;
        let bsdf = scene.shading_bsdf(mat, &mut si);
        let passes = bsdf.passes_through();
        if bsdf.has_non_delta() && !passes {
            bsdf.diffuse_response(si.wo)?;
            let n = si.ng.dot(si.ns).signum() * si.ns;
            return Some((si, n, length));
        }
        let bs = specular::next_bounce(&bsdf, si.wo, Follow::Specular, rng)?;
        path = bs.next_path(path);
        ray = si.spawn_ray(bs.wi);
    }
    None
}

/// A new cache, filled for the view of `ctx`'s scene.
pub fn fill(
    ctx: &EyeCtx,
    s: &RenderSettings,
    progress: &(dyn Fn(f32) + Sync),
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<IrradianceCache> {
    let a = s.cache_tolerance.max(1e-3);
    let cache = IrradianceCache::new(a, 0.05 * ctx.scene.radius);
    extend(ctx, s, cache, progress, cancelled)
}

/// `cache` (records are world-space: one filled for another view of the same scene, with
/// the same maps and settings) extended for the view of `ctx`'s scene: the same rounds as
/// [`fill`], where only the points the cache does not cover yet get a record. A cache
/// filled for this very view gets none.
pub fn extend(
    ctx: &EyeCtx,
    s: &RenderSettings,
    mut cache: IrradianceCache,
    progress: &(dyn Fn(f32) + Sync),
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<IrradianceCache> {
    let scene = ctx.scene;
    let (w, h) = (scene.width, scene.height);
    let a = s.cache_tolerance.max(1e-3);
    let r_cap = 0.25 * scene.radius / a;
    let pixel_angle = scene.camera.pixel_angle();
    let rays = s.final_gather_rays.max(1);
    let strides: Vec<usize> = [32usize, 16, 8, 4, 2, 1].into_iter().collect();
    progress(0.0);
    for (round, &stride) in strides.iter().enumerate() {
        if cancelled() {
            return Err(Error::Cancelled);
        }
        let coarser = if round == 0 {
            usize::MAX
        } else {
            strides[round - 1]
        };
        let pixels: Vec<(usize, usize)> = (0..h)
            .step_by(stride)
            .flat_map(|y| (0..w).step_by(stride).map(move |x| (x, y)))
            .filter(|&(x, y)| round == 0 || x % coarser != 0 || y % coarser != 0)
            .collect();
        let candidates: Vec<(usize, SurfaceInteraction, Vec3, f32)> = pixels
            .par_iter()
            .filter_map(|&(x, y)| {
                let idx = y * w + x;
                let mut rng = Rng::derive(s.seed, 0x1C, idx as u64);
                let (si, n, len) = first_diffuse(ctx, x, y, &mut rng)?;
                cache
                    .lookup(si.p, n, None)
                    .is_none()
                    .then_some((idx, si, n, len))
            })
            .collect();
        // The cancel flag is read before every record (a record can take many gather rays).
        let records: Option<Vec<Record>> = candidates
            .par_iter()
            .map_init(KnnScratch::new, |scratch, (idx, si, n, len)| {
                if cancelled() {
                    return None;
                }
                let mut rng = Rng::derive(s.seed, 0x1D, *idx as u64);
                let stack = scene.medium_stack_at(si.p + *n * (1e-4 * scene.radius));
                // With light groups, each group's share of the record's irradiance.
                let mut parts = vec![Spectrum::ZERO; scene.light_groups.len()];
                let mut split = Split::new(&mut parts);
                let g = gather_hemisphere(
                    scene,
                    ctx.maps,
                    si,
                    *n,
                    rays,
                    &stack,
                    &mut rng,
                    scratch,
                    (!split.is_empty()).then_some(&mut split),
                );
                let fp = (len * pixel_angle).max(1e-6);
                let r_min = (R_MIN_PIXELS * fp / a).min(r_cap);
                let r_max = (R_MAX_PIXELS * fp / a).min(r_cap).max(r_min);
                let mut rec = Record::new(si.p, *n, &g, r_min, r_max);
                rec.groups = fractions(&parts, g.irradiance);
                Some(rec)
            })
            .collect();
        for r in records.ok_or(Error::Cancelled)? {
            cache.insert(r);
        }
        progress((round + 1) as f32 / strides.len() as f32);
    }
    cache.settle();
    Ok(cache)
}
