//! The photon pass as the renderer runs it: which maps the scene needs, their parameters,
//! and why a map was skipped.

use crate::lights::Target;
use crate::photon::map::{MapKind, PhotonMap};
use crate::photon::trace::{build_map, TraceParams};
use crate::photon::volume_points::VolumePointMap;
use crate::render::settings::RenderSettings;
use crate::scene::Scene;
use serde::Serialize;
use std::sync::atomic::AtomicBool;

/// The maps of one render and the parameters of their radiance estimates.
pub struct PhotonMaps {
    pub global: Option<PhotonMap>,
    pub caustic: Option<PhotonMap>,
    pub volume: Option<PhotonMap>,
    /// Precomputed radiance at a subset of the volume map's photons, for isotropic media
    /// (`photon::volume_points`); Jensen's mode only.
    pub volume_points: Option<VolumePointMap>,
    pub gather: usize,
    pub global_r2: f32,
    pub caustic_r2: f32,
}

/// Statistics of one map, or the reason it was not built.
#[derive(Clone, Debug, Serialize)]
pub struct MapStats {
    pub map: &'static str,
    pub built: bool,
    pub stored: u64,
    pub emitted: u64,
    pub memory_bytes: u64,
    /// Bytes per stored photon: 20 (RGBE power) or 28 (`f32` power).
    pub bytes_per_photon: u64,
    /// Largest search radius of the map's radiance estimates, in scene units (`--radius`, or
    /// 0.1 of the scene's bounding-sphere radius).
    pub max_radius: f32,
    pub seconds: f64,
    /// Of `seconds`, the kd-tree build.
    pub kdtree_seconds: f64,
    /// Points of precomputed irradiance (global map: every fourth photon), in `memory_bytes`.
    pub irradiance_points: u64,
    /// Points of precomputed volume radiance (volume map, scenes with an isotropic medium:
    /// every fourth photon).
    pub volume_points: u64,
    /// Points of precomputed exitance at subsurface exits (global map, scenes with a
    /// subsurface material: the exits among every fourth photon), in `memory_bytes`.
    pub exitance_points: u64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skipped_because: Option<String>,
}

/// Bounding spheres of the instances whose materials are specular (mirrors, glass).
pub fn specular_targets(scene: &Scene) -> Vec<Target> {
    let mut out = Vec::new();
    for (ii, inst) in scene.accel.instances().iter().enumerate() {
        let mesh = scene.accel.mesh(inst.mesh);
        let specular = mesh.material_ids.iter().any(|&m| {
            scene
                .materials
                .get(m as usize)
                .is_some_and(|m| m.has_specular())
        });
        if !specular {
            continue;
        }
        let mut b = crate::math::Bounds3::EMPTY;
        for prim in 0..mesh.indices.len() as u32 {
            if scene
                .materials
                .get(mesh.material_ids[prim as usize] as usize)
                .is_some_and(|m| m.has_specular())
            {
                for v in scene.accel.triangle_world(ii as u32, prim) {
                    b.extend(v);
                }
            }
        }
        let (center, radius) = b.bounding_sphere();
        if radius > 0.0 {
            out.push(Target {
                center,
                radius: radius * 1.001,
            });
        }
    }
    out
}

/// Environment variable of a debug hook: set to `render`, the photon pass panics on a worker
/// thread. It lets the front ends' tests prove that a panic of the core reaches the user as an
/// ordinary error (`photonmap.PhotonmapError` in Python, a report in Blender).
pub const DEBUG_PANIC_VAR: &str = "PHOTONMAP_DEBUG_PANIC";

fn debug_panic_hook() {
    if std::env::var_os(DEBUG_PANIC_VAR).is_some_and(|v| v == "render") {
        use rayon::prelude::*;
        (0..2u32).into_par_iter().for_each(|i| {
            if i == 1 {
                panic!("{DEBUG_PANIC_VAR}=render: a deliberate panic in a render worker");
            }
        });
    }
}

