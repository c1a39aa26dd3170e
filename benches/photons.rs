//! Photon-pass and final-gathering benchmarks on the default scene (Cornell box with a glass
//! and a mirror sphere), printed as a table for BENCHMARKS.md:
//! - photon paths per second per thread, and the 1 -> 2 thread scaling;
//! - the gain of aiming caustic photons at specular objects;
//! - the irradiance cache's speed-up and error against gathering at every pixel sample.
//!
//! Run: `cargo bench --bench photons` (`-- --one-core`: the photon pass on one thread only).

use photonmap::command::exr::read_rgb_layers;
use photonmap::photon::map::MapKind;
use photonmap::photon::trace::{build_map, TraceParams};
use photonmap::render::aov::Term;
use photonmap::render::film::Image;
use photonmap::render::photons::specular_targets;
use photonmap::render::settings::FilterName;
use photonmap::render::{RenderSettings, Renderer};
use photonmap::scene::Scene;
use std::time::Instant;

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn block_rel_mse(a: &Image, b: &Image, block: usize) -> f64 {
    let (bw, bh) = (a.width / block, a.height / block);
    let mut sum = 0.0;
    for by in 0..bh {
        for bx in 0..bw {
            let (mut p, mut q) = ([0.0f64; 3], [0.0f64; 3]);
            for y in by * block..(by + 1) * block {
                for x in bx * block..(bx + 1) * block {
                    for c in 0..3 {
                        p[c] += a.get(x, y)[c] as f64;
                        q[c] += b.get(x, y)[c] as f64;
                    }
                }
            }
            for c in 0..3 {
                let n = (block * block) as f64;
                sum += ((p[c] - q[c]) / n).powi(2) / ((q[c] / n).powi(2) + 1e-2);
            }
        }
    }
    sum / (bw * bh * 3) as f64
}

fn main() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let desc = photonmap::io::scene_json::load(root.join("tests/data/scenes/cornell_spheres.json"))
        .expect("scene");
    let scene = Scene::build(&desc).expect("scene builds");

    // `-- --one-core`: the 1-thread row alone (for a run pinned to one core beside LuxCore).
    let one_core = std::env::args().any(|a| a == "--one-core");
    println!("## Photon pass (default scene, global map, 1,000,000 photons stored)\n");
    println!("| threads | paths/s | paths/s per thread | photons stored/s | scaling |");
    println!("|---|---|---|---|---|");
    let mut base = 0.0;
    let threads_run: &[usize] = if one_core { &[1] } else { &[1, 2] };
    for &threads in threads_run {
        let params = TraceParams {
            kind: MapKind::Global,
            target: 1_000_000,
            max_emitted: 100_000_000,
            max_bounces: 64,
            seed: 1,
            targets: &[],
            cancel: None,
            f32_power: false,
            irradiance: None,
        };
        let t = Instant::now();
        let map = pool(threads)
            .install(|| build_map(&scene, &params))
            .expect("map");
        let secs = t.elapsed().as_secs_f64();
        let rate = map.emitted as f64 / secs;
        if threads == 1 {
            base = rate;
        }
        println!(
            "| {threads} | {:.0} | {:.0} | {:.0} | {:.2}x |",
            rate,
            rate / threads as f64,
            map.len() as f64 / secs,
            rate / base
        );
    }

    if one_core {
        return;
    }
    println!("\n## Caustic photons aimed at specular objects (200,000 stored)\n");
    println!("| emission | paths emitted | stored per 1000 paths | seconds |");
    println!("|---|---|---|---|");
    let targets = specular_targets(&scene);
    let mut rates = vec![];
    for (name, t) in [
        ("whole light", &[][..]),
        ("towards specular bounding spheres", &targets[..]),
    ] {
        let params = TraceParams {
            kind: MapKind::Caustic,
            target: 200_000,
            max_emitted: 200_000_000,
            max_bounces: 64,
            seed: 2,
            targets: t,
            cancel: None,
            f32_power: false,
            irradiance: None,
        };
        let t0 = Instant::now();
        let map = build_map(&scene, &params).expect("map");
        let per = 1000.0 * map.len() as f64 / map.emitted as f64;
        rates.push(per);
        println!(
            "| {name} | {} | {per:.1} | {:.2} |",
            map.emitted,
            t0.elapsed().as_secs_f64()
        );
    }
    println!(
        "\nGain: {:.1}x more caustic photons per emitted path.",
        rates[1] / rates[0]
    );

    println!(
        "\n## Irradiance cache against gathering at every sample (128x128, 16 spp, 10^6 photons)\n"
    );
    let reference = read_rgb_layers(root.join("tests/data/references/cornell_spheres_full.exr"))
        .expect("reference")
        .0[""]
        .clone();
    println!("| final gathering | seconds (cache + camera pass) | records | 8x8-block relMSE vs Mitsuba |");
    println!("|---|---|---|---|");
    let mut times = vec![];
    for (name, cache) in [
        ("irradiance cache (a = 0.15)", true),
        ("every sample", false),
    ] {
        let photons = RenderSettings {
            photons: 1_000_000,
            caustic_photons: 1_000_000,
            final_gather_rays: 512,
            irradiance_cache: cache,
            ..Default::default()
        };
        let settings = RenderSettings {
            spp: 16,
            seed: 5,
            filter: FilterName::Box,
            ..photons
        };
        let out = Renderer::new(&scene)
            .settings(settings)
            .render()
            .expect("render");
        let secs = out.stats.seconds["irradiance_cache"] + out.stats.seconds["render"];
        times.push(secs);
        let err = block_rel_mse(&out.film.combined(), &reference, 8);
        let _ = out.film.term(Term::Indirect);
        println!(
            "| {name} | {secs:.2} | {} | {err:.3e} |",
            out.stats.irradiance_cache_records
        );
    }
    println!("\nSpeed-up of the cache: {:.1}x.", times[1] / times[0]);
}
