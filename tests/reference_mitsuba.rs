//! Our terms against Mitsuba 3 references (made by `scripts/make_references.py`).
//!
//! Statistic: relMSE(ours, reference) against the relMSE that noise alone predicts,
//! E = mean((var_ours + var_ref) / (ref^2 + eps)), with both variances estimated from
//! independent batches. For an unbiased match the ratio relMSE / E is 1 in expectation; with
//! 128x128x3 pixel channels its sampling spread is a few percent. We accept ratio < 1.3: a
//! brightness error of 2% on the lit pixels alone would add about 4e-4 relMSE, several times
//! the noise floors of these renders, and fail the test. The mean image values must also
//! agree within 1% (4 standard errors of the combined means are well under 0.5%).

mod common;
use common::*;
use photonmap::io::exr::read_rgb_layers;
use photonmap::render::aov::{Term, TermMask};
use photonmap::render::film::Image;
use photonmap::scene::desc::LightDesc;
use photonmap::scene::SceneDesc;

fn reference(name: &str) -> (Image, Image) {
    let (mean, _) =
        read_rgb_layers(data(&format!("references/{name}.exr"))).expect("reference EXR");
    let (se, _) = read_rgb_layers(data(&format!("references/{name}.stderr.exr")))
        .expect("reference stderr EXR");
    let mean = mean[""].clone();
    let mut var = se[""].clone();
    for p in var.data.iter_mut() {
        for c in p.iter_mut() {
            *c *= *c;
        }
    }
    (mean, var)
}

/// (relMSE / noise-only relMSE, relative error of the mean per channel).
fn compare_desc(
    desc: &SceneDesc,
    reference_name: &str,
    terms: &[Term],
    spp: u32,
) -> (f64, [f32; 3]) {
    // Only the compared terms run: with the photon terms off, nothing else reaches `specular`.
    let mask = terms.iter().fold(TermMask::NONE, |m, t| m.with(*t));
    let batches: Vec<Image> = (0..4)
        .map(|seed| sum_terms(&render_terms(desc, spp, 1000 + seed, 0, mask), terms))
        .collect();
    let (ours, var_ours) = mean_and_var(&batches);
    let (refm, var_ref) = reference(reference_name);
    assert_eq!((ours.width, ours.height), (refm.width, refm.height));
    let measured = rel_mse(&ours, &refm);
    let expected = expected_rel_mse(&var_ours, &var_ref, &refm);
    let ratio = measured / expected;
    let (mo, mr) = (ours.mean(), refm.mean());
    eprintln!(
        "{reference_name}: relMSE {measured:.3e}, noise-only {expected:.3e}, ratio {ratio:.3}; mean ours {mo:?} ref {mr:?}"
    );
    (ratio, [0, 1, 2].map(|c| (mo[c] / mr[c] - 1.0).abs()))
}

fn compare(scene: &str, reference_name: &str, terms: &[Term], spp: u32) {
    let (ratio, mean_err) = compare_desc(&load_scene(scene), reference_name, terms, spp);
    assert!(
        ratio < 1.3,
        "{reference_name}: relMSE is {ratio:.2}x the noise floor"
    );
    for (c, rel) in mean_err.iter().enumerate() {
        assert!(
            *rel < 0.01,
            "{reference_name}: mean channel {c} differs by {:.2}%",
            rel * 100.0
        );
    }
}

/// The statistic has the power to see a small error: the same scene with a 2% brighter light
/// must fail the threshold that the faithful scene passes.
#[test]
fn a_two_percent_brighter_light_is_detected() {
    let mut desc = load_scene("cornell_diffuse");
    for l in desc.lights.iter_mut() {
        if let LightDesc::Rect { power, .. } = l {
            *power *= 1.02;
        }
    }
    let (ratio, mean_err) = compare_desc(
        &desc,
        "cornell_diffuse_direct",
        &[Term::Direct, Term::Emission],
        64,
    );
    assert!(ratio > 1.3, "a 2% error went unnoticed: ratio {ratio:.3}");
    assert!(mean_err.iter().all(|e| *e > 0.01), "{mean_err:?}");
}

#[test]
fn diffuse_cornell_direct_matches_mitsuba() {
    compare(
        "cornell_diffuse",
        "cornell_diffuse_direct",
        &[Term::Direct, Term::Emission],
        64,
    );
}

#[test]
fn spheres_direct_specular_emission_match_mitsuba() {
    compare(
        "cornell_spheres",
        "cornell_spheres_direct_specular",
        &[Term::Direct, Term::Specular, Term::Emission],
        64,
    );
}
