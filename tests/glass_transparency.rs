//! Glass mixed with transparency (a Mix Shader of Glass and Transparent BSDFs, or a glass whose
//! alpha is below one): a camera path may enter the glass by refraction and leave it straight
//! through, or the other way round. Both are lossless, so a sphere of such a material in a
//! white furnace (uniform environment of radiance 1, nothing else) is invisible: every pixel
//! is 1, at the centre of the sphere and at its rim alike.
//!
//! This holds only when refraction is weighted as Cycles weights it, by the Fresnel
//! transmittance without the 1/eta^2 of physical radiance (`materials::bsdf`): with that
//! factor a path that enters by refraction and leaves by transparency keeps it, and the
//! sphere's centre came out 14% bright and its rim 8% dark at a Mix factor of 0.5.

use crate::common;
use common::*;
use glam::Vec3;
use photonmap::geometry::shapes;
use photonmap::render::settings::FilterName;
use photonmap::render::{RenderOutput, RenderSettings};
use photonmap::scene::SceneDesc;

const SIZE: usize = 32;

fn furnace_scene(fac: f32, roughness: f32) -> SceneDesc {
    let s = shapes::sphere(Vec3::ZERO, 1.0, 64, 128);
    let desc = serde_json::json!({
        "camera": {"transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4.0], [0, 0, 0, 1]],
                   "fov": 0.55},
        "film": {"width": SIZE, "height": SIZE},
        "environment": {"color": [1, 1, 1], "strength": 1.0},
        "materials": [{
            "type": "graph", "name": "GlassyGhost",
            "nodes": [
                {"type": "mix_shader", "name": "Mix Shader",
                 "inputs": {"fac": fac, "shader1": {"node": 1, "output": "bsdf"},
                            "shader2": {"node": 2, "output": "bsdf"}}},
                {"type": "glass", "name": "Glass BSDF", "params": {"multiscatter": true},
                 "inputs": {"color": [1, 1, 1], "roughness": roughness, "ior": 1.45}},
                {"type": "transparent", "name": "Transparent BSDF",
                 "inputs": {"color": [1, 1, 1]}},
            ],
            "surface": {"node": 0},
        }],
        "meshes": [{
            "name": "sphere", "material": 0,
            "positions": s.positions.iter().map(|p| p.to_array()).collect::<Vec<_>>(),
            "indices": s.indices,
            "normals": s.normals.as_ref().map(|n| n.iter().map(|v| v.to_array()).collect::<Vec<_>>()),
        }],
    });
    serde_json::from_value(desc).expect("a valid scene")
}

fn settings(seed: u64) -> RenderSettings {
    RenderSettings {
        spp: 64,
        seed,
        filter: FilterName::Box,
        photons: 0,
        caustic_photons: 0,
        volume_photons: 0,
        ..Default::default()
    }
}

/// Mean and standard error (over pixels) of the red channel on the ring of pixels whose
/// distance from the image centre, over the sphere's image radius, is in [r0, r1).
fn ring(out: &RenderOutput, r0: f32, r1: f32) -> (f64, f64) {
    let img = out.film.combined();
    // The sphere (radius 1 at distance 4) spans tan(asin(1/4)) / tan(fov / 2) of the half-width.
    let radius = (0.25f32.asin().tan() / (0.55f32 / 2.0).tan()) * SIZE as f32 / 2.0;
    let c = SIZE as f32 / 2.0;
    let v: Vec<f64> = (0..SIZE * SIZE)
        .filter_map(|i| {
            let (x, y) = ((i % SIZE) as f32 + 0.5, (i / SIZE) as f32 + 0.5);
            let d = ((x - c).powi(2) + (y - c).powi(2)).sqrt() / radius;
            (d >= r0 && d < r1).then(|| img.data[i][0] as f64)
        })
        .collect();
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

#[test]
fn glass_mixed_with_transparency_is_invisible_in_a_white_furnace() {
    for roughness in [0.0f32, 0.3] {
        for fac in [0.25f32, 0.5, 0.75] {
            let desc = furnace_scene(fac, roughness);
            let out = render_settings(&desc, settings(1));
            for (r0, r1) in [(0.0f32, 0.5f32), (0.5, 0.8), (0.8, 0.97)] {
                let (m, se) = ring(&out, r0, r1);
                eprintln!("roughness {roughness}, fac {fac}, ring {r0}-{r1}: {m:.4} +- {se:.4}");
                // 4.5 standard errors plus 0.5% (the tessellated sphere's normals).
                assert!(
                    (m - 1.0).abs() <= 4.5 * se + 0.005,
                    "roughness {roughness}, Mix fac {fac}, ring {r0}-{r1} of the sphere's \
                     radius: {m:.4} +- {se:.4} against 1"
                );
            }
        }
    }
}
