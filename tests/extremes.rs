//! Numerical stability at the extremes: scene scale and translation, glass IOR, albedo 0 and
//! 1, light power over 18 decades, tiny and huge photon counts, gather sizes and radii,
//! degenerate geometry, thin and dense media. Every render goes through `firewall`: no AOV
//! pixel is NaN, infinite or negative, and the stats report the dropped non-finite samples.
//! Then: NaN/Inf in every kind of IR field is rejected with a JSON pointer; determinism on a
//! scene with glass, fog and an irradiance cache; the memory budget checked before the
//! photon pass.
//!
//! Images are 16x16 with few samples and small photon maps, so that each test takes seconds.

use crate::common;
use common::*;
use glam::Vec3;
use photonmap::cli::{Cli, Command};
use photonmap::geometry::shapes;
use photonmap::render::aov::Term;
use photonmap::render::settings::Bytes;
use photonmap::render::settings::FilterName;
use photonmap::render::settings::{BYTES_PER_PHOTON, BYTES_PER_TRIANGLE};
use photonmap::render::{Quality, RenderOutput, RenderSettings, Renderer};
use photonmap::scene::desc::*;
use photonmap::scene::{Scene, SceneDesc};
use photonmap::Error;
use std::sync::{Arc, Mutex};

// ---------------------------------------------------------------------------------------
// Helpers

/// Small photon maps and few samples.
fn small_settings(seed: u64) -> RenderSettings {
    RenderSettings {
        spp: 2,
        seed,
        threads: 0,
        filter: FilterName::Box,
        photons: 4_000,
        caustic_photons: 2_000,
        volume_photons: 2_000,
        final_gather_rays: 16,
        gather: 50,
        ..Default::default()
    }
}

fn run(desc: &SceneDesc, settings: RenderSettings) -> RenderOutput {
    let scene = Scene::build(desc).expect("scene builds");
    Renderer::new(&scene)
        .settings(settings)
        .render()
        .expect("render succeeds")
}

/// The NaN/Inf firewall: every pixel of every AOV is finite and >= 0, the stats carry the
/// count of non-finite estimates that were dropped (also in the stats JSON), and that count
/// is at most `allowed_non_finite`. Returns the count.
fn firewall(label: &str, out: &RenderOutput, allowed_non_finite: u64) -> u64 {
    for t in Term::ALL {
        for (i, p) in out.film.term(t).data.iter().enumerate() {
            assert!(
                p.iter().all(|c| c.is_finite() && *c >= 0.0),
                "{label}: {} pixel {i} = {p:?}",
                t.name()
            );
        }
    }
    let json = serde_json::to_value(&out.stats).expect("stats serialise");
    let n = json["non_finite_samples"]
        .as_u64()
        .expect("stats JSON reports non_finite_samples");
    assert_eq!(n, out.stats.non_finite_samples);
    eprintln!("{label}: non_finite_samples = {n}");
    assert!(
        n <= allowed_non_finite,
        "{label}: {n} non-finite samples dropped"
    );
    n
}

/// Every term of `out` against its twin's, per 4x4-pixel block: the largest relative
/// difference of a block mean (over the twin's block mean plus 1% of the twin's image mean).
fn worst_block_vs_twin(out: &RenderOutput, twin: &RenderOutput) -> (f64, &'static str) {
    let mut worst = (0.0f64, "");
    for t in Term::ALL {
        let (a, b) = (out.film.term(t), twin.film.term(t));
        let floor = 0.01 * mean(twin, t);
        let (w, h) = (a.width, a.height);
        for by in 0..h / 4 {
            for bx in 0..w / 4 {
                let (mut sa, mut sb) = (0.0f64, 0.0f64);
                for y in by * 4..by * 4 + 4 {
                    for x in bx * 4..bx * 4 + 4 {
                        sa += a.get(x, y).element_sum() as f64;
                        sb += b.get(x, y).element_sum() as f64;
                    }
                }
                let (ma, mb) = (sa / 48.0, sb / 48.0);
                let d = (ma - mb).abs() / (mb + floor).max(1e-12);
                if d > worst.0 {
                    worst = (d, t.name());
                }
            }
        }
    }
    worst
}

/// Seeds of each side of a twin comparison: its noise is taken from their spread.
const TWIN_SEEDS: u64 = 6;

/// A render against its unperturbed twin: for each term, the image means of both (over the
/// seeds) and the t-tests of its 4x4 blocks (extreme minus twin, the farthest first).
#[derive(Debug)]
struct TwinResult {
    terms: Vec<(Term, f64, f64, Vec<common::compare::BlockT>)>,
}

impl TwinResult {
    /// (extreme mean, twin mean) of `t`.
    fn of(&self, t: Term) -> (f64, f64) {
        let (_, a, b, _) = self.terms.iter().find(|x| x.0 == t).expect("term compared");
        (*a, *b)
    }

    /// True when no 4x4 block of `t` is brighter than the twin's beyond its noise.
    fn not_brighter(&self, t: Term) -> bool {
        let (_, _, _, tests) = self.terms.iter().find(|x| x.0 == t).expect("term compared");
        tests.iter().all(|b| b.2 <= b.4)
    }
}

/// `desc` against `twin`, both rendered with `settings(seed)`: see [`twin_renders`].
fn against_twin(
    label: &str,
    desc: &SceneDesc,
    twin: &SceneDesc,
    settings: impl Fn(u64) -> RenderSettings,
    same: &[Term],
) -> TwinResult {
    twin_renders(label, (desc, &settings), (twin, &settings), same)
}

/// `desc` rendered with `settings(seed)` against the same scene with `twin(seed)`.
fn against_twin_settings(
    label: &str,
    desc: &SceneDesc,
    settings: impl Fn(u64) -> RenderSettings,
    twin: impl Fn(u64) -> RenderSettings,
    same: &[Term],
) -> TwinResult {
    twin_renders(label, (desc, &settings), (desc, &twin), same)
}

