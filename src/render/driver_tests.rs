//! Tests of the camera-pass driver, with a toy integrator.

use super::*;
use crate::render::accumulate::Sums;
use crate::render::adaptive::Adaptive;
use crate::render::aov::Term;
use crate::render::error_aov::{replicate_of, Replicates, REPLICATES};
use crate::render::stratified::{replicate_grids, stratified_point};
use crate::scene::default_scene;
use std::sync::Mutex;

fn scene() -> Scene {
    let mut desc = default_scene();
    desc.film.width = 12;
    desc.film.height = 9;
    Scene::build(&desc).unwrap()
}

/// A toy integrator: the direct term is the ray's direction plus a random number, the
/// caustic term is NaN at every `nan_every`-th sample, and each sample adds `further`
/// (counted in `extra`).
struct Toy {
    nan_every: u32,
    further: f32,
    passes_begun: Mutex<Vec<u32>>,
}

impl Toy {
    fn new() -> Self {
        Toy {
            nan_every: 0,
            further: 0.0,
            passes_begun: Mutex::new(Vec::new()),
        }
    }
}

impl Integrator for Toy {
    type Extra = u32;
    type Acc = Sums;
    type Scratch = ();
    type Pass = u32;
    fn scratch(&self) {}
    fn begin_pass(&mut self, k: u32) -> Result<u32> {
        self.passes_begun.lock().unwrap().push(k);
        Ok(k)
    }
    fn sample(
        &self,
        pass: &u32,
        ray: Ray,
        rng: &mut Rng,
        extra: &mut u32,
        k: u32,
        _: &mut (),
        _: &mut SampleAovs,
    ) -> (TermRadiance, Spectrum) {
        assert_eq!(*pass, k.min(*pass), "a sample reads its own pass");
        *extra += 1;
        let mut l = TermRadiance::default();
        let d = ray.d.abs();
        l.add(Term::Direct, Spectrum::new(d.x, d.y, d.z + rng.f32()));
        if self.nan_every > 0 && k % self.nan_every == 0 {
            l.add(Term::Caustic, Spectrum::splat(f32::NAN));
        }
        (l, Spectrum::splat(self.further))
    }
}

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

fn bits(film: &Film) -> Vec<u32> {
    film.terms
        .iter()
        .chain(std::iter::once(&film.error))
        .flat_map(|i| i.data.iter().flatten().map(|v| v.to_bits()))
        .collect()
}

#[test]
fn films_are_bit_identical_for_any_thread_count() {
    let scene = scene();
    let filter = Filter::gaussian(0.5);
    let driver = CameraPass::new(&scene, filter.clone(), 3, "render");
    let one = in_pool(1, || driver.stratified(&mut Toy::new(), 7, None).unwrap().0);
    let two = in_pool(2, || driver.stratified(&mut Toy::new(), 7, None).unwrap().0);
    assert_eq!(bits(&one), bits(&two));
    let p1 = in_pool(1, || {
        driver.progressive(&mut Toy::new(), Schedule::Passes(5), 0)
    });
    let p2 = in_pool(2, || {
        driver.progressive(&mut Toy::new(), Schedule::Passes(5), 0)
    });
    assert_eq!(bits(&p1.unwrap().film), bits(&p2.unwrap().film));
    // Another seed gives another image.
    let other = CameraPass::new(&scene, filter.clone(), 4, "render");
    assert_ne!(
        bits(&one),
        bits(&other.stratified(&mut Toy::new(), 7, None).unwrap().0)
    );
}

