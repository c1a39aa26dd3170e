//! Cancel latency on a large scene: the default scene tessellated to ~1.5 million triangles,
//! rendered at 256x256 with settings that make each phase last seconds. The cancel flag is set
//! 0.3 s into the scene build (validation and BVH), the photon pass, the irradiance-cache fill
//! or the camera pass (timed by the progress callback's phase names), and the build or render
//! must return `Err(Cancelled)` within 1 s. The photon kd-tree build (tens of seconds at 10^8
//! photons) is checked on its own.
//! A cancelled render must not change what an uncancelled one computes: that is the
//! determinism tests' job (`render_invariants.rs`), which run with a cancel flag never set.

use photonmap::error::Error;
use photonmap::photon::{Photon, PhotonKdTree};
use photonmap::render::{ProgressFn, RenderSettings, Renderer};
use photonmap::sampling::Rng;
use photonmap::scene::desc::MeshDesc;
use photonmap::scene::{default_scene, Scene, SceneDesc};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Time from the flag being set to the render returning, at most.
/// How long into the phase the flag is set.
const INTO_PHASE: Duration = Duration::from_millis(300);

/// The renders run one at a time (they use every core and are timed).
static SERIAL: Mutex<()> = Mutex::new(());

/// Splits every triangle into 4^levels (a regular grid of barycentric points), interpolating
/// normals and UVs: the same surfaces, with many more triangles.
fn tessellate(m: &MeshDesc, levels: u32) -> MeshDesc {
    let n = 1u32 << levels;
    let mut out = MeshDesc {
        name: m.name.clone(),
        material: m.material,
        transform: m.transform,
        interior_medium: m.interior_medium,
        normals: m.normals.as_ref().map(|_| Vec::new()),
        uvs: m.uvs.as_ref().map(|_| Vec::new()),
        material_indices: m.material_indices.as_ref().map(|_| Vec::new()),
        ..Default::default()
    };
    fn lerp<const K: usize>(v: [[f32; K]; 3], u: f32, w: f32) -> [f32; K] {
        std::array::from_fn(|k| v[0][k] + u * (v[1][k] - v[0][k]) + w * (v[2][k] - v[0][k]))
    }
    for (t, tri) in m.indices.iter().enumerate() {
        let corners = |a: &[[f32; 3]]| tri.map(|i| a[i as usize]);
        let p = corners(&m.positions);
        let nrm = m.normals.as_deref().map(corners);
        let uv = m.uvs.as_deref().map(|a| tri.map(|i| a[i as usize]));
        let base = out.positions.len() as u32;
        // Grid points (i, j), i + j <= n, at barycentric (i/n, j/n).
        let mut index = vec![vec![0u32; (n + 1) as usize]; (n + 1) as usize];
        for i in 0..=n {
            for j in 0..=(n - i) {
                let (u, w) = (i as f32 / n as f32, j as f32 / n as f32);
                index[i as usize][j as usize] = out.positions.len() as u32 - base;
                out.positions.push(lerp(p, u, w));
                if let (Some(v), Some(o)) = (nrm, out.normals.as_mut()) {
                    o.push(lerp(v, u, w));
                }
                if let (Some(v), Some(o)) = (uv, out.uvs.as_mut()) {
                    o.push(lerp(v, u, w));
                }
            }
        }
        let at = |i: u32, j: u32| base + index[i as usize][j as usize];
        for i in 0..n {
            for j in 0..(n - i) {
                out.indices.push([at(i, j), at(i + 1, j), at(i, j + 1)]);
                if i + j + 1 < n {
                    out.indices
                        .push([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
                }
            }
        }
        if let (Some(src), Some(dst)) = (&m.material_indices, out.material_indices.as_mut()) {
            dst.extend(std::iter::repeat(src[t]).take((n * n) as usize));
        }
    }
    out
}

/// The default scene at 256x256, every mesh split 4^4 times (~1.5 million triangles).
fn large_desc() -> &'static SceneDesc {
    static DESC: std::sync::OnceLock<SceneDesc> = std::sync::OnceLock::new();
    DESC.get_or_init(|| {
        let mut desc: SceneDesc = default_scene();
        desc.film.width = 256;
        desc.film.height = 256;
        desc.meshes = desc.meshes.iter().map(|m| tessellate(m, 4)).collect();
        desc
    })
}

fn large_scene() -> &'static Scene {
    static SCENE: std::sync::OnceLock<Scene> = std::sync::OnceLock::new();
    SCENE.get_or_init(|| {
        let t = Instant::now();
        let scene = Scene::build(large_desc()).expect("scene builds");
        eprintln!(
            "large scene: {} triangles, built in {:.2} s",
            scene.triangle_count,
            t.elapsed().as_secs_f64()
        );
        scene
    })
}

