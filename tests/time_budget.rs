//! `--time-budget`: the render fills the budget, a tiny budget still gives an image, and the
//! recorded plan reproduces the image bit for bit.
mod common;

use common::load_scene;
use photonmap::render::aov::Term;
use photonmap::render::{RenderOutput, RenderSettings, Renderer};
use photonmap::scene::{Scene, SceneDesc};
use std::sync::Mutex;
use std::time::Instant;

/// The tests time renders: run them one at a time.
static SERIAL: Mutex<()> = Mutex::new(());

fn scene_64() -> Scene {
    let mut desc: SceneDesc = load_scene("cornell_spheres");
    desc.film.width = 64;
    desc.film.height = 64;
    Scene::build(&desc).expect("scene builds")
}

fn render(scene: &Scene, settings: RenderSettings) -> (RenderOutput, f64) {
    let t = Instant::now();
    let out = Renderer::new(scene)
        .settings(settings)
        .render()
        .expect("render succeeds");
    (out, t.elapsed().as_secs_f64())
}

fn budgeted(budget: f64, seed: u64, threads: usize) -> RenderSettings {
    RenderSettings {
        seed,
        threads,
        time_budget: Some(budget),
        ..Default::default()
    }
}

fn assert_finite(out: &RenderOutput) {
    for t in Term::ALL {
        assert!(
            out.film
                .term(t)
                .data
                .iter()
                .all(|p| p.iter().all(|v| v.is_finite())),
            "{} has a non-finite pixel",
            t.name()
        );
    }
}

#[test]
fn wall_time_is_within_five_percent_of_the_budget() {
    let _g = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let scene = scene_64();
    for budget in [1.0, 2.0, 4.0] {
        let (out, wall) = render(&scene, budgeted(budget, 7, 0));
        let bs = out.stats.time_budget.as_ref().expect("budget stats");
        let tolerance = (0.05 * budget).max(0.15);
        eprintln!(
            "budget {budget} s: wall {wall:.3} s, actual {:.3} s, planned {:.3} s, {} passes, \
             photons {}/{}",
            bs.actual_seconds, bs.planned_seconds, bs.passes, bs.photons_global, bs.photons_caustic
        );
        eprintln!(
            "  {:?} cache records {}",
            out.stats.seconds, out.stats.irradiance_cache_records
        );
        assert!(
            (wall - budget).abs() <= tolerance,
            "budget {budget} s took {wall:.3} s (tolerance {tolerance} s): {bs:?}"
        );
        assert!(!bs.too_small);
        assert!(bs.passes >= 1 && out.stats.spp == bs.passes);
        assert_finite(&out);
    }
}

#[test]
fn tiny_budget_still_renders_one_pass_and_says_so() {
    let _g = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let scene = scene_64();
    // A millisecond: the calibration alone takes longer.
    let (out, _) = render(&scene, budgeted(0.001, 3, 0));
    let bs = out.stats.time_budget.as_ref().expect("budget stats");
    assert!(out.stats.spp >= 1 && bs.passes >= 1);
    assert!(bs.too_small, "{bs:?}");
    let json = serde_json::to_string(&out.stats).expect("stats serialise");
    assert!(json.contains("\"too_small\":true"), "{json}");
    assert!(json.contains("too small"), "{json}");
    assert_finite(&out);
}

#[test]
fn recorded_plan_reproduces_the_image_bit_for_bit() {
    let _g = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let scene = scene_64();
    let (a, _) = render(&scene, budgeted(1.0, 11, 2));
    let bs = a.stats.time_budget.clone().expect("budget stats");
    // The plan, passed explicitly, with another thread count.
    let mut explicit = RenderSettings {
        seed: 11,
        threads: 1,
        spp: bs.spp,
        progressive: true,
        gather_rays_per_sample: Some(bs.gather_rays_per_sample),
        ..Default::default()
    };
    explicit.photons.global = bs.photons_global;
    explicit.photons.caustic = bs.photons_caustic;
    explicit.photons.volume = bs.photons_volume;
    explicit.photons.final_gather_rays = bs.final_gather_rays;
    let (b, _) = render(&scene, explicit);
    assert!(b.stats.time_budget.is_none());
    assert_eq!(a.stats.spp, b.stats.spp);
    assert_eq!(a.stats.photons_stored, b.stats.photons_stored);
    for t in Term::ALL {
        let (x, y) = (&a.film.term(t).data, &b.film.term(t).data);
        assert!(
            x.iter()
                .zip(y)
                .all(|(p, q)| p.map(f32::to_bits) == q.map(f32::to_bits)),
            "{} differs",
            t.name()
        );
    }
}

#[test]
fn invalid_budgets_name_the_setting() {
    let scene = scene_64();
    for bad in [-1.0, f64::NAN, f64::INFINITY] {
        let err = Renderer::new(&scene)
            .settings(budgeted(bad, 0, 1))
            .render()
            .err()
            .expect("an invalid budget is an error");
        assert!(err.to_string().contains("`time_budget`"), "{err}");
        assert!(err.for_cli().to_string().contains("`--time-budget`"));
    }
}

/// Progressive photon mapping under a budget: passes (each with its photon map) are added
/// while the next fits, and the wall time lands within 5% of the budget; the same number of
/// passes without a budget gives the same image, bit for bit.
#[test]
fn progressive_mode_fills_the_budget_and_replays() {
    let _g = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let scene = scene_64();
    let sppm = |budget: Option<f64>, spp: u32| RenderSettings {
        seed: 3,
        spp,
        time_budget: budget,
        mode: photonmap::render::settings::RenderMode::Sppm,
        photons: photonmap::render::PhotonSettings {
            global: 10_000,
            ..Default::default()
        },
        ..Default::default()
    };
    for budget in [1.0, 2.0, 4.0] {
        let (out, wall) = render(&scene, sppm(Some(budget), 1));
        let bs = out.stats.time_budget.as_ref().expect("budget stats");
        eprintln!(
            "sppm, budget {budget} s: wall {wall:.3} s, {} passes of {:.4} s",
            bs.passes, bs.seconds_per_pass
        );
        let tolerance = (0.05 * budget).max(0.15);
        assert!(
            (wall - budget).abs() <= tolerance,
            "budget {budget} s took {wall:.3} s: {bs:?}"
        );
        assert!(bs.passes > 4 && out.stats.sppm.as_ref().unwrap().passes == bs.passes);
        assert_finite(&out);
        if budget == 1.0 {
            let (again, _) = render(&scene, sppm(None, bs.passes));
            assert_eq!(again.film.combined(), out.film.combined());
        }
    }
}
