//! The beauty's alpha: Film > Transparent and the Holdout closure, as Cycles resolves them.
//! A camera ray that reaches the background straight through transparent surfaces (no
//! reflection or refraction on the way) adds its throughput to the sample's transparency,
//! and so does a Holdout it reaches that way, by its weight; the alpha is one minus the mean.
//! With Film > Transparent such a ray draws no background, but the world still lights the
//! scene and is still seen in mirrors.
//!
//! A sphere of radius 1 seen from 4 units away in a white furnace: pixels well inside its
//! image and well outside it, with a box filter, see only the sphere or only the background.

use crate::common;
use glam::Vec3;
use photonmap::geometry::shapes;
use photonmap::render::aov::Term;
use photonmap::render::settings::{FilterName, RenderMode};
use photonmap::render::{RenderOutput, RenderSettings};
use photonmap::scene::SceneDesc;

const SIZE: usize = 32;
const SPP: u32 = 64;
/// The camera's field of view: the sphere's image is about half the frame across.
const FOV: f32 = 0.9;

fn scene(material: serde_json::Value, transparent: bool) -> SceneDesc {
    let s = shapes::sphere(Vec3::ZERO, 1.0, 64, 128);
    let desc = serde_json::json!({
        "camera": {"transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4.0], [0, 0, 0, 1]],
                   "fov": FOV},
        "film": {"width": SIZE, "height": SIZE, "transparent": transparent},
        "environment": {"color": [1, 1, 1], "strength": 1.0},
        "materials": [material],
        "meshes": [{
            "name": "sphere", "material": 0,
            "positions": s.positions.iter().map(|p| p.to_array()).collect::<Vec<_>>(),
            "indices": s.indices,
            "normals": s.normals.as_ref().map(|n| n.iter().map(|v| v.to_array()).collect::<Vec<_>>()),
        }],
    });
    serde_json::from_value(desc).expect("a valid scene")
}

fn diffuse() -> serde_json::Value {
    serde_json::json!({"type": "diffuse", "name": "white", "color": [0.8, 0.8, 0.8]})
}

fn graph(nodes: serde_json::Value) -> serde_json::Value {
    serde_json::json!({"type": "graph", "name": "g", "nodes": nodes, "surface": {"node": 0}})
}

fn render(desc: &SceneDesc, mode: RenderMode) -> RenderOutput {
    common::render_settings(
        desc,
        RenderSettings {
            mode,
            spp: SPP,
            seed: 5,
            filter: FilterName::Box,
            photons: 2000,
            caustic_photons: 0,
            volume_photons: 0,
            ..Default::default()
        },
    )
}

/// Pixels wholly inside the sphere's image (distance from the centre below 0.85 of its
/// radius) and wholly outside it (above 1.15).
fn regions() -> (Vec<usize>, Vec<usize>) {
    let radius = (0.25f32.asin().tan() / (FOV / 2.0).tan()) * SIZE as f32 / 2.0;
    let c = SIZE as f32 / 2.0;
    let d = |i: usize| {
        let (x, y) = ((i % SIZE) as f32 + 0.5, (i / SIZE) as f32 + 0.5);
        ((x - c).powi(2) + (y - c).powi(2)).sqrt() / radius
    };
    let inside = (0..SIZE * SIZE).filter(|&i| d(i) < 0.85).collect();
    let outside = (0..SIZE * SIZE).filter(|&i| d(i) > 1.15).collect();
    (inside, outside)
}

/// Film > Transparent in every mode: the background pixels are transparent and black, the
/// sphere's opaque; and every term but `emission` is the same bits as without it (the world
/// still lights the sphere).
#[test]
fn film_transparent_drops_the_background_and_keeps_its_light() {
    let (inside, outside) = regions();
    assert!(inside.len() > 150 && outside.len() > 600);
    for mode in [RenderMode::Jensen, RenderMode::Sppm, RenderMode::Pppm] {
        let opaque = render(&scene(diffuse(), false), mode);
        let clear = render(&scene(diffuse(), true), mode);
        let (a, b) = (&opaque.film, &clear.film);
        assert!(a.alpha.iter().all(|&v| v == 1.0), "{mode:?}");
        for &i in &outside {
            assert_eq!(b.alpha[i], 0.0, "{mode:?} pixel {i}");
            assert_eq!(b.term(Term::Emission).data[i], [0.0; 3], "{mode:?}");
            assert_eq!(a.term(Term::Emission).data[i], [1.0; 3], "{mode:?}");
        }
        for &i in &inside {
            assert_eq!(b.alpha[i], 1.0, "{mode:?} pixel {i}");
            assert!(b.term(Term::Direct).data[i][0] > 0.3, "{mode:?}");
        }
        for t in Term::ALL.into_iter().filter(|&t| t != Term::Emission) {
            assert!(a.term(t).data == b.term(t).data, "{mode:?} {}", t.name());
        }
    }
}

