//! The compositing AOVs beside the terms: the denoising guides (`albedo`, `normal`) through
//! mirrors and glass, and Cryptomatte mattes against each object's coverage.

use crate::common;
use common::*;
use photonmap::render::aov::{AovRequest, Cryptomatte};
use photonmap::render::film::Film;
use photonmap::render::RenderSettings;
use photonmap::scene::SceneDesc;

fn desc(v: serde_json::Value) -> SceneDesc {
    serde_json::from_value(v).expect("test scene parses")
}

/// A quad of material `m` spanning [-s, s]^2 in the plane z = `z`, facing +z when `up`.
fn quad_z(name: &str, z: f32, s: f32, m: u32, up: bool) -> serde_json::Value {
    let idx = if up {
        serde_json::json!([[0, 1, 2], [0, 2, 3]])
    } else {
        serde_json::json!([[0, 2, 1], [0, 3, 2]])
    };
    serde_json::json!({
        "name": name, "material": m,
        "positions": [[-s, -s, z], [s, -s, z], [s, s, z], [-s, s, z]],
        "indices": idx,
    })
}

fn settings(spp: u32, aovs: AovRequest) -> RenderSettings {
    let mut s = RenderSettings {
        spp,
        seed: 3,
        threads: 2,
        adaptive_sampling: false,
        denoising_data: aovs.denoising_data,
        denoise: aovs.denoise,
        cryptomatte: aovs.cryptomatte,
        cryptomatte_levels: aovs.cryptomatte_levels,
        ..RenderSettings::default()
    };
    s.photons = 2000;
    s.caustic_photons = 2000;
    s.final_gather_rays = 16;
    s
}

fn guides() -> AovRequest {
    AovRequest {
        denoising_data: true,
        ..AovRequest::default()
    }
}

/// Mean of the (R, G, B) or (X, Y, Z) of an AOV over the pixels of the centre square of
/// half-width `r` pixels.
fn centre_mean(film: &Film, name: &str, r: usize) -> [f32; 3] {
    let a = film.aov(name).unwrap_or_else(|| panic!("no {name}"));
    let n = a.spec.channels().len();
    let (cx, cy) = (film.width / 2, film.height / 2);
    let mut s = [0.0f64; 3];
    let mut k = 0.0;
    for y in cy - r..cy + r {
        for x in cx - r..cx + r {
            let i = (y * film.width + x) * n;
            for c in 0..3 {
                s[c] += a.data[i + c] as f64;
            }
            k += 1.0;
        }
    }
    s.map(|v| (v / k) as f32)
}

fn close(a: [f32; 3], b: [f32; 3], tol: f32) -> bool {
    a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= tol)
}

/// The camera at the origin looks down -z at a mirror at z = -2; behind the camera, at
/// z = 2, a red wall faces the mirror. A point light between them lights the wall.
fn mirror_scene(mirror: bool) -> SceneDesc {
    let front = if mirror {
        serde_json::json!({"type": "mirror", "name": "mirror", "color": [0.9, 0.9, 0.9]})
    } else {
        serde_json::json!({"type": "diffuse", "name": "grey", "color": [0.5, 0.5, 0.5]})
    };
    desc(serde_json::json!({
        "camera": {"fov": 0.5},
        "film": {"width": 24, "height": 24},
        "materials": [front,
                      {"type": "diffuse", "name": "red", "color": [0.8, 0.1, 0.1]}],
        "meshes": [quad_z("front", -2.0, 3.0, 0, true), quad_z("wall", 2.0, 5.0, 1, false)],
        "lights": [{"type": "point", "name": "bulb", "position": [0.0, 1.5, 0.5],
                    "power": 200.0}],
    }))
}

/// Seen through a perfect mirror, the guides are those of the surface it shows: its albedo
/// times the mirror's tint, and its normal (facing the mirror, away from the camera: +z in
/// camera space). Seen directly, a surface gives its own albedo and a normal facing the
/// camera (-z).
#[test]
fn guides_see_through_a_mirror() {
    let out = render_settings(&mirror_scene(true), settings(4, guides()));
    let albedo = centre_mean(&out.film, "albedo", 4);
    let normal = centre_mean(&out.film, "normal", 4);
    assert!(
        close(albedo, [0.72, 0.09, 0.09], 1e-3),
        "albedo through the mirror {albedo:?}"
    );
    assert!(
        close(normal, [0.0, 0.0, 1.0], 1e-3),
        "normal through the mirror {normal:?}"
    );
    let direct = render_settings(&mirror_scene(false), settings(4, guides()));
    let albedo = centre_mean(&direct.film, "albedo", 4);
    let normal = centre_mean(&direct.film, "normal", 4);
    assert!(close(albedo, [0.5, 0.5, 0.5], 1e-3), "{albedo:?}");
    assert!(close(normal, [0.0, 0.0, -1.0], 1e-3), "{normal:?}");
    // Without the request, there are no guides.
    let none = render_settings(&mirror_scene(true), settings(1, AovRequest::default()));
    assert!(none.film.aov("albedo").is_none() && none.film.aovs.is_empty());
}

