//! Every reference comparison of the suite sees a small error: each is run here, at its own
//! tolerance (tests/common/compare.rs), on its scene with one error put in, and must fail.
//!
//! | comparison (claim) | tolerance | errors put in |
//! |---|---|---|
//! | surface direct, per pixel (`reference_mitsuba.rs`) | relMSE < 1.3x the noise floors, means within 1% | light +2%, albedo -2%, area light two-sided |
//! | mirror and glass, per pixel (`reference_mitsuba.rs`) | the same | light +2% |
//! | single scattering, per pixel (`media_reference.rs`) | the same | spot turned by 5 deg, volume term x 0.95 |
//! | glass in fog, 8x8 blocks and mean (`media_reference.rs`) | block relMSE < 4e-3, mean within 1.5% | volume term x 0.95, caustic photons dropped |
//! | thick sphere, 8x8 blocks and mean (`media_reference.rs`) | every block's t-test (8 seeds) at a family-wise 10^-3, mean within 1.5% | volume term x 0.95 and x 1.05, direct term x 0.9 |
//! | full GI, 8x8 blocks at 10^6 photons (`photon_terms.rs`) | block relMSE < 2e-4 | caustic photons dropped, light +2% |
//!
//! The corpus against Cycles has its own sensitivity tests (tests/blender/test_corpus.py).

use crate::common;
use common::compare::*;
use common::*;
use photonmap::render::aov::Term;
use photonmap::scene::desc::{LightDesc, MaterialDesc};
use photonmap::scene::SceneDesc;

fn brighter(mut desc: SceneDesc) -> SceneDesc {
    for l in desc.lights.iter_mut() {
        match l {
            LightDesc::Point { power, .. }
            | LightDesc::Spot { power, .. }
            | LightDesc::Rect { power, .. }
            | LightDesc::Disk { power, .. }
            | LightDesc::Sphere { power, .. } => *power *= 1.02,
            _ => panic!("a light kind this test does not scale"),
        }
    }
    desc
}

fn darker_albedo(mut desc: SceneDesc) -> SceneDesc {
    let mut n = 0;
    for m in desc.materials.iter_mut() {
        if let MaterialDesc::Diffuse { color, .. } = m {
            if let photonmap::scene::desc::ColorInput::Value(c) = color {
                for x in c.iter_mut() {
                    *x *= 0.98;
                }
                n += 1;
            }
        }
    }
    assert!(n > 0, "no diffuse material");
    desc
}

fn two_sided(mut desc: SceneDesc) -> SceneDesc {
    let mut n = 0;
    for l in desc.lights.iter_mut() {
        if let LightDesc::Rect { two_sided, .. } = l {
            *two_sided = true;
            n += 1;
        }
    }
    assert!(n > 0, "no area light");
    desc
}

fn spot_turned(mut desc: SceneDesc) -> SceneDesc {
    let a = 5f32.to_radians();
    let mut n = 0;
    for l in desc.lights.iter_mut() {
        if let LightDesc::Spot { direction, .. } = l {
            let [x, y, z] = *direction;
            *direction = [x * a.cos() - y * a.sin(), x * a.sin() + y * a.cos(), z];
            n += 1;
        }
    }
    assert!(n > 0, "no spot");
    desc
}

fn must_fail_pixels(label: &str, res: PixelResult) {
    assert!(!res.passed(), "{label} went unnoticed: {res:?}");
}

/// The surface-direct comparison (cornell_diffuse against its Mitsuba reference) must fail
/// on `desc`.
fn surface_direct_must_fail(label: &str, desc: SceneDesc) {
    let terms = [Term::Direct, Term::Emission];
    let batches = surface_batches(&desc, &terms, 64, &[]);
    must_fail_pixels(
        label,
        pixel_compare(label, &batches, "cornell_diffuse_direct"),
    );
}

#[test]
fn surface_direct_sees_a_light_two_percent_brighter() {
    surface_direct_must_fail("light +2%", brighter(load_scene("cornell_diffuse")));
}