/// A Mix Shader of a Diffuse and a Holdout at factor 0.3: the sphere's pixels have alpha
/// 0.7, whether or not the film is transparent; the background keeps alpha 1 on an opaque
/// film.
#[test]
fn holdout_makes_its_weight_transparent() {
    let (inside, outside) = regions();
    let m = graph(serde_json::json!([
        {"type": "mix_shader", "inputs": {"fac": 0.3, "shader1": {"node": 1, "output": "bsdf"},
                                          "shader2": {"node": 2, "output": "holdout"}}},
        {"type": "diffuse", "inputs": {"color": [0.8, 0.8, 0.8]}},
        {"type": "holdout"},
    ]));
    for transparent in [false, true] {
        let out = render(&scene(m.clone(), transparent), RenderMode::Jensen);
        assert!(out.stats.warnings.iter().all(|w| !w.contains("Holdout")));
        for &i in &inside {
            assert!(
                (out.film.alpha[i] - 0.7).abs() < 1e-5,
                "{} at {i}",
                out.film.alpha[i]
            );
        }
        for &i in &outside {
            let want = if transparent { 0.0 } else { 1.0 };
            assert_eq!(out.film.alpha[i], want);
        }
    }
    // A full Holdout ends the path: black and transparent.
    let full = graph(serde_json::json!([{"type": "holdout"}]));
    let out = render(&scene(full, false), RenderMode::Jensen);
    for &i in &inside {
        assert_eq!(out.film.alpha[i], 0.0);
        assert_eq!(out.film.combined().data[i], [0.0; 3]);
    }
}

/// A sphere of Principled Alpha `a` on a transparent film: a camera ray crosses its front and
/// its back, so the sphere's pixels have alpha 1 - (1 - a)^2 in expectation. The tolerance
/// is four standard errors of the mean over the pixels (each sample is transparent or not);
/// it is asserted to be tighter than the change an Alpha 0.02 off would make.
#[test]
fn partial_alpha_is_seen_through_twice() {
    let (inside, _) = regions();
    let a = 0.4f64;
    let expect = |a: f64| 1.0 - (1.0 - a).powi(2);
    let m = graph(serde_json::json!([
        {"type": "principled", "inputs": {"alpha": a}},
    ]));
    let out = render(&scene(m, true), RenderMode::Jensen);
    let n = inside.len() as f64;
    let mean = inside
        .iter()
        .map(|&i| out.film.alpha[i] as f64)
        .sum::<f64>()
        / n;
    let p = expect(a);
    let tol = 4.0 * (p * (1.0 - p) / (n * SPP as f64)).sqrt();
    for off in [-0.02, 0.02] {
        assert!(
            (expect(a + off) - p).abs() > tol,
            "tolerance {tol} too loose"
        );
    }
    assert!((mean - p).abs() < tol, "alpha {mean}, expected {p} ± {tol}");
}

/// The background seen in a mirror is drawn and opaque on a transparent film (only rays
/// that reach it straight are transparent, as in Cycles).
#[test]
fn mirrors_show_the_background_on_a_transparent_film() {
    let (inside, _) = regions();
    let mirror = graph(serde_json::json!([
        {"type": "glossy", "inputs": {"color": [1, 1, 1], "roughness": 0.0}},
    ]));
    let out = render(&scene(mirror, true), RenderMode::Jensen);
    let img = out.film.combined();
    for &i in &inside {
        assert_eq!(out.film.alpha[i], 1.0);
        assert!(img.data[i][0] > 0.9, "{:?}", img.data[i]);
    }
}

/// A holdout object (Blender's Object > Visibility > Holdout): black and transparent where it
/// is opaque; with Principled Alpha `a` on an opaque film, a camera ray is held out at the
/// front by `a`, and behind it at the back by `a` again, so alpha is (1 - a)^2 in
/// expectation (the background shows through the rest).
#[test]
fn holdout_objects_are_holes_where_they_are_opaque() {
    let (inside, outside) = regions();
    let mut desc = scene(diffuse(), false);
    desc.meshes[0].holdout = true;
    let out = render(&desc, RenderMode::Jensen);
    let img = out.film.combined();
    for &i in &inside {
        assert_eq!(out.film.alpha[i], 0.0);
        assert_eq!(img.data[i], [0.0; 3]);
    }
    for &i in &outside {
        assert_eq!(out.film.alpha[i], 1.0);
    }
    let a = 0.4f64;
    let mut desc = scene(
        graph(serde_json::json!([{"type": "principled", "inputs": {"alpha": a}}])),
        false,
    );
    desc.meshes[0].holdout = true;
    let out = render(&desc, RenderMode::Jensen);
    let n = inside.len() as f64;
    let mean = inside
        .iter()
        .map(|&i| out.film.alpha[i] as f64)
        .sum::<f64>()
        / n;
    let p = (1.0 - a).powi(2);
    let tol = 4.0 * (p * (1.0 - p) / (n * SPP as f64)).sqrt();
    for off in [-0.02, 0.02] {
        assert!(
            ((1.0 - a - off).powi(2) - p).abs() > tol,
            "tolerance {tol} too loose"
        );
    }
    assert!((mean - p).abs() < tol, "alpha {mean}, expected {p} ± {tol}");
}