/// A pane of smooth glass (a slab 0.1 thick) in front of a green wall, lit from the
/// camera's side: through the glass the guides are the wall's (each sample refracts into
/// the wall or reflects back into the black world, which adds zero: about (1 - F)² of the
/// wall's albedo), not the glass's (albedo 1).
#[test]
fn guides_see_through_glass() {
    let d = desc(serde_json::json!({
        "camera": {"fov": 0.4},
        "film": {"width": 24, "height": 24},
        "materials": [{"type": "dielectric", "name": "glass", "ior": 1.5},
                      {"type": "diffuse", "name": "green", "color": [0.1, 0.6, 0.2]}],
        "meshes": [quad_z("pane_front", -1.5, 2.0, 0, true),
                   quad_z("pane_back", -1.6, 2.0, 0, false),
                   quad_z("wall", -3.0, 6.0, 1, true)],
        "lights": [{"type": "point", "name": "bulb", "position": [0.0, 0.5, 0.0],
                    "power": 100.0}],
    }));
    let out = render_settings(&d, settings(64, guides()));
    let albedo = centre_mean(&out.film, "albedo", 4);
    let normal = centre_mean(&out.film, "normal", 4);
    // Two interfaces at normal incidence transmit (1 - 0.04)² = 0.92.
    let t = 0.92;
    assert!(
        close(albedo, [0.1 * t, 0.6 * t, 0.2 * t], 0.04),
        "albedo through glass {albedo:?}"
    );
    assert!(
        normal[2] < -0.85 && normal[0].abs() < 0.05,
        "normal through glass {normal:?}"
    );
}

/// Same seed, 1 or 2 threads: the AOVs are bit-identical too.
#[test]
fn guides_are_deterministic_for_any_thread_count() {
    let d = mirror_scene(true);
    let mut s1 = settings(2, guides());
    s1.threads = 1;
    let a = render_settings(&d, s1);
    let b = render_settings(&d, settings(2, guides()));
    assert_eq!(a.film.aovs, b.film.aovs);
}

/// A matte extracted as Cryptomatte decoders do (Nuke's gizmo, Blender's node): the sum of
/// the coverages of the ranks whose id is the name's.
fn matte(film: &Film, type_name: &str, name: &str) -> Vec<f32> {
    let id = photonmap::render::cryptomatte::name_id(name);
    let mut out = vec![0.0f32; film.width * film.height];
    for layer in film
        .aovs
        .iter()
        .filter(|a| a.spec.name.starts_with(type_name))
    {
        for (i, px) in layer.data.chunks_exact(4).enumerate() {
            for pair in px.chunks_exact(2) {
                if pair[0] == id {
                    out[i] += pair[1];
                }
            }
        }
    }
    out
}

/// The camera looks down -z at two quads parallel to the film: a "card" at z = -2 whose
/// edges fall at fractions of pixels, in front of a "backdrop"; with the box filter a
/// pixel's coverage by the card is the share of its area the card covers.
fn card_scene() -> (SceneDesc, impl Fn(usize, usize) -> f32) {
    // fov 0.5 rad over 32 px at depth 2: a pixel is 2 tan(0.25) * 2 / 32 wide.
    let (w, depth) = (32usize, 2.0f32);
    let px = 2.0 * (0.25f32).tan() * depth / w as f32;
    // Card edges in pixels from the left/top: x in [7.3, 20.6], y in [10.25, 25.8].
    let (x0, x1, y0, y1) = (7.3f32, 20.6f32, 10.25f32, 25.8f32);
    let to_world = |x: f32, y: f32| [(x - 16.0) * px, (16.0 - y) * px, -depth];
    let c = [
        to_world(x0, y1),
        to_world(x1, y1),
        to_world(x1, y0),
        to_world(x0, y0),
    ];
    let d = desc(serde_json::json!({
        "camera": {"fov": 0.5},
        "film": {"width": w, "height": w},
        "materials": [{"type": "diffuse", "name": "paper", "color": [0.7, 0.7, 0.7]},
                      {"type": "diffuse", "name": "felt", "color": [0.2, 0.3, 0.5]}],
        "meshes": [
            {"name": "card", "material": 0, "positions": c, "indices": [[0, 1, 2], [0, 2, 3]]},
            quad_z("backdrop", -4.0, 4.0, 1, true),
        ],
        "lights": [{"type": "point", "name": "bulb", "position": [0.0, 0.0, 0.0],
                    "power": 50.0}],
    }));
    let overlap = |a: f32, b: f32, lo: f32, hi: f32| (b.min(hi) - a.max(lo)).max(0.0);
    let coverage = move |x: usize, y: usize| {
        let (x, y) = (x as f32, y as f32);
        overlap(x, x + 1.0, x0, x1) * overlap(y, y + 1.0, y0, y1)
    };
    (d, coverage)
}

