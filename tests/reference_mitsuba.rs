//! Our terms against Mitsuba 3 references (made by `scripts/make_references.py`).
//!
//! Statistic: relMSE(ours, reference) against the relMSE that noise alone predicts,
//! E = mean((var_ours + var_ref) / (ref^2 + eps)), with both variances estimated from
//! independent batches. For an unbiased match the ratio relMSE / E is 1 in expectation; with
//! 128x128x3 pixel channels its sampling spread is a few percent. We accept ratio < 1.3: a
//! brightness error of 2% on the lit pixels alone would add about 4e-4 relMSE, several times
//! the noise floors of these renders, and fail the test. The mean image values must also
//! agree within 1% (4 standard errors of the combined means are well under 0.5%).

#[path = "common_render.rs"]
mod common;
use common::*;
use photonmap::io::exr::read_rgb_layers;
use photonmap::render::aov::Term;
use photonmap::render::film::Image;

fn reference(name: &str) -> (Image, Image) {
    let (mean, _) = read_rgb_layers(data(&format!("references/{name}.exr"))).expect("reference EXR");
    let (se, _) = read_rgb_layers(data(&format!("references/{name}.stderr.exr"))).expect("reference stderr EXR");
    let mean = mean[""].clone();
    let mut var = se[""].clone();
    for p in var.data.iter_mut() {
        for c in p.iter_mut() {
            *c *= *c;
        }
    }
    (mean, var)
}

fn compare(scene: &str, reference_name: &str, terms: &[Term], spp: u32) {
    let desc = load_scene(scene);
    let batches: Vec<Image> = (0..4).map(|seed| sum_terms(&render(&desc, spp, 1000 + seed, 0), terms)).collect();
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
    assert!(ratio < 1.3, "{reference_name}: relMSE {measured:.3e} is {ratio:.2}x the noise floor {expected:.3e}");
    for c in 0..3 {
        let rel = (mo[c] / mr[c] - 1.0).abs();
        assert!(rel < 0.01, "{reference_name}: mean channel {c} differs by {:.2}%", rel * 100.0);
    }
}

#[test]
fn diffuse_cornell_direct_matches_mitsuba() {
    compare("cornell_diffuse", "cornell_diffuse_direct", &[Term::Direct, Term::Emission], 64);
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