#[test]
fn the_image_after_k_passes_does_not_depend_on_the_passes_that_follow() {
    let scene = scene();
    let filter = Filter::gaussian(0.5);
    let previews = std::sync::Arc::new(Mutex::new(Vec::<(u32, Vec<u32>)>::new()));
    let sink = previews.clone();
    let keep = move |f: &Film, k: u32| sink.lock().unwrap().push((k, bits(f)));
    let mut driver = CameraPass::new(&scene, filter.clone(), 9, "render");
    driver.preview = Some(&keep);
    let mut toy = Toy::new();
    let out = driver
        .progressive(&mut toy, Schedule::Passes(8), 0)
        .unwrap();
    assert_eq!(out.passes, 8);
    assert_eq!(
        *toy.passes_begun.lock().unwrap(),
        (0..8).collect::<Vec<_>>()
    );
    assert!(out.pixels.iter().all(|px| px.extra == 8));
    let previews = previews.lock().unwrap().clone();
    let ks: Vec<u32> = previews.iter().map(|(k, _)| *k).collect();
    for k in [1, 2, 4, 8] {
        assert!(ks.contains(&k), "preview after pass {k}: {ks:?}");
    }
    let quiet = CameraPass::new(&scene, filter.clone(), 9, "render");
    for (k, preview) in previews.iter().filter(|(k, _)| [1, 4].contains(k)) {
        let alone = quiet
            .progressive(&mut Toy::new(), Schedule::Passes(*k), 0)
            .unwrap();
        assert_eq!(bits(&alone.film), *preview, "after {k} passes");
    }
}

#[test]
fn the_firewall_drops_non_finite_terms_and_counts_them() {
    let scene = scene();
    let filter = Filter::gaussian(0.5);
    let driver = CameraPass::new(&scene, filter.clone(), 1, "render");
    let mut toy = Toy::new();
    toy.nan_every = 2;
    let film = driver.stratified(&mut toy, 4, None).unwrap().0;
    // Samples 0 and 2 of each pixel carry a NaN caustic term.
    assert_eq!(driver.non_finite_samples(), (12 * 9 * 2) as u64);
    assert!(film
        .term(Term::Caustic)
        .data
        .iter()
        .flatten()
        .all(|v| *v == 0.0));
    assert!(film
        .term(Term::Direct)
        .data
        .iter()
        .flatten()
        .all(|v| v.is_finite() && *v > 0.0));
    assert!(film.error.data.iter().flatten().all(|v| v.is_finite()));
}

#[test]
fn the_further_share_enters_the_error_not_the_eye_terms() {
    let scene = scene();
    let filter = Filter::gaussian(0.5);
    let driver = CameraPass::new(&scene, filter.clone(), 1, "render");
    let base = driver
        .progressive(&mut Toy::new(), Schedule::Passes(8), 0)
        .unwrap();
    let mut toy = Toy::new();
    toy.further = 1.0;
    let shifted = driver
        .progressive(&mut toy, Schedule::Passes(8), 0)
        .unwrap();
    // The default resolve reports the eye terms only, and a constant share leaves the
    // spread of the replicates, and so the error, alone (to rounding).
    for t in Term::ALL {
        assert!(base.film.term(t).data == shifted.film.term(t).data, "{t:?}");
    }
    let (e0, e1) = (&base.film.error.data, &shifted.film.error.data);
    let worst = e0
        .iter()
        .flatten()
        .zip(e1.iter().flatten())
        .map(|(a, b)| (a - b).abs() / a.max(1e-6))
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-3, "error AOV moved by {worst}");
    let mean = |p: &Passes<u32>| p.pixels[0].sums.batches.mean();
    let d = mean(&shifted) - mean(&base);
    assert!(
        (d - Spectrum::splat(1.0)).abs().max_element() < 1e-5,
        "{d:?}"
    );
}

#[test]
fn stratified_samples_fall_one_per_cell_of_their_replicates_grid() {
    assert_eq!(replicate_grids(64), [(4, 4); 4]);
    assert_eq!(replicate_grids(6), [(1, 2), (1, 2), (1, 1), (1, 1)]);
    assert_eq!(replicate_grids(1), [(1, 1); 4]);
    assert_eq!(replicate_grids(128), [(4, 8); 4]);
    assert_eq!(replicate_grids(384), [(8, 12); 4]);
    assert_eq!(replicate_grids(28), [(1, 7); 4]);
    for spp in [1u32, 6, 16, 28, 64, 100, 128, 130, 384] {
        let grids = replicate_grids(spp);
        let mut rng = Rng::new(5, 0);
        for r in 0..REPLICATES {
            let (nx, ny) = grids[r];
            let mut cells = vec![0u32; (nx * ny) as usize];
            for i in (0..spp).filter(|i| replicate_of(*i).0 == r) {
                let u = stratified_point(&grids, i, rng.vec2());
                assert!(u.min_element() >= 0.0 && u.max_element() < 1.0, "{u}");
                let (cx, cy) = ((u.x * nx as f32) as u32, (u.y * ny as f32) as u32);
                cells[(cy * nx + cx) as usize] += 1;
            }
            // Every cell exactly once (a replicate with no sample has no grid to fill): an
            // empty cell would bias the pixel's samples.
            assert!(
                spp <= r as u32 || cells.iter().all(|c| *c == 1),
                "spp {spp} replicate {r}: {cells:?}"
            );
        }
    }
}