#[test]
fn surface_direct_sees_an_albedo_two_percent_darker() {
    surface_direct_must_fail("albedo -2%", darker_albedo(load_scene("cornell_diffuse")));
}

#[test]
fn surface_direct_sees_a_two_sided_area_light() {
    surface_direct_must_fail(
        "two-sided area light",
        two_sided(load_scene("cornell_diffuse")),
    );
}

#[test]
fn mirror_and_glass_see_a_light_two_percent_brighter() {
    let desc = brighter(load_scene("cornell_spheres"));
    let terms = [Term::Direct, Term::Specular, Term::Emission];
    let res = pixel_compare(
        "light +2%",
        &surface_batches(&desc, &terms, 64, &[]),
        "cornell_spheres_direct_specular",
    );
    must_fail_pixels("light +2%", res);
}

#[test]
fn single_scattering_sees_a_spot_turned_by_five_degrees() {
    let desc = spot_turned(load_scene("fog_spot"));
    let res = pixel_compare(
        "spot +5 deg",
        &single_scattering_batches(&desc, &[]),
        "fog_spot_single",
    );
    must_fail_pixels("spot turned 5 deg", res);
}

#[test]
fn single_scattering_sees_the_volume_term_five_percent_low() {
    let desc = load_scene("fog_spot");
    let res = pixel_compare(
        "volume x0.95",
        &single_scattering_batches(&desc, &[(Term::Volume, 0.95)]),
        "fog_spot_single",
    );
    must_fail_pixels("volume x 0.95", res);
}

/// One render of fog_glass, judged with the volume term 5% low and with its caustic photons
/// dropped.
#[test]
fn glass_in_fog_sees_the_volume_term_low_and_the_caustic_photons_dropped() {
    let scales: [Scale; 2] = [&[(Term::Volume, 0.95)], &[(Term::Caustic, 0.0)]];
    let res = media_full_each("fog_glass", &load_scene("fog_glass"), "fog_glass", &scales);
    for (what, r) in ["volume x 0.95", "dropped caustics"].iter().zip(&res) {
        assert!(!r.passed(), "{what} went unnoticed: {r:?}");
    }
}

/// One set of renders of thick_sphere, judged with the volume term 5% low, 5% high, and with
/// the direct term 10% low: each fails the per-block t-tests (not only the mean).
#[test]
fn thick_sphere_blocks_see_the_volume_and_direct_terms_off() {
    let scales: [Scale; 3] = [
        &[(Term::Volume, 0.95)],
        &[(Term::Volume, 1.05)],
        &[(Term::Direct, 0.9)],
    ];
    let desc = load_scene("thick_sphere");
    let res = media_blocks_each("thick_sphere", &desc, "thick_sphere", &scales);
    for (what, r) in ["volume x 0.95", "volume x 1.05", "direct x 0.9"]
        .iter()
        .zip(&res)
    {
        assert!(r.blocks_over > 0, "{what}: no block off: {r:?}");
    }
}

#[test]
fn full_gi_sees_the_caustic_photons_dropped() {
    let (_, block) = full_gi(
        &load_scene("cornell_spheres"),
        "cornell_spheres_full",
        1_000_000,
        &[(Term::Caustic, 0.0)],
    );
    let limit = full_gi_limit("cornell_spheres_full");
    assert!(
        block > limit,
        "dropped caustics went unnoticed: {block:.3e} < {limit:.1e}"
    );
}

#[test]
fn full_gi_sees_a_light_two_percent_brighter() {
    let desc = brighter(load_scene("cornell_diffuse"));
    let (_, block) = full_gi(&desc, "cornell_diffuse_full", 1_000_000, &[]);
    let limit = full_gi_limit("cornell_diffuse_full");
    assert!(
        block > limit,
        "a 2% brighter light went unnoticed: {block:.3e} < {limit:.1e}"
    );
}
