//! The photon terms: white furnace for `indirect`, energy of the stored photons, and the full
//! global illumination against Mitsuba 3 references, converging as photons grow.

use crate::common;
use common::*;
use photonmap::geometry::shapes;
use photonmap::photon::map::MapKind;
use photonmap::photon::trace::{build_map, TraceParams};
use photonmap::render::aov::Term;
use photonmap::render::settings::FilterName;
use photonmap::render::RenderSettings;
use photonmap::scene::desc::*;
use photonmap::scene::{Scene, SceneDesc};

fn mesh_desc(m: &photonmap::geometry::MeshGeom, name: &str, material: u32) -> MeshDesc {
    MeshDesc {
        name: name.into(),
        positions: m.positions.iter().map(|p| p.to_array()).collect(),
        indices: m.indices.clone(),
        normals: m
            .normals
            .as_ref()
            .map(|n| n.iter().map(|v| v.to_array()).collect()),
        material,
        ..Default::default()
    }
}

fn render_with(
    desc: &SceneDesc,
    spp: u32,
    photons: RenderSettings,
    seed: u64,
) -> photonmap::render::RenderOutput {
    render_settings(
        desc,
        RenderSettings {
            spp,
            seed,
            filter: FilterName::Box,
            ..photons
        },
    )
}

/// Inside a diffuse sphere of albedo Kd lit by a point light at its centre, every bounce
/// multiplies the radiance by Kd, so indirect / direct = Kd / (1 - Kd) everywhere.
#[test]
fn white_furnace_indirect_matches_kd_over_one_minus_kd() {
    for kd in [0.5f32, 0.9] {
        let sphere = shapes::sphere(glam::Vec3::ZERO, 1.0, 96, 192);
        let desc = SceneDesc {
            camera: CameraDesc {
                fov: Some(1.2),
                ..Default::default()
            },
            film: FilmDesc {
                width: 24,
                height: 24,
                transparent: false,
            },
            materials: vec![MaterialDesc::Diffuse {
                name: "white".into(),
                color: ColorInput::Value([kd; 3]),
            }],
            meshes: vec![mesh_desc(&sphere, "sphere", 0)],
            lights: vec![LightDesc::Point {
                name: "centre".into(),
                position: [0.0; 3],
                power: 100.0,
                color: [1.0; 3],
                radius: 0.0,
                soft_falloff: false,
                camera_visible: true,
            }],
            ..Default::default()
        };
        let photons = RenderSettings {
            photons: 100_000,
            max_bounces: 100_000,
            final_gather_rays: 512,
            ..Default::default()
        };
        let out = render_with(&desc, 4, photons, 3);
        let ratio = out.film.term(Term::Indirect).mean() / out.film.term(Term::Direct).mean();
        let expected = kd / (1.0 - kd);
        eprintln!("Kd {kd}: indirect/direct {ratio:?}, expected {expected}");
        for c in 0..3 {
            assert!(
                (ratio[c] / expected - 1.0).abs() < 0.025,
                "Kd {kd}: ratio {} vs {expected}",
                ratio[c]
            );
        }
    }
}

/// In a closed white box every photon's first hit is stored, so their power sums to the
/// lights' Φ (up to RGBE rounding, unbiased to well under 1%).
#[test]
fn first_hit_power_equals_light_power() {
    let b = shapes::cuboid(glam::Vec3::splat(-1.0), glam::Vec3::splat(1.0));
    let rect = [
        [1.0, 0.0, 0.0, 0.1],
        [0.0, 0.0, 1.0, 0.8],
        [0.0, -1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    let desc = SceneDesc {
        camera: CameraDesc {
            fov: Some(1.0),
            ..Default::default()
        },
        film: FilmDesc {
            width: 8,
            height: 8,
            transparent: false,
        },
        materials: vec![MaterialDesc::Diffuse {
            name: "white".into(),
            color: ColorInput::Value([0.8; 3]),
        }],
        meshes: vec![mesh_desc(&b, "box", 0)],
        lights: vec![
            LightDesc::Rect {
                name: "panel".into(),
                transform: rect,
                width: 0.4,
                height: 0.3,
                power: 30.0,
                color: [1.0, 0.5, 0.25],
                two_sided: false,
                spread: std::f32::consts::PI,
                camera_visible: true,
            },
            LightDesc::Point {
                name: "bulb".into(),
                position: [0.3, -0.2, 0.1],
                power: 10.0,
                color: [1.0; 3],
                radius: 0.0,
                soft_falloff: false,
                camera_visible: true,
            },
            LightDesc::Sphere {
                name: "ball".into(),
                position: [-0.5, 0.0, 0.2],
                power: 5.0,
                color: [0.2, 1.0, 0.4],
                radius: 0.1,
                camera_visible: true,
            },
        ],
        ..Default::default()
    };
    let scene = Scene::build(&desc).unwrap();
    let params = TraceParams {
        kind: MapKind::Global,
        target: 200_000,
        max_emitted: 10_000_000,
        max_bounces: 64,
        seed: 1,
        targets: &[],
        cancel: None,
        f32_power: false,
        irradiance: None,
    };
    let map = build_map(&scene, &params).unwrap();
    let stored = map.first_hit_power();
    let expected = glam::Vec3::new(30.0 + 10.0 + 1.0, 15.0 + 10.0 + 5.0, 7.5 + 10.0 + 2.0);
    eprintln!(
        "first-hit power {stored:?}, lights {expected:?}, {} photons from {} paths",
        map.len(),
        map.emitted
    );
    for c in 0..3 {
        assert!(
            (stored[c] / expected[c] - 1.0).abs() < 0.01,
            "channel {c}: {} vs {}",
            stored[c],
            expected[c]
        );
    }
}

fn full_gi_errors(scene: &str, reference: &str, counts: &[usize]) -> Vec<(f64, f64)> {
    let desc = load_scene(scene);
    counts
        .iter()
        .map(|&n| common::compare::full_gi(&desc, reference, n, &[]))
        .collect()
}

/// Photon mapping is biased but consistent: the error of 8x8-pixel block means against the
/// path-traced reference (the worst 2 of 256 blocks left out) must fall as the maps grow from
/// 10^4 to 10^6 photons. The thresholds at 10^6 photons leave a 2x margin over the measured
/// figures (seed 11, printed by the test); a 2% brightness error alone would add 4e-4.
#[test]
fn diffuse_cornell_full_gi_converges_to_mitsuba() {
    let errs = full_gi_errors(
        "cornell_diffuse",
        "cornell_diffuse_full",
        &[10_000, 100_000, 1_000_000],
    );
    assert!(
        errs[1].1 < errs[0].1 && errs[2].1 < errs[1].1,
        "block error must fall as photons grow: {errs:?}"
    );
    assert!(
        errs[2].1 < common::compare::full_gi_limit("cornell_diffuse_full"),
        "{errs:?}"
    );
}

#[test]
fn spheres_cornell_full_gi_converges_to_mitsuba() {
    let errs = full_gi_errors(
        "cornell_spheres",
        "cornell_spheres_full",
        &[10_000, 100_000, 1_000_000],
    );
    assert!(
        errs[1].1 < errs[0].1 && errs[2].1 < errs[1].1,
        "block error must fall as photons grow: {errs:?}"
    );
    assert!(
        errs[2].1 < common::compare::full_gi_limit("cornell_spheres_full"),
        "{errs:?}"
    );
}