#[test]
fn stratified_samples_are_centred_on_the_pixel_for_every_count() {
    // With the jitter at its mean (0.5), each replicate's samples average to the pixel's
    // centre: the film position is unbiased whatever the sample count.
    for spp in 1u32..=520 {
        let grids = replicate_grids(spp);
        for r in 0..REPLICATES {
            let mine: Vec<Vec2> = (0..spp)
                .filter(|i| replicate_of(*i).0 == r)
                .map(|i| stratified_point(&grids, i, Vec2::splat(0.5)))
                .collect();
            if mine.is_empty() {
                continue;
            }
            let mean = mine.iter().copied().sum::<Vec2>() / mine.len() as f32;
            assert!(
                (mean - Vec2::splat(0.5)).abs().max_element() < 1e-4,
                "spp {spp} replicate {r}: mean film offset {mean}"
            );
        }
    }
}

#[test]
fn cancelling_ends_either_loop_with_cancelled() {
    let scene = scene();
    let filter = Filter::gaussian(0.5);
    let flag = AtomicBool::new(true);
    let mut driver = CameraPass::new(&scene, filter.clone(), 1, "render");
    driver.cancel = Some(&flag);
    assert!(matches!(
        driver.stratified(&mut Toy::new(), 4, None).map(|r| r.0),
        Err(Error::Cancelled)
    ));
    assert!(matches!(
        driver.progressive(&mut Toy::new(), Schedule::Passes(4), 0),
        Err(Error::Cancelled)
    ));
}

#[test]
fn a_deadline_runs_at_least_one_pass_and_stops() {
    let scene = scene();
    let filter = Filter::gaussian(0.5);
    let driver = CameraPass::new(&scene, filter.clone(), 1, "render");
    let start = Instant::now();
    let past = Schedule::Deadline {
        start,
        deadline: 0.0,
    };
    assert_eq!(
        driver.progressive(&mut Toy::new(), past, 0).unwrap().passes,
        1
    );
    let soon = Schedule::Deadline {
        start,
        deadline: 0.2,
    };
    let out = driver.progressive(&mut Toy::new(), soon, 0).unwrap();
    assert!(out.passes > 1, "{}", out.passes);
    assert!(start.elapsed().as_secs_f64() < 5.0);
}

/// A rare bright path: each sample's direct term is `value` with probability `p`, else 0
/// (a small light seen through glass); `extra` counts the pixel's samples.
struct Rare {
    p: f32,
    value: f32,
}

impl Integrator for Rare {
    type Extra = u32;
    type Acc = Sums;
    type Scratch = ();
    type Pass = ();
    fn scratch(&self) {}
    fn begin_pass(&mut self, _k: u32) -> Result<()> {
        Ok(())
    }
    fn sample(
        &self,
        _: &(),
        _: Ray,
        rng: &mut Rng,
        extra: &mut u32,
        _: u32,
        _: &mut (),
        _: &mut SampleAovs,
    ) -> (TermRadiance, Spectrum) {
        *extra += 1;
        let mut l = TermRadiance::default();
        if rng.f32() < self.p {
            l.add(Term::Direct, Spectrum::splat(self.value));
        }
        (l, Spectrum::ZERO)
    }
}

fn wide_scene(w: usize, h: usize) -> Scene {
    let mut desc = default_scene();
    desc.film.width = w as u32;
    desc.film.height = h as u32;
    Scene::build(&desc).unwrap()
}

