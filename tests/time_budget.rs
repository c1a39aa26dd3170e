//! `--time-budget`: the render stops at the deadline and not before, a bigger budget buys a
//! bigger plan, a tiny budget still gives an image, and the recorded plan reproduces the image
//! bit for bit. No assertion reads the wall clock against the budget: how close a render lands
//! to its budget depends on the machine and its load, and is measured in `benches/`. What is
//! asserted is what the planner and the driver decide from their own measurements.
mod common;

use common::load_scene;
use photonmap::render::aov::Term;
use photonmap::render::budget::{BudgetStats, MIN_GATHER_RAYS, MIN_PHOTONS};
use photonmap::render::driver::deadline;
use photonmap::render::{ProgressFn, RenderOutput, RenderSettings, Renderer};
use photonmap::scene::{Scene, SceneDesc};
use std::sync::{Arc, Mutex};

/// Budgeted renders plan from timings measured while they run: run them one at a time, so
/// that one does not slow the other down in the middle of its plan.
static SERIAL: Mutex<()> = Mutex::new(());

fn scene_64() -> Scene {
    let mut desc: SceneDesc = load_scene("cornell_spheres");
    desc.film.width = 64;
    desc.film.height = 64;
    Scene::build(&desc).expect("scene builds")
}

/// Renders, and returns the progress fractions reported under `phase`, in order.
fn render(
    scene: &Scene,
    settings: RenderSettings,
    phase: &'static str,
) -> (RenderOutput, Vec<f32>) {
    let reports: Arc<Mutex<Vec<f32>>> = Arc::default();
    let sink = reports.clone();
    let progress: Arc<ProgressFn> = Arc::new(move |f: f32, name: &str| {
        if name == phase {
            sink.lock().unwrap().push(f);
        }
    });
    let out = Renderer::new(scene)
        .settings(settings)
        .progress(progress)
        .render()
        .expect("render succeeds");
    let reports = reports.lock().unwrap().clone();
    (out, reports)
}

