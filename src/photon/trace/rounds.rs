//! The photon pass's rounds: batches traced in parallel until the map holds its target, their
//! records appended in order, the irradiance points taken, and the kd-tree balanced in place.

use super::{record_of, trace_batch, IrradianceSite, RawPhoton, TraceParams, BATCH};
use crate::photon::append::append_parallel;
use crate::photon::irradiance::{self, IrradianceMap};
use crate::photon::map::{PhotonMap, PhotonTree, Select, FLAG_SUBSURFACE_EXIT};
use crate::photon::{PhotonKdTree, PhotonRecord};
use crate::scene::Scene;
use glam::Vec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// [`super::build_map`] with records of type `P`; `tree` wraps the kd-tree and the power scale.
pub(super) fn build_map_of<P: PhotonRecord>(
    scene: &Scene,
    params: &TraceParams,
    tree: fn(PhotonKdTree<P>, f32) -> PhotonTree,
) -> Option<PhotonMap> {
    let cancelled = || params.cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    // The stored records, in batch order; each round's are appended in parallel.
    let mut photons: Vec<P> = Vec::new();
    // The irradiance points: every `irradiance::STRIDE`-th photon traced, counted over the
    // rounds in order.
    let take_points = params.irradiance.is_some();
    let mut points: Vec<IrradianceSite> = Vec::new();
    let mut seen = 0usize;
    let mut stored = 0usize;
    let mut batches = 0u64;
    let max_batches = params.max_emitted.div_ceil(BATCH).max(1);
    let mut round = 4u64;
    while stored < params.target && batches < max_batches {
        if cancelled() {
            return None;
        }
        let n = round.min(max_batches - batches);
        let results: Vec<Vec<RawPhoton>> = (batches..batches + n)
            .into_par_iter()
            .map(|b| {
                if cancelled() {
                    return Vec::new();
                }
                trace_batch(scene, params, b)
            })
            .collect();
        if cancelled() {
            return None;
        }
        // The round's records and its irradiance points, batch by batch in parallel; each
        // batch knows the index of its first photon, so the points are the same for any
        // thread count. The records are then appended to the map's array, in parallel.
        let mut first = Vec::with_capacity(results.len());
        let mut count = 0usize;
        for r in &results {
            first.push(seen + count);
            count += r.len();
        }
        seen += count;
        let converted: Vec<(Vec<P>, Vec<IrradianceSite>)> = results
            .into_par_iter()
            .zip(first)
            .map(|(raw, first)| {
                let points = if take_points {
                    let skip =
                        (irradiance::STRIDE - first % irradiance::STRIDE) % irradiance::STRIDE;
                    raw.iter()
                        .skip(skip)
                        .step_by(irradiance::STRIDE)
                        .map(|r| (r.p, r.n, r.flags & FLAG_SUBSURFACE_EXIT as u8 != 0))
                        .collect()
                } else {
                    Vec::new()
                };
                (raw.iter().filter_map(record_of::<P>).collect(), points)
            })
            .collect();
        let batches_done: Vec<&[P]> = converted.iter().map(|c| &c.0[..]).collect();
        append_parallel(&mut photons, &batches_done);
        for (_, pts) in &converted {
            points.extend_from_slice(pts);
        }
        drop(converted);
        stored += count;
        batches += n;
        // Size the next round from the storage rate seen so far (deterministic).
        let per_batch = stored as f64 / batches as f64;
        let missing = params.target.saturating_sub(stored) as f64;
        round = if per_batch > 0.0 {
            ((missing / per_batch).ceil() as u64).clamp(1, 512)
        } else {
            (round * 2).min(512)
        };
    }
    let emitted = batches * BATCH;
    let t = std::time::Instant::now();
    let kd = balance(photons, params.cancel)?;
    let mut map = PhotonMap {
        kind: params.kind,
        tree: tree(kd, 1.0 / emitted as f32),
        irradiance: None,
        exitance: None,
        emitted,
        build_seconds: t.elapsed().as_secs_f64(),
    };
    if let Some((k, max_r2, select)) = params.irradiance {
        // The sites at subsurface exits hold the exits' exitance, the others irradiance.
        // (In place: the others stay in the sites' own array.)
        let exits: Vec<IrradianceSite> = points.iter().filter(|s| s.2).copied().collect();
        if !exits.is_empty() {
            points.retain(|s| !s.2);
        }
        let strip = |v: Vec<IrradianceSite>| v.into_iter().map(|(p, n, _)| (p, n)).collect();
        let build = |sites: Vec<(Vec3, (u8, u8))>, select: Select| {
            let mut m = IrradianceMap::build(&map, sites, k, max_r2, select, params.cancel)?;
            if !scene.light_groups.is_empty() {
                m.split_groups(&map, scene.light_groups.len(), k, select, params.cancel)?;
            }
            Some(m)
        };
        let irradiance = build(strip(points), select)?;
        let exitance = if exits.is_empty() {
            None
        } else {
            Some(build(strip(exits), Select::with(FLAG_SUBSURFACE_EXIT))?)
        };
        map.irradiance = Some(irradiance);
        map.exitance = exitance;
    }
    Some(map)
}

/// The kd-tree of `photons`, balanced with the cancel flag polled if there is one (`None`
/// when cancelled).
fn balance<P: PhotonRecord>(
    photons: Vec<P>,
    cancel: Option<&AtomicBool>,
) -> Option<PhotonKdTree<P>> {
    if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
        return None;
    }
    match cancel {
        Some(flag) => PhotonKdTree::build_cancellable(photons, flag),
        None => Some(PhotonKdTree::build(photons)),
    }
}