/// Renders with `settings` on another thread, sets the cancel flag `INTO_PHASE` after the
/// progress callback first names `phase`, and checks the render returns `Err(Cancelled)`
/// with `phase` still the current one when the flag was set, and bounds the work done after
/// it: no later phase starts and the phase never reports itself finished. The latency is
/// printed (BENCHMARKS.md, "Cancel latency"), not asserted.
fn cancel_during(phase: &'static str, settings: RenderSettings) {
    let _g = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let scene = large_scene();
    let flag = Arc::new(AtomicBool::new(false));
    let current: Arc<Mutex<(String, Option<Instant>)>> =
        Arc::new(Mutex::new((String::new(), None)));
    // Reports received after the flag was set: (phase, fraction).
    let after: Arc<Mutex<Vec<(String, f32)>>> = Arc::default();
    let sink = current.clone();
    let (after_sink, flag_seen) = (after.clone(), flag.clone());
    let progress: Arc<ProgressFn> = Arc::new(move |f: f32, name: &str| {
        if flag_seen.load(Ordering::Relaxed) {
            after_sink.lock().unwrap().push((name.to_string(), f));
        }
        let mut g = sink.lock().unwrap();
        if g.0 != name {
            g.0 = name.to_string();
            if name == phase {
                g.1 = Some(Instant::now());
            }
        }
    });
    std::thread::scope(|s| {
        let worker = {
            let flag = flag.clone();
            s.spawn(move || {
                let r = Renderer::new(scene)
                    .settings(settings)
                    .progress(progress)
                    .cancel_flag(flag)
                    .render();
                (r, Instant::now())
            })
        };
        // Wait for the phase to start (or the render to end, which fails below).
        let started = loop {
            if let Some(t) = current.lock().unwrap().1 {
                break t;
            }
            if worker.is_finished() {
                panic!("the render ended before its `{phase}` phase");
            }
            std::thread::sleep(Duration::from_millis(2));
        };
        std::thread::sleep(INTO_PHASE.saturating_sub(started.elapsed()));
        let (in_phase, set_at) = {
            let g = current.lock().unwrap();
            flag.store(true, Ordering::Relaxed);
            (g.0.clone(), Instant::now())
        };
        let (result, returned_at) = worker.join().expect("render thread");
        let latency = returned_at.saturating_duration_since(set_at);
        eprintln!(
            "{phase}: cancelled {:.0} ms into the phase, returned after {:.0} ms",
            set_at.duration_since(started).as_secs_f64() * 1e3,
            latency.as_secs_f64() * 1e3
        );
        assert_eq!(
            in_phase, phase,
            "the `{phase}` phase was over before the flag was set: make it longer"
        );
        assert!(
            matches!(result, Err(Error::Cancelled)),
            "expected Err(Cancelled), got {:?}",
            result.map(|_| "an image")
        );
        let after = after.lock().unwrap();
        assert!(
            after.iter().all(|(n, f)| n == phase && *f < 1.0),
            "work went on after the flag was set during `{phase}`: {after:?}"
        );
    });
}

fn base() -> RenderSettings {
    let mut s = RenderSettings {
        spp: 4,
        seed: 3,
        threads: 0,
        ..Default::default()
    };
    s.photons = 100_000;
    s.caustic_photons = 20_000;
    s.final_gather_rays = 64;
    s.memory_limit = None;
    s
}