/// Builds the maps the settings and the scene call for. `need_global` is false when nothing
/// reads the global map (indirect light disabled).
/// `need` says which maps the render reads: global, caustic, volume.
pub fn build(
    scene: &Scene,
    s: &RenderSettings,
    seed: u64,
    need: [bool; 3],
    cancel: Option<&AtomicBool>,
) -> (PhotonMaps, Vec<MapStats>) {
    build_with(scene, s, seed, need, cancel, true)
}

/// Whether a surface of the scene can scatter light (`Material::scatters`): where none can, a
/// photon leaving a light is never stored on a surface, and the global and caustic maps are not
/// traced (a scene of emitters alone would emit `max_emitted_factor` times the photons asked
/// for, all lost).
fn surfaces_scatter(scene: &Scene) -> bool {
    scene.accel.instances().iter().any(|inst| {
        let mesh = scene.accel.mesh(inst.mesh);
        mesh.material_ids.iter().any(|&m| {
            scene
                .materials
                .get(m as usize)
                .map_or(true, |m| m.scatters())
        })
    })
}

/// As [`build`]; `irradiance_points` false leaves out the global map's precomputed
/// irradiance (which only final gathering reads).
pub fn build_with(
    scene: &Scene,
    s: &RenderSettings,
    seed: u64,
    need: [bool; 3],
    cancel: Option<&AtomicBool>,
    irradiance_points: bool,
) -> (PhotonMaps, Vec<MapStats>) {
    debug_panic_hook();
    let [need_global, need_caustic, need_volume] = need;
    let max_r = s.radius.unwrap_or(0.1 * scene.radius);
    let mut stats = Vec::new();
    let no_lights = scene.lights.is_empty();
    let receives = surfaces_scatter(scene);
    let mut run = |kind: MapKind,
                   wanted: bool,
                   target: usize,
                   targets: &[Target],
                   why_not: Option<String>|
     -> Option<PhotonMap> {
        let reason = if no_lights {
            Some("the scene has no lights".to_string())
        } else if kind != MapKind::Volume && !receives {
            Some("no surface of the scene scatters light (its materials only emit or let light through)".to_string())
        } else if !wanted {
            why_not
        } else if target == 0 {
            Some("photon count set to 0".to_string())
        } else {
            None
        };
        if let Some(r) = reason {
            stats.push(MapStats {
                map: kind.name(),
                built: false,
                stored: 0,
                emitted: 0,
                memory_bytes: 0,
                bytes_per_photon: s.bytes_per_photon(),
                max_radius: max_r,
                seconds: 0.0,
                kdtree_seconds: 0.0,
                irradiance_points: 0,
                volume_points: 0,
                exitance_points: 0,
                skipped_because: Some(r),
            });
            return None;
        }
        let t0 = std::time::Instant::now();
        let params = TraceParams {
            kind,
            target,
            max_emitted: (target as u64)
                .saturating_mul(s.max_emitted_factor as u64)
                .max(100_000),
            max_bounces: s.max_bounces,
            seed,
            targets,
            cancel,
            f32_power: s.f32_power(),
            irradiance: (kind == MapKind::Global && irradiance_points).then_some((
                s.gather,
                max_r * max_r,
                super::terms::indirect::IRRADIANCE_POINT_PHOTONS,
            )),
        };
        let map = build_map(scene, &params)?;
        stats.push(MapStats {
            map: kind.name(),
            built: true,
            stored: map.len() as u64,
            emitted: map.emitted,
            memory_bytes: map.memory_bytes() as u64,
            bytes_per_photon: map.bytes_per_photon() as u64,
            max_radius: max_r,
            seconds: t0.elapsed().as_secs_f64(),
            kdtree_seconds: map.build_seconds,
            irradiance_points: map.irradiance.as_ref().map_or(0, |m| m.len() as u64),
            volume_points: 0,
            exitance_points: map.exitance.as_ref().map_or(0, |m| m.len() as u64),
            skipped_because: None,
        });
        Some(map)
    };
    let targets = specular_targets(scene);
    let global = run(
        MapKind::Global,
        need_global,
        s.photons,
        &[],
        Some("indirect light is not rendered".into()),
    );
    let caustic_reason = if targets.is_empty() {
        "the scene has no specular or transmissive surfaces"
    } else {
        "caustics are not rendered"
    };
    let caustic = run(
        MapKind::Caustic,
        need_caustic && !targets.is_empty(),
        s.caustic_photons,
        &targets,
        Some(caustic_reason.into()),
    );
    let volume_reason = if scene.has_media() {
        "the volume term is not rendered"
    } else {
        "the scene has no participating media"
    };
    let volume = run(
        MapKind::Volume,
        need_volume && scene.has_media(),
        s.volume_photons,
        &[],
        Some(volume_reason.into()),
    );
    let maps = PhotonMaps {
        global,
        caustic,
        volume,
        volume_points: None,
        gather: s.gather,
        global_r2: max_r * max_r,
        caustic_r2: max_r * max_r,
    };
    (maps, stats)
}