/// What a render under a deadline must show, whatever the machine's speed:
/// - it stopped because the next pass would have ended after the deadline, not before: the
///   driver stops at the first check where `elapsed + time per pass > deadline`, so the
///   render's own measurements satisfy `actual + seconds_per_pass > deadline`;
/// - every pass after the first was started before the deadline, and was announced: the
///   driver reports `elapsed / deadline` before each pass it decides to run (`passes - 1`
///   reports below 1) and 1 at the end;
/// - the last pass was started only because it fitted: the driver ran it when `elapsed +
///   time per pass <= deadline`, and its time per pass then (the mean since the first pass
///   began, before the first report) is at least the mean between the first and the last
///   report, so those reports alone must satisfy `e_last + (e_last - e_first) / (passes - 1)
///   <= deadline` (to the f32 rounding of the fractions);
/// - the plan in the stats is the sum of its parts, and no more than the time taken.
fn assert_stopped_at_the_deadline(bs: &BudgetStats, reports: &[f32], parts: f64) {
    let d = deadline(bs.budget_seconds);
    assert!(bs.passes >= 1 && bs.spp == bs.passes, "{bs:?}");
    assert!(
        bs.actual_seconds + bs.seconds_per_pass > d,
        "stopped before the deadline: {:.4} s + {:.4} s per pass <= {d:.4} s: {bs:?}",
        bs.actual_seconds,
        bs.seconds_per_pass
    );
    let (last, before) = reports.split_last().expect("progress reports");
    assert_eq!(*last, 1.0, "{reports:?}");
    assert_eq!(before.len() as u32, bs.passes - 1, "{reports:?}");
    assert!(
        before.iter().all(|f| *f < 1.0) && before.windows(2).all(|w| w[0] <= w[1]),
        "a pass started after the deadline: {reports:?}"
    );
    if let (Some(first), Some(last)) = (before.first(), before.last()) {
        let (e_first, e_last) = (*first as f64 * d, *last as f64 * d);
        let per_pass_at_least = (e_last - e_first) / before.len() as f64;
        eprintln!(
            "  last pass: deadline - (start + per pass) = {:+.4} s (must be >= 0)",
            d - e_last - per_pass_at_least
        );
        assert!(
            e_last + per_pass_at_least <= d * (1.0 + 1e-6),
            "the last pass did not fit: started {e_last:.4} s in, at {per_pass_at_least:.4} s \
             per pass or more, deadline {d:.4} s: {bs:?}"
        );
    }
    eprintln!(
        "  stop: actual + per pass - deadline = {:+.4} s (must be > 0)",
        bs.actual_seconds + bs.seconds_per_pass - d
    );
    let planned = parts + bs.passes as f64 * bs.seconds_per_pass;
    assert!(
        (bs.planned_seconds - planned).abs() <= 1e-9 * planned.max(1.0),
        "planned {} s is not the sum of its parts {planned} s: {bs:?}",
        bs.planned_seconds
    );
    assert!(bs.planned_seconds <= bs.actual_seconds, "{bs:?}");
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

/// Jensen's mode under budgets of 1, 2 and 4 s: each render stops at its deadline (see
/// `assert_stopped_at_the_deadline`), the photon targets are the preset's scaled by one
/// factor (their ratio kept), and a bigger budget buys more photons.
#[test]
fn budget_stops_at_the_deadline_and_scales_the_plan() {
    let _g = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let scene = scene_64();
    let preset = RenderSettings::default();
    let mut plans: Vec<BudgetStats> = Vec::new();
    for budget in [1.0, 2.0, 4.0] {
        let (out, reports) = render(&scene, budgeted(budget, 7, 0), "render");
        let bs = out.stats.time_budget.clone().expect("budget stats");
        eprintln!(
            "budget {budget} s: actual {:.3} s, planned {:.3} s, {} passes of {:.4} s, \
             photons {}/{}, final gathering {} rays ({} per sample)",
            bs.actual_seconds,
            bs.planned_seconds,
            bs.passes,
            bs.seconds_per_pass,
            bs.photons_global,
            bs.photons_caustic,
            bs.final_gather_rays,
            bs.gather_rays_per_sample
        );
        assert!(!bs.too_small, "{bs:?}");
        assert_eq!(out.stats.spp, bs.passes);
        let sec = &out.stats.seconds;
        let parts = bs.calibration_seconds + sec["photons"] + sec["irradiance_cache"];
        assert_stopped_at_the_deadline(&bs, &reports, parts);
        // One scale factor for every map: the preset's caustic/global ratio, to rounding.
        let ratio = preset.caustic_photons as f64 / preset.photons as f64;
        if bs.photons_caustic > MIN_PHOTONS && bs.photons_global > MIN_PHOTONS {
            let off = (bs.photons_caustic as f64 - ratio * bs.photons_global as f64).abs();
            assert!(
                off <= 1.0 + ratio,
                "photon targets off the preset's ratio: {bs:?}"
            );
        }
        // Final gathering: never more rays than the preset's, never fewer than the floor.
        assert!(
            (MIN_GATHER_RAYS..=preset.final_gather_rays.max(MIN_GATHER_RAYS))
                .contains(&bs.final_gather_rays),
            "{bs:?}"
        );
        assert!(bs.gather_rays_per_sample >= 4, "{bs:?}");
        assert_eq!(out.stats.non_finite_samples, 0);
        assert_finite(&out);
        plans.push(bs);
    }
    // Four times the budget: more photons (the plan scales with the budget on any machine;
    // timing noise would have to be fourfold to reverse it). The passes need not grow: the
    // bigger maps make each pass dearer.
    let (small, big) = (&plans[0], &plans[2]);
    assert!(
        big.photons_global > small.photons_global && big.photons_caustic > small.photons_caustic,
        "4 s planned no more photons than 1 s: {small:?} {big:?}"
    );
}

#[test]
fn tiny_budget_still_renders_one_pass_and_says_so() {
    let _g = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let scene = scene_64();
    // A millisecond: the calibration alone takes longer.
    let (out, _) = render(&scene, budgeted(0.001, 3, 0), "render");
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
    let (a, _) = render(&scene, budgeted(1.0, 11, 2), "render");
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
    explicit.photons = bs.photons_global;
    explicit.caustic_photons = bs.photons_caustic;
    explicit.volume_photons = bs.photons_volume;
    explicit.final_gather_rays = bs.final_gather_rays;
    let (b, _) = render(&scene, explicit, "render");
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
/// while the next fits, and each render stops at its deadline (see
/// `assert_stopped_at_the_deadline`; the plan is the passes alone); four times the budget
/// runs more passes; the same number of passes without a budget gives the same image, bit
/// for bit.
#[test]
fn progressive_mode_stops_at_the_deadline_and_replays() {
    let _g = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let scene = scene_64();
    let sppm = |budget: Option<f64>, spp: u32| RenderSettings {
        seed: 3,
        spp,
        time_budget: budget,
        mode: photonmap::render::settings::RenderMode::Sppm,
        photons: 10_000,
        ..Default::default()
    };
    let mut passes = Vec::new();
    for budget in [1.0, 2.0, 4.0] {
        let (out, reports) = render(&scene, sppm(Some(budget), 1), "progressive");
        let bs = out.stats.time_budget.clone().expect("budget stats");
        eprintln!(
            "sppm, budget {budget} s: actual {:.3} s, {} passes of {:.4} s",
            bs.actual_seconds, bs.passes, bs.seconds_per_pass
        );
        assert!(!bs.too_small, "{bs:?}");
        assert_stopped_at_the_deadline(&bs, &reports, 0.0);
        assert_eq!(out.stats.sppm.as_ref().unwrap().passes, bs.passes);
        assert_eq!(out.stats.spp, bs.passes);
        assert_finite(&out);
        if budget == 1.0 {
            let (again, _) = render(&scene, sppm(None, bs.passes), "progressive");
            assert_eq!(again.film.combined(), out.film.combined());
        }
        passes.push(bs.passes);
    }
    assert!(
        passes[2] > passes[0],
        "4 s ran no more passes than 1 s: {passes:?}"
    );
}
