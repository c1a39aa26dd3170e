//! The subsurface walk against Mitsuba 3's `volpath` on index-matched objects (references made
//! by `scripts/make_references.py`, scenes by `scripts/make_media_scenes.py`).
//!
//! With roughness 0, IOR 1.01 (the least the renderer takes), specular 0 and weight 1, our
//! walk (Cycles' Random Walk) enters straight, scatters in the homogeneous medium of the
//! material's radius and colour, and leaves through a white Lambertian surface. Mitsuba
//! renders the same medium behind a `null` surface, whose exit is straight on. Under a
//! constant environment and with nothing else in the scene the two exits see the same light,
//! so every pixel is the same probability of a walk leaving again, per channel: an exact
//! reference for the walk in finite geometry (a smooth sphere; a flat-shaded slab of large
//! triangles, seen on three faces). Per pixel, relMSE against the noise floors of both images
//! and the image means, as for the other references (`common::compare::pixel_compare`).

use crate::common;
use common::compare::pixel_compare;
use common::*;
use photonmap::render::film::Image;
use photonmap::render::settings::FilterName;
use photonmap::render::RenderSettings;
use photonmap::scene::SceneDesc;

/// Four batches of 64 spp (seeds 300..303). Nothing else in the scene: no photon maps.
fn batches(desc: &SceneDesc) -> Vec<Image> {
    (0..4)
        .map(|seed| {
            let out = render_settings(
                desc,
                RenderSettings {
                    spp: 64,
                    seed: 300 + seed,
                    filter: FilterName::Box,
                    photons: 0,
                    caustic_photons: 0,
                    ..Default::default()
                },
            );
            out.film.combined()
        })
        .collect()
}

/// The object's mean per channel, ours against the reference, over the pixels where the
/// reference varies (the environment seen straight is exactly 1 in both): the relative
/// difference and its standard error (ours from the batches, the reference's from its
/// standard errors; pixels taken as independent).
fn object_means(batches: &[Image], reference: &str) -> [(f64, f64); 3] {
    let (refm, var_ref) = common::compare::reference(reference);
    let (ours, var_ours) = mean_and_var(batches);
    let mut out = [(0.0, 0.0); 3];
    for (c, o) in out.iter_mut().enumerate() {
        let (mut so, mut sr, mut vo, mut vr, mut n) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for i in 0..refm.data.len() {
            if var_ref.data[i][c] > 0.0 {
                so += ours.data[i][c] as f64;
                sr += refm.data[i][c] as f64;
                vo += var_ours.data[i][c] as f64;
                vr += var_ref.data[i][c] as f64;
                n += 1.0;
            }
        }
        let (mo, mr) = (so / n, sr / n);
        *o = (mo / mr - 1.0, (vo + vr).sqrt() / n / mr);
    }
    out
}

/// Passes when the per-pixel comparison does and each channel's object mean lies within
/// `OBJECT_SIGMAS` standard errors plus `OBJECT_MARGIN` of the reference's.
fn passes(label: &str, desc: &SceneDesc, scene: &str) -> bool {
    let b = batches(desc);
    let reference = format!("{scene}_full");
    let res = pixel_compare(label, &b, &reference);
    let means = object_means(&b, &reference);
    eprintln!("{label}: object means (relative difference, standard error) {means:?}");
    res.passed()
        && means
            .iter()
            .all(|(d, se)| d.abs() < OBJECT_SIGMAS * se + OBJECT_MARGIN)
}

/// Standard errors an object mean may lie off the reference's.
const OBJECT_SIGMAS: f64 = 4.0;
/// Allowed beyond the noise. Measured: the sphere's blue channel reads 0.64% low (4.8 standard
/// errors; the 256-event cap is not the cause, raising it changes nothing), the others lie
/// within 2.3 standard errors. A colour 2% off moves the object means by 1.2-2.5%, a radius
/// 10% off by 1.1-1.9%.
const OBJECT_MARGIN: f64 = 0.005;

fn compare(scene: &str) {
    assert!(passes(scene, &load_scene(scene), scene), "{scene}");
}

#[test]
fn subsurface_sphere_matches_mitsuba() {
    compare("sss_sphere");
}

#[test]
fn subsurface_slab_matches_mitsuba() {
    compare("sss_slab");
}

/// The same comparison fails with the subsurface colour 2% off (the walks' albedo), or the
/// radius 10% off, on the sphere.
#[test]
fn the_comparison_catches_a_colour_or_radius_slightly_off() {
    for (what, colour, radius) in [
        ("colour +2%", 1.02f32, 1.0f32),
        ("colour -2%", 0.98, 1.0),
        ("radius +10%", 1.0, 1.1),
        ("radius -10%", 1.0, 0.9),
    ] {
        let mut desc = load_scene("sss_sphere");
        let json = serde_json::to_value(&desc).unwrap();
        let mut json = json;
        let m = &mut json["materials"][0];
        for c in m["base_color"].as_array_mut().unwrap() {
            *c = serde_json::json!(c.as_f64().unwrap() as f32 * colour);
        }
        for r in m["subsurface"]["radius"].as_array_mut().unwrap() {
            *r = serde_json::json!(r.as_f64().unwrap() as f32 * radius);
        }
        desc = serde_json::from_value(json).unwrap();
        assert!(!passes(what, &desc, "sss_sphere"), "{what} passed");
    }
}
