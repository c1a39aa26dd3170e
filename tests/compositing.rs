//! The compositing AOVs beside the terms: the denoising guides (`albedo`, `normal`) through
//! mirrors and glass, and Cryptomatte mattes against each object's coverage.

mod common;
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
        noise_threshold: 0.0,
        aovs,
        ..RenderSettings::default()
    };
    s.photons.global = 2000;
    s.photons.caustic = 2000;
    s.photons.final_gather_rays = 16;
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
