//! Tests of the camera-pass driver, with a toy integrator.

use super::*;
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
    let driver = CameraPass::new(&scene, &filter, 3, "render");
    let one = in_pool(1, || driver.stratified(&mut Toy::new(), 7).unwrap());
    let two = in_pool(2, || driver.stratified(&mut Toy::new(), 7).unwrap());
    assert_eq!(bits(&one), bits(&two));
    let p1 = in_pool(1, || {
        driver.progressive(&mut Toy::new(), Schedule::Passes(5))
    });
    let p2 = in_pool(2, || {
        driver.progressive(&mut Toy::new(), Schedule::Passes(5))
    });
    assert_eq!(bits(&p1.unwrap().film), bits(&p2.unwrap().film));
    // Another seed gives another image.
    let other = CameraPass::new(&scene, &filter, 4, "render");
    assert_ne!(
        bits(&one),
        bits(&other.stratified(&mut Toy::new(), 7).unwrap())
    );
}

#[test]
fn the_image_after_k_passes_does_not_depend_on_the_passes_that_follow() {
    let scene = scene();
    let filter = Filter::gaussian(0.5);
    let previews = std::sync::Arc::new(Mutex::new(Vec::<(u32, Vec<u32>)>::new()));
    let sink = previews.clone();
    let keep = move |f: &Film, k: u32| sink.lock().unwrap().push((k, bits(f)));
    let mut driver = CameraPass::new(&scene, &filter, 9, "render");
    driver.preview = Some(&keep);
    let mut toy = Toy::new();
    let out = driver.progressive(&mut toy, Schedule::Passes(8)).unwrap();
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
    let quiet = CameraPass::new(&scene, &filter, 9, "render");
    for (k, preview) in previews.iter().filter(|(k, _)| [1, 4].contains(k)) {
        let alone = quiet
            .progressive(&mut Toy::new(), Schedule::Passes(*k))
            .unwrap();
        assert_eq!(bits(&alone.film), *preview, "after {k} passes");
    }
}

#[test]
fn the_firewall_drops_non_finite_terms_and_counts_them() {
    let scene = scene();
    let filter = Filter::gaussian(0.5);
    let driver = CameraPass::new(&scene, &filter, 1, "render");
    let mut toy = Toy::new();
    toy.nan_every = 2;
    let film = driver.stratified(&mut toy, 4).unwrap();
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
    let driver = CameraPass::new(&scene, &filter, 1, "render");
    let base = driver
        .progressive(&mut Toy::new(), Schedule::Passes(8))
        .unwrap();
    let mut toy = Toy::new();
    toy.further = 1.0;
    let shifted = driver.progressive(&mut toy, Schedule::Passes(8)).unwrap();
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
    let mean = |p: &Passes<u32>| p.pixels[0].batches.mean();
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
    let mut driver = CameraPass::new(&scene, &filter, 1, "render");
    driver.cancel = Some(&flag);
    assert!(matches!(
        driver.stratified(&mut Toy::new(), 4),
        Err(Error::Cancelled)
    ));
    assert!(matches!(
        driver.progressive(&mut Toy::new(), Schedule::Passes(4)),
        Err(Error::Cancelled)
    ));
}

#[test]
fn a_deadline_runs_at_least_one_pass_and_stops() {
    let scene = scene();
    let filter = Filter::gaussian(0.5);
    let driver = CameraPass::new(&scene, &filter, 1, "render");
    let start = Instant::now();
    let past = Schedule::Deadline {
        start,
        deadline: 0.0,
    };
    assert_eq!(driver.progressive(&mut Toy::new(), past).unwrap().passes, 1);
    let soon = Schedule::Deadline {
        start,
        deadline: 0.2,
    };
    let out = driver.progressive(&mut Toy::new(), soon).unwrap();
    assert!(out.passes > 1, "{}", out.passes);
    assert!(start.elapsed().as_secs_f64() < 5.0);
}