#[test]
fn cancel_during_the_photon_pass() {
    let mut s = base();
    // Five million photons: seconds of tracing, then the kd-tree.
    s.photons = 5_000_000;
    cancel_during("photons", s);
}

#[test]
fn cancel_during_the_irradiance_cache_fill() {
    let mut s = base();
    // Thousands of records of 4096 gather rays each.
    s.irradiance_cache = true;
    s.final_gather_rays = 4096;
    s.cache_tolerance = 0.05;
    cancel_during("irradiance cache", s);
}

#[test]
fn cancel_during_the_camera_pass() {
    let mut s = base();
    // Final gathering at every sample, no cache: a long camera pass, and seconds per image
    // row (the flag must be read more often than once a row).
    s.irradiance_cache = false;
    s.final_gather_rays = 1024;
    s.spp = 16;
    cancel_during("render", s);
}

#[test]
fn cancel_during_the_scene_build() {
    let _g = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let desc = large_desc();
    let flag = AtomicBool::new(false);
    std::thread::scope(|s| {
        let t = Instant::now();
        let worker = s.spawn(|| {
            let r = Scene::build_cancellable(desc, Some(&flag));
            (r.map(|_| ()), Instant::now())
        });
        std::thread::sleep(INTO_PHASE);
        let still_building = !worker.is_finished();
        let set_at = Instant::now();
        flag.store(true, Ordering::Relaxed);
        let (result, returned_at) = worker.join().expect("build thread");
        let latency = returned_at.saturating_duration_since(set_at);
        eprintln!(
            "scene build: cancelled {:.0} ms in, returned after {:.0} ms",
            set_at.duration_since(t).as_secs_f64() * 1e3,
            latency.as_secs_f64() * 1e3
        );
        assert!(still_building, "the build was over before the flag was set");
        assert!(
            matches!(result, Err(Error::Cancelled)),
            "expected Err(Cancelled), got {result:?}"
        );
    });
    // Uncancelled, the same description builds.
    assert!(Scene::build_cancellable(desc, Some(&AtomicBool::new(false))).is_ok());
}

/// `n` photons at random positions in the unit cube.
fn random_photons(n: usize) -> Vec<Photon> {
    let mut rng = Rng::new(11, 0);
    (0..n)
        .map(|_| Photon::new(rng.vec3(), glam::Vec3::ONE, -rng.vec3() - 0.1).expect("photon"))
        .collect()
}

#[test]
fn kdtree_build_is_the_same_when_not_cancelled() {
    // Above the parallel threshold, so that the flag is read at several levels.
    let photons = random_photons(300_000);
    let plain = PhotonKdTree::build(photons.clone());
    let flag = AtomicBool::new(false);
    let cancellable = PhotonKdTree::build_cancellable(photons.clone(), &flag).expect("built");
    assert_eq!(plain.photons(), cancellable.photons());
    flag.store(true, Ordering::Relaxed);
    assert!(PhotonKdTree::build_cancellable(photons, &flag).is_none());
}

#[test]
fn cancel_during_the_kdtree_build() {
    let _g = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let photons = random_photons(10_000_000);
    let flag = AtomicBool::new(false);
    std::thread::scope(|s| {
        let t = Instant::now();
        let worker = s.spawn(|| {
            let r = PhotonKdTree::build_cancellable(photons, &flag);
            (r.is_none(), Instant::now())
        });
        std::thread::sleep(INTO_PHASE);
        let still_building = !worker.is_finished();
        let set_at = Instant::now();
        flag.store(true, Ordering::Relaxed);
        let (gave_up, returned_at) = worker.join().expect("build thread");
        let latency = returned_at.saturating_duration_since(set_at);
        eprintln!(
            "kd-tree build: cancelled {:.0} ms in, returned after {:.0} ms",
            set_at.duration_since(t).as_secs_f64() * 1e3,
            latency.as_secs_f64() * 1e3
        );
        assert!(still_building, "the build was over before the flag was set");
        assert!(gave_up, "the build went on to the end");
    });
}