/// One object's matte, extracted from the Cryptomatte layers by its name's id, is the
/// object's coverage of each pixel; the material matte of its material too, and the mattes
/// of the card and the backdrop sum to 1 (every sample hits one of them).
#[test]
fn a_cryptomatte_matte_is_the_objects_coverage() {
    let (d, coverage) = card_scene();
    let mut s = settings(
        64,
        AovRequest {
            cryptomatte: Cryptomatte::Both,
            cryptomatte_levels: 6,
            ..AovRequest::default()
        },
    );
    s.filter = photonmap::render::settings::FilterName::Box;
    let out = render_settings(&d, s);
    let film = &out.film;
    assert_eq!(film.cryptomatte["CryptoObject"], vec!["backdrop", "card"]);
    assert_eq!(film.cryptomatte["CryptoMaterial"], vec!["felt", "paper"]);
    let card = matte(film, "CryptoObject", "card");
    let paper = matte(film, "CryptoMaterial", "paper");
    let backdrop = matte(film, "CryptoObject", "backdrop");
    let (mut worst, mut sum_abs, mut sum_signed, mut edge_pixels) = (0.0f32, 0.0f32, 0.0f32, 0);
    for y in 0..film.height {
        for x in 0..film.width {
            let i = y * film.width + x;
            let c = coverage(x, y);
            let e = (card[i] - c).abs();
            worst = worst.max(e);
            sum_abs += e;
            if c > 0.0 && c < 1.0 {
                edge_pixels += 1;
                sum_signed += card[i] - c;
                // A pixel the edge crosses has a fractional matte.
                assert!(card[i] > 0.0 && card[i] < 1.0, "({x}, {y}): {}", card[i]);
            } else {
                assert_eq!(card[i], c, "({x}, {y})");
            }
            assert_eq!(card[i], paper[i], "({x}, {y})");
            assert!((card[i] + backdrop[i] - 1.0).abs() < 1e-5, "({x}, {y})");
        }
    }
    assert!(edge_pixels > 40, "{edge_pixels}");
    // 64 stratified samples per pixel (4 replicates of a jittered 4x4 grid): within a
    // sixteenth, about 2% on average at the edges, and no bias.
    assert!(worst <= 1.0 / 16.0 + 1e-6, "worst pixel off by {worst}");
    let mean = sum_abs / edge_pixels as f32;
    let bias = sum_signed / edge_pixels as f32;
    assert!(mean < 0.025, "mean error at the edges {mean}");
    assert!(bias.abs() < 0.005, "mean signed error at the edges {bias}");
}

/// The matte of an object moved by a third of a pixel is told apart (the test above would
/// fail on a matte off by that much).
#[test]
fn a_matte_shifted_by_a_third_of_a_pixel_is_caught() {
    let (d, coverage) = card_scene();
    let mut s = settings(
        64,
        AovRequest {
            cryptomatte: Cryptomatte::Object,
            cryptomatte_levels: 2,
            ..AovRequest::default()
        },
    );
    s.filter = photonmap::render::settings::FilterName::Box;
    let out = render_settings(&d, s);
    let card = matte(&out.film, "CryptoObject", "card");
    let shifted = |x: usize, y: usize| {
        let c = |x: usize| coverage(x, y);
        // The coverage a third of a pixel further right, by linear interpolation.
        (2.0 * c(x) + if x > 0 { c(x - 1) } else { 0.0 }) / 3.0
    };
    let worst = (0..32 * 32)
        .map(|i| (card[i] - shifted(i % 32, i / 32)).abs())
        .fold(0.0f32, f32::max);
    assert!(worst > 0.2, "{worst}");
}