/// Adaptive sampling adds whole rounds where the neighbours are noisy, takes the same film for
/// any thread count, and its rounds show in the stats.
#[test]
fn adaptive_rounds_are_deterministic_and_counted() {
    let scene = wide_scene(24, 16);
    let filter = Filter::Box;
    let driver = CameraPass::new(&scene, filter.clone(), 5, "render");
    let a = Some(Adaptive {
        threshold: 0.5,
        max_factor: 4,
    });
    let run = |threads| {
        in_pool(threads, || {
            driver
                .stratified(
                    &mut Rare {
                        p: 0.05,
                        value: 20.0,
                    },
                    8,
                    a,
                )
                .unwrap()
        })
    };
    let (one, s1) = run(1);
    let (two, s2) = run(2);
    assert_eq!(bits(&one), bits(&two));
    assert_eq!(s1, s2);
    let s = s1.unwrap();
    assert!(s.pixels_refined > 0 && s.pixels_refined < 24 * 16, "{s:?}");
    assert_eq!(
        s.mean_spp * (24 * 16) as f64,
        (24 * 16 * 8) as f64 + s.extra_samples as f64
    );
    assert_eq!(s.extra_samples % 8, 0, "whole rounds of spp");
}

/// A pixel's rounds come from its neighbours' noise, never its own, so each pixel's mean stays
/// unbiased: over 64 x 64 pixels of a rare bright path (p = 0.02, value 50, mean 1), the image
/// mean is within 4.5 standard errors of 1. The same test rejects the rule that refines a
/// pixel by its own noise (simulated below), which keeps pixels that missed the path dark and
/// dilutes those that caught it: its mean is near a quarter of the truth.
#[test]
fn adaptive_sampling_is_unbiased_on_a_rare_bright_path() {
    let (w, h, spp) = (64usize, 64usize, 8u32);
    let (p, value) = (0.02f32, 50.0f32);
    let a = Adaptive {
        threshold: 0.3,
        max_factor: 8,
    };
    let truth = (p * value) as f64;
    // Standard error of an image mean of pixels of at least spp samples each.
    let sigma =
        ((p * (1.0 - p)) as f64 * (value as f64).powi(2) / (spp as f64 * (w * h) as f64)).sqrt();
    let z = |m: f64| (m - truth) / sigma;

    let scene = wide_scene(w, h);
    let filter = Filter::Box;
    let driver = CameraPass::new(&scene, filter.clone(), 11, "render");
    let (film, stats) = driver
        .stratified(&mut Rare { p, value }, spp, Some(a))
        .unwrap();
    let stats = stats.unwrap();
    assert!(stats.pixels_refined > 100, "{stats:?}");
    let mean = film
        .term(Term::Direct)
        .data
        .iter()
        .map(|v| v[1] as f64)
        .sum::<f64>()
        / (w * h) as f64;
    assert!(
        z(mean).abs() < 4.5,
        "adaptive mean {mean} (z {:.1})",
        z(mean)
    );

    // The rule that reads a pixel's own noise, on the same kind of samples (the image's
    // brightness taken as the truth).
    let mut rng = Rng::new(11, 0);
    let mut own = 0.0f64;
    let b = truth as f32;
    for _ in 0..w * h {
        let mut reps = Replicates::default();
        let mut sum = 0.0f64;
        let mut draw = |k: u32, reps: &mut Replicates, sum: &mut f64| {
            let v = if rng.f32() < p { value } else { 0.0 };
            reps.add(k, Spectrum::splat(v));
            *sum += v as f64;
        };
        for k in 0..spp {
            draw(k, &mut reps, &mut sum);
        }
        let (m, se) = (reps.mean().y, reps.standard_error().y);
        let n = se / (m.max(1e-3 * b) * b).sqrt();
        let rounds = ((n / a.threshold).powi(2).ceil() as u32).clamp(1, a.max_factor);
        for k in spp..rounds * spp {
            draw(k, &mut reps, &mut sum);
        }
        own += sum / (rounds * spp) as f64;
    }
    own /= (w * h) as f64;
    eprintln!(
        "image mean: adaptive {mean:.4} (z {:.2}), own-noise rule {own:.4} (z {:.1})",
        z(mean),
        z(own)
    );
    assert!(
        z(own) < -4.5,
        "the own-noise rule's mean {own} (z {:.1})",
        z(own)
    );
}