/// Support rays of a volume point's boundary correction: it is computed once and read by many
/// march steps, so with four times the rays of a step's own.
const VOLUME_POINT_SUPPORT_RAYS: u32 = 32;

/// Precomputes the volume map's points (`photon::volume_points`) where a medium of the scene
/// is isotropic, records their count in `stats`, and returns the seconds taken. Deterministic:
/// point `i`'s support rays draw from `Rng::new(seed ^ SALT, i)`.
pub fn build_volume_points(
    scene: &Scene,
    s: &RenderSettings,
    maps: &mut PhotonMaps,
    stats: &mut [MapStats],
    seed: u64,
    cancel: Option<&AtomicBool>,
) -> f64 {
    const SALT: u64 = 0x766f_6c5f_7074;
    let t0 = std::time::Instant::now();
    let isotropic = scene.media.iter().any(|m| m.phase().g == 0.0);
    // Points hold the total radiance only; a render split by light group reads the map.
    if !s.volume_points || !scene.light_groups.is_empty() {
        return 0.0;
    }
    let Some(vm) = maps.volume.as_ref().filter(|_| isotropic) else {
        return 0.0;
    };
    let reach = |i: u64, p: glam::Vec3, r: f32| {
        let mut rng = crate::sampling::Rng::new(seed ^ SALT, i);
        super::terms::volume::reachable_fraction_with(
            scene,
            p,
            r,
            &mut rng,
            VOLUME_POINT_SUPPORT_RAYS,
        )
    };
    maps.volume_points = VolumePointMap::build(vm, maps.gather, maps.global_r2, &reach, cancel);
    if let (Some(vp), Some(st)) = (
        maps.volume_points.as_ref(),
        stats.iter_mut().find(|m| m.map == MapKind::Volume.name()),
    ) {
        st.volume_points = vp.len() as u64;
        st.memory_bytes += vp.memory_bytes() as u64;
    }
    t0.elapsed().as_secs_f64()
}

/// [`MapStats`] read back from JSON (the map names are the three static ones).
pub fn parse_map_stats(text: &str) -> std::result::Result<Vec<MapStats>, String> {
    #[derive(serde::Deserialize)]
    struct In {
        map: String,
        built: bool,
        stored: u64,
        emitted: u64,
        memory_bytes: u64,
        bytes_per_photon: u64,
        max_radius: f32,
        seconds: f64,
        kdtree_seconds: f64,
        irradiance_points: u64,
        #[serde(default)]
        volume_points: u64,
        #[serde(default)]
        exitance_points: u64,
        skipped_because: Option<String>,
    }
    let v: Vec<In> = serde_json::from_str(text).map_err(|e| format!("map stats: {e}"))?;
    v.into_iter()
        .map(|m| {
            let map = match m.map.as_str() {
                "global" => "global",
                "caustic" => "caustic",
                "volume" => "volume",
                other => return Err(format!("map stats: unknown map `{other}`")),
            };
            Ok(MapStats {
                map,
                built: m.built,
                stored: m.stored,
                emitted: m.emitted,
                memory_bytes: m.memory_bytes,
                bytes_per_photon: m.bytes_per_photon,
                max_radius: m.max_radius,
                seconds: m.seconds,
                kdtree_seconds: m.kdtree_seconds,
                irradiance_points: m.irradiance_points,
                volume_points: m.volume_points,
                exitance_points: m.exitance_points,
                skipped_because: m.skipped_because,
            })
        })
        .collect()
}