/// An extreme and its twin, each rendered for `TWIN_SEEDS` seeds (each render through the
/// firewall): every 4x4 block of each term of `same` must agree by a Welch t-test, the noise
/// of each side from the spread of its seeds (camera samples and photon maps alike),
/// Bonferroni over the blocks and terms at a family-wise false-alarm rate of 10^-3. Every
/// term's means and block tests are returned for the cases where the extreme must change
/// the image.
fn twin_renders(
    label: &str,
    extreme: (&SceneDesc, &dyn Fn(u64) -> RenderSettings),
    twin: (&SceneDesc, &dyn Fn(u64) -> RenderSettings),
    same: &[Term],
) -> TwinResult {
    use common::compare::{block_t_tests, Blocks};
    let renders = |(d, settings): (&SceneDesc, &dyn Fn(u64) -> RenderSettings), what: &str| {
        (0..TWIN_SEEDS)
            .map(|k| {
                let out = run(d, settings(101 + k));
                firewall(&format!("{label} ({what}, seed {})", 101 + k), &out, 0);
                out
            })
            .collect::<Vec<RenderOutput>>()
    };
    let (a, b) = (renders(extreme, "extreme"), renders(twin, "twin"));
    let mut terms = Vec::new();
    for t in Term::ALL {
        let img = |outs: &[RenderOutput]| -> Vec<photonmap::render::film::Image> {
            outs.iter().map(|o| o.film.term(t).clone()).collect()
        };
        let (ba, bb) = (Blocks::of_seeds(&img(&a), 4), Blocks::of_seeds(&img(&b), 4));
        let ma = a.iter().map(|o| mean(o, t)).sum::<f64>() / a.len() as f64;
        let mb = b.iter().map(|o| mean(o, t)).sum::<f64>() / b.len() as f64;
        let tests = block_t_tests(&ba, &bb, 1e-3 / same.len().max(1) as f64);
        let worst = tests[0];
        eprintln!(
            "{label}: {} mean {ma:.5e} vs twin {mb:.5e}; farthest 4x4 block (bx, by, t, \
             ratio, critical |t|) {worst:?}",
            t.name()
        );
        if same.contains(&t) {
            assert!(
                worst.2.abs() <= worst.4,
                "{label}: {} block ({}, {}) off its twin's by t = {:.2} (critical {:.2}): \
                 {:.5e} vs {:.5e}",
                t.name(),
                worst.0,
                worst.1,
                worst.2,
                worst.4,
                ba.mean[worst.1 * ba.width + worst.0],
                bb.mean[worst.1 * bb.width + worst.0]
            );
        }
        terms.push((t, ma, mb, tests));
    }
    TwinResult { terms }
}

fn mean(out: &RenderOutput, t: Term) -> f64 {
    let m = out.film.term(t).mean();
    (m.x as f64 + m.y as f64 + m.z as f64) / 3.0
}

fn small(mut desc: SceneDesc) -> SceneDesc {
    desc.film.width = 16;
    desc.film.height = 16;
    desc
}

/// Maps world points by p -> s p + t: mesh positions are scaled and the translation of every
/// transform is mapped (rotations are kept); lights grow by s and their power by s^2, so that
/// the radiance of area lights (P / (pi A)) and the irradiance of point lights
/// (P / (4 pi d^2)) are unchanged.
fn rescale(desc: &SceneDesc, s: f32, t: Vec3) -> SceneDesc {
    let map_t = |m: &mut Matrix| {
        for r in 0..3 {
            m[r][3] = s * m[r][3] + t[r];
        }
    };
    let mut d = desc.clone();
    for mesh in &mut d.meshes {
        for p in &mut mesh.positions {
            for v in p.iter_mut() {
                *v *= s;
            }
        }
        map_t(&mut mesh.transform);
    }
    map_t(&mut d.camera.transform);
    d.camera.near *= s;
    for l in &mut d.lights {
        match l {
            LightDesc::Rect {
                transform,
                width,
                height,
                power,
                ..
            } => {
                map_t(transform);
                *width *= s;
                *height *= s;
                *power *= s * s;
            }
            LightDesc::Disk {
                transform,
                radius,
                power,
                ..
            } => {
                map_t(transform);
                *radius *= s;
                *power *= s * s;
            }
            LightDesc::Point {
                position,
                power,
                radius,
                ..
            } => {
                *position = (Vec3::from(*position) * s + t).to_array();
                *radius *= s;
                *power *= s * s;
            }
            other => panic!("rescale: light {other:?} not handled"),
        }
    }
    d
}

fn scale_lights(desc: &mut SceneDesc, k: f32) {
    for l in &mut desc.lights {
        match l {
            LightDesc::Rect { power, .. }
            | LightDesc::Disk { power, .. }
            | LightDesc::Point { power, .. }
            | LightDesc::Spot { power, .. }
            | LightDesc::Sphere { power, .. } => *power *= k,
            LightDesc::Distant { irradiance, .. } => *irradiance *= k,
        }
    }
}

fn cuboid_mesh(name: &str, min: Vec3, max: Vec3, material: u32) -> MeshDesc {
    let b = shapes::cuboid(min, max);
    MeshDesc {
        name: name.into(),
        positions: b.positions.iter().map(|p| p.to_array()).collect(),
        indices: b.indices.clone(),
        material,
        ..Default::default()
    }
}

/// A closed diffuse box [-1, 1]^3 of the given albedo; the camera is inside at z = 0.8
/// looking down -z; a point light of 10 W at `light`.
fn closed_box(albedo: f32, light: [f32; 3]) -> SceneDesc {
    let mut cam = IDENTITY;
    cam[2][3] = 0.8;
    SceneDesc {
        camera: CameraDesc {
            transform: cam,
            fov: Some(1.2),
            ..Default::default()
        },
        film: FilmDesc {
            width: 16,
            height: 16,
            transparent: false,
        },
        meshes: vec![cuboid_mesh("box", Vec3::splat(-1.0), Vec3::splat(1.0), 0)],
        materials: vec![MaterialDesc::Diffuse {
            name: "wall".into(),
            color: ColorInput::Value([albedo; 3]),
        }],
        lights: vec![LightDesc::Point {
            name: "bulb".into(),
            position: light,
            power: 10.0,
            color: [1.0; 3],
            radius: 0.0,
            soft_falloff: false,
            camera_visible: true,
        }],
        ..Default::default()
    }
}

