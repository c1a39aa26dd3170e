//! Thread scaling, 1 against 2 threads, of the photon pass and of a whole render, phase by
//! phase, printed as tables for BENCHMARKS.md.
//!
//! - Photon pass: the global map of the default scene, 1,000,000 photons stored, split into
//!   tracing and the map's build (records and kd-tree).
//! - Whole render: the default scene at 256x256 with the `medium` preset, split into the
//!   photon pass, the irradiance cache and the camera pass.
//!
//! The thread counts alternate (1, 2, 1, 2, ...) and the best time of each is kept, so a
//! passing load hits both alike. The process's CPU time per pass is read from `/proc` (Linux),
//! to show how much more work two threads do than one. Run on idle cores:
//! `cargo bench --bench scaling` (`-- --rounds N`, default 3).

use photonmap::photon::map::MapKind;
use photonmap::photon::trace::{build_map, TraceParams};
use photonmap::render::{Quality, RenderSettings, Renderer};
use photonmap::scene::Scene;
use std::time::Instant;

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

/// The process's user + system CPU seconds, from `/proc/self/stat` (0 elsewhere).
fn cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return 0.0;
    };
    // Fields after the command name (which is in parentheses and may hold spaces).
    let rest = stat.rsplit_once(')').map_or("", |r| r.1);
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| f.get(i).and_then(|s| s.parse::<f64>().ok()).unwrap_or(0.0);
    // utime and stime are fields 14 and 15 of the line, 12 and 13 after the name.
    (ticks(11) + ticks(12)) / 100.0
}

/// Best (smallest) value of each phase over the runs of one thread count.
#[derive(Clone, Default)]
struct Best(Vec<f64>);

impl Best {
    fn keep(&mut self, v: &[f64]) {
        if self.0.is_empty() {
            self.0 = v.to_vec();
        } else {
            for (b, x) in self.0.iter_mut().zip(v) {
                *b = b.min(*x);
            }
        }
    }
}

fn photon_pass(scene: &Scene, threads: usize) -> Vec<f64> {
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
    let (t, c) = (Instant::now(), cpu_seconds());
    let map = pool(threads)
        .install(|| build_map(scene, &params))
        .expect("map");
    let total = t.elapsed().as_secs_f64();
    let cpu = cpu_seconds() - c;
    vec![total - map.build_seconds, map.build_seconds, total, cpu]
}

fn whole_render(scene: &Scene, threads: usize) -> Vec<f64> {
    let mut settings = RenderSettings::preset(Quality::Medium);
    settings.seed = 3;
    settings.threads = threads;
    let (t, c) = (Instant::now(), cpu_seconds());
    let out = Renderer::new(scene)
        .settings(settings)
        .render()
        .expect("render");
    let total = t.elapsed().as_secs_f64();
    let cpu = cpu_seconds() - c;
    let s = &out.stats.seconds;
    vec![s["photons"], s["irradiance_cache"], s["render"], total, cpu]
}

/// The machine's own ceiling: the same loop of work on every thread, pure arithmetic
/// (`memory` false) or dependent random reads from a 512 MiB array (`memory` true).
fn machine(threads: usize, memory: bool, table: &[u64]) -> Vec<f64> {
    let t = Instant::now();
    let per = 2usize;
    pool(threads).install(|| {
        use rayon::prelude::*;
        let sum: u64 = (0..per * 2)
            .into_par_iter()
            .map(|k| {
                let mut x = 0x9E37_79B9_7F4A_7C15u64 ^ k as u64;
                let mut acc = 0u64;
                let steps = if memory { 4_000_000 } else { 150_000_000 };
                for _ in 0..steps {
                    x ^= x << 13;
                    x ^= x >> 7;
                    x ^= x << 17;
                    if memory {
                        let v = table[(x ^ acc) as usize % table.len()];
                        acc = acc.wrapping_add(v);
                    } else {
                        acc = acc.wrapping_add(x);
                    }
                }
                acc
            })
            .sum();
        std::hint::black_box(sum);
    });
    vec![t.elapsed().as_secs_f64()]
}

fn table(title: &str, phases: &[&str], one: &Best, two: &Best) {
    println!("\n## {title}\n");
    println!("| phase | 1 thread, s | 2 threads, s | scaling |");
    println!("|---|---|---|---|");
    for (i, name) in phases.iter().enumerate() {
        let (a, b) = (one.0[i], two.0[i]);
        if name.starts_with("CPU") {
            println!("| {name} | {a:.3} | {b:.3} | {:.2}x the work |", b / a);
        } else {
            println!("| {name} | {a:.3} | {b:.3} | {:.2}x |", a / b);
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let rounds = args
        .iter()
        .position(|a| a == "--rounds")
        .and_then(|i| args.get(i + 1))
        .and_then(|s| s.parse().ok())
        .unwrap_or(3usize);
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut desc =
        photonmap::io::scene_json::load(root.join("tests/data/scenes/cornell_spheres.json"))
            .expect("scene");
    let scene = Scene::build(&desc).expect("scene builds");
    desc.film.width = 256;
    desc.film.height = 256;
    let big = Scene::build(&desc).expect("scene builds");
    println!(
        "cores available: {}",
        std::thread::available_parallelism().map_or(0, |n| n.get())
    );

    // Four equal pieces of work: two threads should take half the time of one.
    let big_table: Vec<u64> = (0..64u64 << 20).collect();
    for (name, memory) in [
        ("arithmetic loop", false),
        ("random reads from 512 MiB", true),
    ] {
        let (mut m1, mut m2) = (Best::default(), Best::default());
        for _ in 0..rounds {
            m1.keep(&machine(1, memory, &big_table));
            m2.keep(&machine(2, memory, &big_table));
        }
        table(&format!("The machine: {name}"), &[name], &m1, &m2);
    }
    drop(big_table);

    let (mut p1, mut p2) = (Best::default(), Best::default());
    for _ in 0..rounds {
        p1.keep(&photon_pass(&scene, 1));
        p2.keep(&photon_pass(&scene, 2));
    }
    table(
        "Photon pass (default scene, global map, 1,000,000 photons stored; best of each)",
        &[
            "tracing",
            "records and kd-tree",
            "whole pass",
            "CPU time of the pass",
        ],
        &p1,
        &p2,
    );

    let (mut r1, mut r2) = (Best::default(), Best::default());
    for _ in 0..rounds {
        r1.keep(&whole_render(&big, 1));
        r2.keep(&whole_render(&big, 2));
    }
    table(
        "Whole render (default scene at 256x256, `medium`; best of each)",
        &[
            "photon pass",
            "irradiance cache",
            "camera pass",
            "whole render",
            "CPU time of the render",
        ],
        &r1,
        &r2,
    );
}