fn set_glass_ior(desc: &mut SceneDesc, value: f32) {
    let mut n = 0;
    for m in &mut desc.materials {
        if let MaterialDesc::Dielectric { ior, .. } = m {
            *ior = value;
            n += 1;
        }
    }
    assert!(n > 0, "the scene has glass");
}

// ---------------------------------------------------------------------------------------
// Scene scale and translation

/// Expected: p -> s p + t with light power x s^2 leaves every radiance unchanged (area-light
/// radiance P / (pi A) and the BRDFs are scale-free; photon radii and the march step are
/// derived from the scene radius, so the photon density estimate is scale-free too).
/// Tolerance: the direct term's image mean within 3% of the unit scene's, the indirect
/// term's within 5% (same seed: only floating-point differences and the paths they change).
#[test]
fn scale_and_translation_leave_the_image_unchanged() {
    let base = small(load_scene("cornell_diffuse"));
    let reference = run(&base, small_settings(3));
    firewall("unit scale", &reference, 0);
    let (d0, i0) = (
        mean(&reference, Term::Direct),
        mean(&reference, Term::Indirect),
    );
    assert!(d0 > 0.0 && i0 > 0.0);
    eprintln!("unit scale: direct {d0:.6e}, indirect {i0:.6e}");
    let cases = [
        ("scale 1e-3", 1e-3, Vec3::ZERO),
        ("scale 1e3", 1e3, Vec3::ZERO),
        ("translate 1e5", 1.0, Vec3::splat(1e5)),
    ];
    let mut failures = Vec::new();
    for (label, s, t) in cases {
        let out = run(&rescale(&base, s, t), small_settings(3));
        firewall(label, &out, 0);
        let (d, i) = (mean(&out, Term::Direct), mean(&out, Term::Indirect));
        let (rd, ri) = (d / d0 - 1.0, i / i0 - 1.0);
        eprintln!(
            "{label}: direct {d:.6e} ({:+.3}%), indirect {i:.6e} ({:+.3}%)",
            rd * 100.0,
            ri * 100.0
        );
        if rd.abs() > 0.03 || ri.abs() > 0.05 {
            failures.push(format!(
                "{label}: direct {:+.2}% (tol 3%), indirect {:+.2}% (tol 5%)",
                rd * 100.0,
                ri * 100.0
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

// ---------------------------------------------------------------------------------------
// Glass IOR

/// Expected: IOR 1.0001 (nearly index-matched: almost no reflection, TIR nowhere) and 4.0
/// (strong Fresnel reflection and total internal reflection over most of the inside) both
/// give finite, non-negative AOVs with no dropped samples. The IOR changes only what is seen
/// through or in the glass and what it focuses: the direct and emission terms match the
/// twin scene's (IOR 1.5) per 4x4 block within noise (shadow rays stop at glass whatever
/// its IOR). IOR 1.0001 is all but index-matched:
/// every term matches the scene with its glass at IOR 1 per 4x4 block within noise.
#[test]
fn extreme_glass_ior_changes_only_the_glass() {
    let base = small(photonmap::scene::default_scene());
    let with_ior = |ior: f32| {
        let mut d = base.clone();
        set_glass_ior(&mut d, ior);
        d
    };
    against_twin(
        "ior 4",
        &with_ior(4.0),
        &base,
        small_settings,
        &[Term::Direct, Term::Emission],
    );
    against_twin(
        "ior 1.0001",
        &with_ior(1.0001),
        &with_ior(1.0),
        small_settings,
        &Term::ALL,
    );
}

// ---------------------------------------------------------------------------------------
// Albedo 0 and 1

/// Expected: a closed box of albedo exactly 1 with a light inside never absorbs a photon:
/// Russian roulette always continues, so only `max_bounces` ends a path. The photon pass and
/// the render terminate and are finite. Tolerance: exact (finite, >= 0, no dropped samples).
#[test]
fn closed_white_box_of_albedo_one_terminates() {
    let desc = closed_box(1.0, [0.0, 0.5, 0.0]);
    let mut s = small_settings(7);
    s.max_bounces = 64;
    let t0 = std::time::Instant::now();
    let out = run(&desc, s);
    firewall("albedo 1 box", &out, 0);
    let built: Vec<_> = out.stats.photon_maps.iter().filter(|m| m.built).collect();
    assert!(built.iter().any(|m| m.map == "global" && m.stored > 0));
    assert!(mean(&out, Term::Indirect) > 0.0);
    eprintln!(
        "albedo 1 box: {:.2} s, direct {:.4e}, indirect {:.4e}",
        t0.elapsed().as_secs_f64(),
        mean(&out, Term::Direct),
        mean(&out, Term::Indirect)
    );
}

/// Expected: albedo 0 reflects nothing, so indirect light (final gathering of light
/// reflected off other surfaces, times the albedo at the gather point) is exactly 0, and
/// so is direct light (albedo x irradiance). Tolerance: exactly 0.
#[test]
fn black_box_has_no_indirect_light() {
    let desc = closed_box(0.0, [0.0, 0.5, 0.0]);
    let out = run(&desc, small_settings(7));
    firewall("albedo 0 box", &out, 0);
    for t in [Term::Indirect, Term::Direct, Term::Caustic] {
        assert_eq!(mean(&out, t), 0.0, "{}", t.name());
        assert!(out.film.term(t).data.iter().all(|p| *p == [0.0; 3]));
    }
}

// ---------------------------------------------------------------------------------------
// Light power

/// Expected: radiance is linear in light power, so with the same seed every term's image
/// mean divided by the power is the same for power 1e-6, 1 and 1e12 (photon powers go through
/// RGBE, whose 8-bit shared exponent spans 2^-128..2^127, so 1e12 / photons and
/// 1e-6 / photons are both in range). Tolerance: 1% per term.
#[test]
fn image_scales_linearly_with_light_power() {
    let mut base = small(photonmap::scene::default_scene());
    // Power 1 W.
    let p0 = match &base.lights[0] {
        LightDesc::Rect { power, .. } => *power,
        _ => unreachable!(),
    };
    scale_lights(&mut base, 1.0 / p0);
    let reference = run(&base, small_settings(11));
    firewall("power 1", &reference, 0);
    let mut failures = Vec::new();
    for k in [1e-6f32, 1e12] {
        let mut desc = base.clone();
        scale_lights(&mut desc, k);
        let out = run(&desc, small_settings(11));
        firewall(&format!("power {k:e}"), &out, 0);
        for t in Term::ALL {
            let (a, b) = (mean(&out, t) / k as f64, mean(&reference, t));
            let rel = if b == 0.0 { a } else { a / b - 1.0 };
            eprintln!(
                "power {k:e}: {} mean/power {a:.6e} vs {b:.6e} ({:+.4}%)",
                t.name(),
                rel * 100.0
            );
            if rel.abs() > 0.01 {
                failures.push(format!("power {k:e}, {}: {:+.3}%", t.name(), rel * 100.0));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

// ---------------------------------------------------------------------------------------
// Photon counts, gather size, radius

/// Expected: 1 and 10 stored photons per map (global, caustic, volume, on a scene with
/// glass and fog) terminate and give finite, non-negative AOVs, and leave the terms that read
/// no photon map as they are: direct light and emission match the twin render's (the usual
/// small maps) per 4x4 block within noise.
#[test]
fn one_and_ten_photons_terminate() {
    let desc = small(load_scene("fog_glass"));
    for n in [1usize, 10] {
        let settings = |seed| {
            let mut s = small_settings(seed);
            s.photons = n;
            s.caustic_photons = n;
            s.volume_photons = n;
            s
        };
        // The twin: the same scene with the usual maps, through the same comparison.
        let twin = |seed| small_settings(seed);
        against_twin_settings(
            &format!("{n} photons"),
            &desc,
            settings,
            twin,
            &[Term::Direct, Term::Emission],
        );
    }
}

/// Expected: k = 1 and k = 10000 (more than the map holds), and a maximum radius of 1e-6
/// and 1e6 (every photon in range), give finite, non-negative AOVs on a scene with all three
/// maps, and leave direct light and emission as the twin render's (k = 50, the default
/// radius) per 4x4 block within noise. A radius of 1e-6 finds no photon: the caustic and
/// indirect terms are exactly 0.
#[test]
fn extreme_gather_sizes_and_radii_stay_finite() {
    let desc = small(load_scene("fog_glass"));
    type Tweak = fn(&mut RenderSettings);
    let cases: [(&str, Tweak); 4] = [
        ("gather 1", |p| p.gather = 1),
        ("gather 10000", |p| p.gather = 10_000),
        ("radius 1e-6", |p| p.radius = Some(1e-6)),
        ("radius 1e6", |p| p.radius = Some(1e6)),
    ];
    for (label, tweak) in cases {
        let settings = |seed| {
            let mut s = small_settings(seed);
            tweak(&mut s);
            s
        };
        let r = against_twin_settings(
            label,
            &desc,
            settings,
            small_settings,
            &[Term::Direct, Term::Emission],
        );
        if label == "radius 1e-6" {
            // No photon lies within 1e-6 of a shading point: the caustic term is 0, and the
            // final gather finds only what it reaches through specular bounces.
            assert_eq!(r.of(Term::Caustic).0, 0.0, "{label}: caustic");
            let (ind, twin) = r.of(Term::Indirect);
            assert!(
                ind < 0.5 * twin,
                "{label}: indirect {ind:.4e}, twin {twin:.4e}"
            );
        }
    }
}

// ---------------------------------------------------------------------------------------
// Degenerate geometry

/// Expected: zero-area triangles (collinear vertices, a repeated vertex) and two coincident
/// copies of the same triangles, in an otherwise ordinary Cornell box, give finite AOVs, no
/// dropped samples, and the image of the twin scene holding each real triangle once: every
/// term, per 4x4 block, within 2% (the same seed; only the hit chosen among coincident
/// triangles may differ).
#[test]
fn zero_area_and_duplicate_triangles_stay_finite() {
    let mut desc = small(load_scene("cornell_diffuse"));
    desc.meshes.push(MeshDesc {
        name: "degenerate".into(),
        positions: vec![
            [-0.3, -0.5, 0.0],
            [0.0, -0.5, 0.0],
            [0.3, -0.5, 0.0],
            [0.0, -0.2, 0.0],
            [-0.3, -0.5, 0.3],
            [0.3, -0.5, 0.3],
        ],
        indices: vec![
            [0, 1, 2], // collinear
            [0, 0, 3], // repeated vertex
            [3, 3, 3], // a point
            [0, 2, 3], // a real triangle...
            [0, 2, 3], // ...and its coincident copy
            [2, 0, 3], // ...and a copy with the opposite winding
            [4, 5, 3],
            [4, 5, 3],
        ],
        material: 0,
        ..Default::default()
    });
    let out = run(&desc, small_settings(19));
    firewall("degenerate triangles", &out, 0);
    let mut twin = desc.clone();
    twin.meshes.last_mut().unwrap().indices = vec![[0, 2, 3], [4, 5, 3]];
    let (d, term) = worst_block_vs_twin(&out, &run(&twin, small_settings(19)));
    eprintln!(
        "degenerate triangles vs twin: worst block {:.3}% ({term})",
        100.0 * d
    );
    assert!(
        d < 0.02,
        "degenerate triangles: {term} block off by {:.2}%",
        100.0 * d
    );
}

/// Expected: an emissive mesh whose only triangle has zero area emits nothing (it has no
/// area to sample) and does not poison the image: it renders as the twin scene without it,
/// every term per 4x4 block within 2%.
#[test]
fn zero_area_emissive_triangle_stays_finite() {
    let mut desc = small(load_scene("cornell_diffuse"));
    desc.materials.push(MaterialDesc::Emission {
        name: "glow".into(),
        color: ColorInput::Value([1.0; 3]),
        strength: 10.0,
    });
    let glow = desc.materials.len() as u32 - 1;
    desc.meshes.push(MeshDesc {
        name: "flat_emitter".into(),
        positions: vec![[-0.2, 0.0, 0.0], [0.0, 0.0, 0.0], [0.2, 0.0, 0.0]],
        indices: vec![[0, 1, 2]],
        material: glow,
        ..Default::default()
    });
    let out = run(&desc, small_settings(19));
    firewall("zero-area emissive triangle", &out, 0);
    let (d, term) = worst_block_vs_twin(
        &out,
        &run(&small(load_scene("cornell_diffuse")), small_settings(19)),
    );
    eprintln!(
        "zero-area emitter vs twin: worst block {:.3}% ({term})",
        100.0 * d
    );
    assert!(
        d < 0.02,
        "zero-area emitter: {term} block off by {:.2}%",
        100.0 * d
    );
}

/// Expected: a light of zero area is rejected by validation with the field's JSON pointer
/// and its name in the message.
#[test]
fn zero_area_lights_are_rejected_naming_the_field() {
    let mut desc = load_scene("cornell_diffuse");
    if let LightDesc::Rect { width, .. } = &mut desc.lights[0] {
        *width = 0.0;
    }
    let e = photonmap::scene::validate(&desc).expect_err("width 0 is rejected");
    let msg = e.to_string();
    eprintln!("width 0: {msg}");
    assert!(
        matches!(&e, Error::InvalidScene { pointer, .. } if pointer == "/lights/0/width"),
        "{e:?}"
    );
    assert!(msg.contains("/lights/0/width") && msg.contains("ceiling_light"));
    desc.lights[0] = LightDesc::Disk {
        name: "disk".into(),
        transform: IDENTITY,
        radius: 0.0,
        radius_y: None,
        power: 1.0,
        color: [1.0; 3],
        two_sided: false,
        spread: std::f32::consts::PI,
        camera_visible: true,
    };
    let e = photonmap::scene::validate(&desc).expect_err("radius 0 is rejected");
    assert!(e.to_string().contains("/lights/0/radius"), "{e}");
}

/// Expected: a camera inside a closed box with walls thicker than the largest photon search
/// radius (0.1 x the scene radius), lit only from outside, sees no light at all: every term
/// is exactly 0 in every pixel. Tolerance: exact.
///
/// With zero-thickness walls the same holds for direct light, but not for the photon-map
/// terms: the k-nearest search around a point on an inner wall near an edge reaches photons
/// on the outside of the adjacent wall, which arrive from the side of the inner wall's normal
/// and pass the side test of the radiance estimate. That is the light leak of density
/// estimation at thin geometry (Jensen 2001, §7.5), not a numerical fault; the thin case
/// only checks that it is finite and bounded by the leak's source, and reports its size.
#[test]
fn camera_inside_a_closed_box_lit_from_outside_sees_black() {
    let mut thick = closed_box(0.75, [0.0, 3.0, 0.0]);
    thick
        .meshes
        .push(cuboid_mesh("outer", Vec3::splat(-1.5), Vec3::splat(1.5), 0));
    let scene = Scene::build(&thick).unwrap();
    assert!(
        0.1 * scene.radius < 0.5,
        "walls thicker than the search radius"
    );
    let out = run(&thick, small_settings(23));
    firewall("camera in closed thick box", &out, 0);
    for t in Term::ALL {
        assert!(
            out.film.term(t).data.iter().all(|p| *p == [0.0; 3]),
            "{} is not black",
            t.name()
        );
    }

    let thin = closed_box(0.75, [0.0, 3.0, 0.0]);
    let out = run(&thin, small_settings(23));
    firewall("camera in closed thin box", &out, 0);
    let lit = run(&closed_box(0.75, [0.0, 0.5, 0.0]), small_settings(23));
    for t in [Term::Direct, Term::Caustic, Term::Emission, Term::Specular] {
        assert!(
            out.film.term(t).data.iter().all(|p| *p == [0.0; 3]),
            "thin box: {} is not black",
            t.name()
        );
    }
    let leak = mean(&out, Term::Indirect);
    let inside = mean(&lit, Term::Indirect);
    eprintln!(
        "thin box: indirect leak {leak:.4e}, {:.2}% of the indirect light with the light inside",
        100.0 * leak / inside
    );
    assert!(leak < 0.1 * inside);
    // The leak is the search reaching across the edges: with a radius far below the
    // distance from the edge to the nearest gather point it is gone.
    let mut s = small_settings(23);
    s.radius = Some(1e-4);
    let out = run(&thin, s);
    firewall("camera in closed thin box, radius 1e-4", &out, 0);
    assert_eq!(mean(&out, Term::Indirect), 0.0, "thin box, radius 1e-4");
}

// ---------------------------------------------------------------------------------------
// Media

/// Expected: a fog box with sigma_t = 1e-6 (nearly vacuum) and 1e4 (opaque over 1e-4 units,
/// far below the march step), an albedo-1 medium (sigma_a = 0: only max_bounces ends a photon
/// path in it) and g = +-0.99 (nearly a delta phase function) all terminate with finite,
/// non-negative AOVs, each against a twin:
/// - sigma_t 1e-6 renders as the scene without the fog, every surface term per 4x4 block
///   within noise, and its volume term is below 1e-4 of the direct light;
/// - sigma_t 1e4 hides what lies in and behind the fog box: less direct light is seen than
///   through the twin's fog (sigma_t 0.45), in every block within noise and in the mean;
/// - sigma_a 0 scatters more than the twin with sigma_a 0.05 (same sigma_s): more volume
///   light, and the surfaces seen through it no darker;
/// - g = +-0.99 changes where the fog scatters light, not how much it lets through: direct
///   light and emission match the twin's (g = 0.3) per 4x4 block within noise.
#[test]
fn extreme_media_against_their_twins() {
    let base = small(load_scene("fog_glass"));
    let medium = |sa: f32, ss: f32, g: f32| {
        let mut d = base.clone();
        d.media[0].sigma_a = [sa; 3];
        d.media[0].sigma_s = [ss; 3];
        d.media[0].g = g;
        d
    };
    // The twin without fog: the same scene without the fog box (its boundary is invisible).
    let mut no_fog = base.clone();
    no_fog.meshes.retain(|m| m.interior_medium.is_none());
    let surface: Vec<Term> = Term::ALL
        .into_iter()
        .filter(|&t| t != Term::Volume)
        .collect();
    let r = against_twin(
        "sigma_t 1e-6",
        &medium(1e-7, 9e-7, 0.3),
        &no_fog,
        small_settings,
        &surface,
    );
    // The nearly empty fog scatters about 1e-6 of what crosses it (the twin has no volume).
    let (vol, _) = r.of(Term::Volume);
    let (direct, _) = r.of(Term::Direct);
    assert!(
        vol < 1e-4 * direct,
        "sigma_t 1e-6: volume {vol:.4e} against direct {direct:.4e}"
    );

    let r = against_twin(
        "sigma_t 1e4",
        &medium(1e3, 9e3, 0.3),
        &base,
        small_settings,
        &[],
    );
    let (dense, twin) = r.of(Term::Direct);
    assert!(
        dense < twin,
        "sigma_t 1e4: direct {dense:.4e}, twin {twin:.4e}"
    );
    assert!(
        r.not_brighter(Term::Direct),
        "sigma_t 1e4: a block brighter than the twin's"
    );

    let r = against_twin(
        "albedo 1 (sigma_a 0)",
        &medium(0.0, 1.0, 0.3),
        &medium(0.05, 1.0, 0.3),
        small_settings,
        &[],
    );
    let (v1, v0) = r.of(Term::Volume);
    let (d1, d0) = r.of(Term::Direct);
    assert!(v1 > v0, "albedo 1: volume {v1:.4e}, twin {v0:.4e}");
    assert!(d1 >= d0, "albedo 1: direct {d1:.4e}, twin {d0:.4e}");

    for g in [0.99f32, -0.99] {
        against_twin(
            &format!("g {g}"),
            &medium(0.05, 0.4, g),
            &medium(0.05, 0.4, 0.3),
            small_settings,
            &[Term::Direct, Term::Emission],
        );
    }
}

// ---------------------------------------------------------------------------------------
// NaN / Inf in the scene IR

/// A scene with every kind of IR field: textured material, mesh with normals and uvs,
/// instance, each light type, a medium and the environment.
fn every_field_scene() -> SceneDesc {
    let mut desc = load_scene("cornell_diffuse");
    desc.textures.push(TextureDesc {
        name: "checker".into(),
        width: 2,
        height: 1,
        channels: 3,
        data: vec![0.2, 0.2, 0.2, 0.8, 0.8, 0.8],
        wrap: WrapMode::Repeat,
        encoding: Default::default(),
    });
    desc.materials.push(MaterialDesc::Diffuse {
        name: "textured".into(),
        color: ColorInput::Texture {
            texture: 0,
            scale: [1.0; 3],
        },
    });
    desc.materials.push(MaterialDesc::Dielectric {
        name: "glass".into(),
        ior: 1.5,
        roughness: 0.0,
        color: [1.0; 3],
        multiscatter: true,
    });
    desc.media.push(MediumDesc {
        name: "fog".into(),
        sigma_a: [0.1; 3],
        sigma_s: [0.5; 3],
        g: 0.2,
        density: None,
    });
    desc.meshes.push(MeshDesc {
        name: "card".into(),
        positions: vec![[0.0, 0.0, 0.0], [0.2, 0.0, 0.0], [0.0, 0.2, 0.0]],
        indices: vec![[0, 1, 2]],
        normals: Some(vec![[0.0, 0.0, 1.0]; 3]),
        uvs: Some(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
        material: 3,
        interior_medium: Some(0),
        ..Default::default()
    });
    desc.instances.push(InstanceDesc {
        name: "card_copy".into(),
        mesh: 5,
        transform: IDENTITY,
        ..Default::default()
    });
    desc.lights.push(LightDesc::Spot {
        name: "spot".into(),
        position: [0.0, 0.9, 0.0],
        direction: [0.0, -1.0, 0.0],
        power: 5.0,
        color: [1.0; 3],
        cone_angle: 0.8,
        blend: 0.1,
        radius: 0.0,
        soft_falloff: false,
        camera_visible: true,
    });
    desc.lights.push(LightDesc::Distant {
        name: "sun".into(),
        direction: [0.0, -1.0, -0.2],
        irradiance: 1.0,
        color: [1.0; 3],
        angle: 0.01,
    });
    desc.environment = Some(EnvironmentDesc {
        color: [0.1; 3],
        strength: 1.0,
        texture: None,
        transform: IDENTITY,
    });
    desc
}

type Mutation = fn(&mut SceneDesc, f32);

/// Expected: NaN, +Inf and -Inf in each field are rejected with `InvalidScene` whose pointer
/// names exactly that field. Tolerance: exact pointer.
#[test]
fn non_finite_ir_fields_are_rejected_with_their_pointer() {
    let base = every_field_scene();
    photonmap::scene::validate(&base).expect("the base scene is valid");
    let table: &[(&str, Mutation)] = &[
        ("/meshes/0/positions/1/2", |d, v| {
            d.meshes[0].positions[1][2] = v
        }),
        ("/meshes/5/normals/2/0", |d, v| {
            d.meshes[5].normals.as_mut().unwrap()[2][0] = v
        }),
        ("/meshes/5/uvs/1/1", |d, v| {
            d.meshes[5].uvs.as_mut().unwrap()[1][1] = v
        }),
        ("/meshes/2/transform/1/3", |d, v| {
            d.meshes[2].transform[1][3] = v
        }),
        ("/meshes/2/transform/0/0", |d, v| {
            d.meshes[2].transform[0][0] = v
        }),
        ("/instances/0/transform/2/1", |d, v| {
            d.instances[0].transform[2][1] = v
        }),
        ("/materials/0/color/1", |d, v| {
            d.materials[0] = MaterialDesc::Diffuse {
                name: "white".into(),
                color: ColorInput::Value([0.5, v, 0.5]),
            }
        }),
        ("/materials/3/color/scale/2", |d, v| {
            d.materials[3] = MaterialDesc::Diffuse {
                name: "textured".into(),
                color: ColorInput::Texture {
                    texture: 0,
                    scale: [1.0, 1.0, v],
                },
            }
        }),
        ("/materials/4/ior", |d, v| {
            if let MaterialDesc::Dielectric { ior, .. } = &mut d.materials[4] {
                *ior = v
            }
        }),
        ("/materials/4/roughness", |d, v| {
            if let MaterialDesc::Dielectric { roughness, .. } = &mut d.materials[4] {
                *roughness = v
            }
        }),
        ("/textures/0/data/4", |d, v| d.textures[0].data[4] = v),
        ("/lights/0/power", |d, v| {
            if let LightDesc::Rect { power, .. } = &mut d.lights[0] {
                *power = v
            }
        }),
        ("/lights/0/height", |d, v| {
            if let LightDesc::Rect { height, .. } = &mut d.lights[0] {
                *height = v
            }
        }),
        ("/lights/0/transform/0/3", |d, v| {
            if let LightDesc::Rect { transform, .. } = &mut d.lights[0] {
                transform[0][3] = v
            }
        }),
        ("/lights/0/color/0", |d, v| {
            if let LightDesc::Rect { color, .. } = &mut d.lights[0] {
                color[0] = v
            }
        }),
        ("/lights/1/position/1", |d, v| {
            if let LightDesc::Spot { position, .. } = &mut d.lights[1] {
                position[1] = v
            }
        }),
        ("/lights/1/direction/2", |d, v| {
            if let LightDesc::Spot { direction, .. } = &mut d.lights[1] {
                direction[2] = v
            }
        }),
        ("/lights/1/cone_angle", |d, v| {
            if let LightDesc::Spot { cone_angle, .. } = &mut d.lights[1] {
                *cone_angle = v
            }
        }),
        ("/lights/2/irradiance", |d, v| {
            if let LightDesc::Distant { irradiance, .. } = &mut d.lights[2] {
                *irradiance = v
            }
        }),
        ("/lights/2/angle", |d, v| {
            if let LightDesc::Distant { angle, .. } = &mut d.lights[2] {
                *angle = v
            }
        }),
        ("/camera/transform/2/3", |d, v| d.camera.transform[2][3] = v),
        ("/camera/fov", |d, v| d.camera.fov = Some(v)),
        ("/camera/focal_length", |d, v| d.camera.focal_length = v),
        ("/camera/shift/1", |d, v| d.camera.shift[1] = v),
        ("/camera/near", |d, v| d.camera.near = v),
        ("/camera/focus_distance", |d, v| {
            d.camera.focus_distance = Some(v)
        }),
        ("/media/0/sigma_a/0", |d, v| d.media[0].sigma_a[0] = v),
        ("/media/0/sigma_s/2", |d, v| d.media[0].sigma_s[2] = v),
        ("/media/0/g", |d, v| d.media[0].g = v),
        ("/environment/strength", |d, v| {
            d.environment.as_mut().unwrap().strength = v
        }),
        ("/environment/color/1", |d, v| {
            d.environment.as_mut().unwrap().color[1] = v
        }),
        ("/environment/transform/1/1", |d, v| {
            d.environment.as_mut().unwrap().transform[1][1] = v
        }),
    ];
    let mut failures = Vec::new();
    for (pointer, mutate) in table {
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let mut d = base.clone();
            mutate(&mut d, bad);
            match photonmap::scene::validate(&d) {
                Err(Error::InvalidScene { pointer: p, .. }) if p == *pointer => {}
                other => failures.push(format!("{pointer} = {bad}: {other:?}")),
            }
            // Scene::build validates too, so nothing non-finite reaches the renderer.
            assert!(Scene::build(&d).is_err(), "{pointer} = {bad} builds");
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
    // The far plane is the one field where +Inf is meaningful (no far clipping); NaN is not.
    let mut d = base.clone();
    d.camera.far = f32::NAN;
    assert!(matches!(
        photonmap::scene::validate(&d),
        Err(Error::InvalidScene { pointer, .. }) if pointer == "/camera/far"
    ));
}

// ---------------------------------------------------------------------------------------
// Determinism

/// Expected: every term bit-identical for 1 and 2 threads and for two runs with the same
/// seed, on a scene with glass, fog and the irradiance cache (draft preset, 32x32).
/// Tolerance: exact bits.
#[test]
fn glass_fog_and_irradiance_cache_are_deterministic() {
    let mut desc = load_scene("fog_glass");
    desc.film.width = 32;
    desc.film.height = 32;
    let settings = |threads| RenderSettings {
        seed: 31,
        threads,
        ..RenderSettings::preset(Quality::Draft)
    };
    let a = run(&desc, settings(1));
    let b = run(&desc, settings(2));
    let c = run(&desc, settings(2));
    firewall("fog_glass 1 thread", &a, 0);
    assert!(a.stats.irradiance_cache_records > 0, "the cache is used");
    assert!(mean(&a, Term::Volume) > 0.0 && mean(&a, Term::Caustic) > 0.0);
    for (label, other) in [("2 threads", &b), ("repeat", &c)] {
        for t in Term::ALL {
            let (x, y) = (&a.film.term(t).data, &other.film.term(t).data);
            assert!(
                x.iter()
                    .zip(y)
                    .all(|(p, q)| p.map(f32::to_bits) == q.map(f32::to_bits)),
                "{label}: {} differs",
                t.name()
            );
        }
        assert_eq!(
            a.stats.irradiance_cache_records,
            other.stats.irradiance_cache_records
        );
        assert_eq!(a.stats.photons_stored, other.stats.photons_stored);
    }
}

// ---------------------------------------------------------------------------------------
// Memory budget

/// Expected: 10^8 photons in the global map need 20 B x 10^8 = 2e9 B, over a 1 GiB limit: the
/// render fails before the photon pass with `InvalidSetting` naming `--memory-limit` and the
/// estimate. Tolerance: exact bytes; "fast" = before any phase of the render starts (no
/// progress is reported; the photon pass would take minutes).
#[test]
fn memory_limit_fails_fast_with_the_estimate() {
    let desc = small(load_scene("cornell_diffuse"));
    let scene = Scene::build(&desc).unwrap();
    let mut s = small_settings(37);
    s.photons = 100_000_000;
    s.memory_limit = Some(Bytes(1 << 30));
    let phases: Arc<Mutex<Vec<String>>> = Arc::default();
    let sink = phases.clone();
    let r =
        Renderer::new(&scene)
            .settings(s.clone())
            .progress(Arc::new(move |_f: f32, p: &str| {
                sink.lock().unwrap().push(p.to_string())
            }));
    let est = r.memory_estimate();
    // No specular surfaces and no media: only the global map is built.
    assert_eq!(est.photons, 100_000_000);
    assert_eq!(est.photon_bytes, 20 * 100_000_000);
    assert_eq!(BYTES_PER_PHOTON, 20);
    assert_eq!(est.triangles, scene.triangle_count as u64);
    assert_eq!(
        est.bvh_bytes,
        BYTES_PER_TRIANGLE * scene.triangle_count as u64
    );
    // Precomputed irradiance at every fourth photon of the global map, 20 B each.
    assert_eq!(est.irradiance_bytes, 20 * 25_000_000);
    assert_eq!(
        est.total_bytes,
        est.photon_bytes + est.bvh_bytes + est.irradiance_bytes
    );
    // Photons are traced as their records and the kd-tree is balanced in place, so the peak
    // is the maps and the BVH (BENCHMARKS.md, 10^8 photons).
    assert_eq!(est.peak_bytes, est.total_bytes);
    let e = r.render().err().expect("over the limit");
    let msg = e.to_string();
    eprintln!("{msg}");
    assert!(
        phases.lock().unwrap().is_empty(),
        "{:?}",
        phases.lock().unwrap()
    );
    assert!(
        matches!(&e, Error::InvalidSetting { setting, .. } if setting == "memory_limit"),
        "{e:?}"
    );
    assert!(msg.contains(&est.peak_bytes.to_string()) && msg.contains("2000000000"));

    // Maps that will not be built are not counted: no caustic map without specular
    // surfaces, no volume map without media, no global map without indirect light.
    s.caustic_photons = 100_000_000;
    s.volume_photons = 100_000_000;
    s.final_gather_rays = 0;
    let est = Renderer::new(&scene).settings(s).memory_estimate();
    assert_eq!(est.photons, 0);

    // Every map that will be built is counted: glass and fog build all three.
    let fog = Scene::build(&small(load_scene("fog_glass"))).unwrap();
    let mut s = small_settings(37);
    (s.photons, s.caustic_photons, s.volume_photons) = (1000, 300, 200);
    let est = Renderer::new(&fog).settings(s.clone()).memory_estimate();
    assert_eq!(est.photon_bytes, 20 * 1500);
    // Within the limit the render runs, and the stats report the figures.
    assert_eq!(est.peak_bytes, est.total_bytes);
    s.memory_limit = Some(Bytes(est.peak_bytes));
    let out = run(&small(load_scene("fog_glass")), s);
    let json = serde_json::to_value(&out.stats).unwrap();
    assert_eq!(json["bytes_per_photon"], 20);
    assert_eq!(json["bytes_per_triangle"], BYTES_PER_TRIANGLE);
    assert_eq!(json["memory_estimate"]["total_bytes"], est.total_bytes);
    // The maps built hold at most the estimate (the last batch may overshoot the target by
    // less than one batch; the estimate is of the targets).
    eprintln!(
        "estimate {} B; built maps {:?}",
        est.photon_bytes,
        out.stats
            .photon_maps
            .iter()
            .map(|m| (m.map, m.stored, m.memory_bytes))
            .collect::<Vec<_>>()
    );
}

/// Expected: `--memory-limit` accepts plain bytes and binary suffixes (512M = 512 x 2^20,
/// 8G = 8 x 2^30), rejects other text, and defaults to MemAvailable where /proc/meminfo exists;
/// the command fails up front on a render over the limit.
#[test]
fn memory_limit_flag_parses_sizes() {
    let parse = |v: &str| {
        use clap::Parser;
        Cli::try_parse_from(["photonmap", "render", "-o", "x.exr", "--memory-limit", v]).map(|c| {
            match c.command {
                Command::Render(a) => a,
                Command::Merge(_) => unreachable!("`render` parses as the render command"),
            }
        })
    };
    assert_eq!(
        parse("8G").unwrap().options.memory_limit.map(|b| b.0),
        Some(8 << 30)
    );
    assert_eq!(
        parse("512M").unwrap().settings().memory_limit_bytes(),
        Some(512 << 20)
    );
    assert_eq!(
        parse("1000").unwrap().options.memory_limit.map(|b| b.0),
        Some(1000)
    );
    assert_eq!(
        parse("2GiB").unwrap().options.memory_limit.map(|b| b.0),
        Some(2 << 30)
    );
    assert_eq!(
        parse("64kb").unwrap().options.memory_limit.map(|b| b.0),
        Some(64 << 10)
    );
    for bad in ["", "G", "8X", "1.5G", "-1", "99999999999T"] {
        assert!(parse(bad).is_err(), "`{bad}` accepted");
    }
    let default = photonmap::cli::RenderArgs::defaults()
        .settings()
        .memory_limit_bytes();
    if std::path::Path::new("/proc/meminfo").exists() {
        assert!(default.is_some_and(|b| b > 0), "{default:?}");
    }
    eprintln!("default memory limit: {default:?}");

    let scene = data("scenes/cornell_diffuse.json");
    let out = std::env::temp_dir().join("photonmap_extremes_never_written.exr");
    let mut a = parse("1G").unwrap();
    a.scene = Some(scene);
    a.output = out.clone();
    a.options.photons = 100_000_000;
    a.quiet = true;
    let e = photonmap::command::run_render(&a, photonmap::command::Frontend::default())
        .expect_err("over the limit");
    assert!(e.to_string().contains("--memory-limit"), "{e}");
    assert!(!out.exists());
}
