//! Our terms against Mitsuba 3 references (made by `scripts/make_references.py`).
//!
//! Statistic: relMSE(ours, reference) against the relMSE that noise alone predicts,
//! E = mean((var_ours + var_ref) / (ref^2 + eps)), with both variances estimated from
//! independent batches. For an unbiased match the ratio relMSE / E is 1 in expectation; with
//! 128x128x3 pixel channels its sampling spread is a few percent. We accept ratio < 1.3: a
//! brightness error of 2% on the lit pixels alone would add about 4e-4 relMSE, several times
//! the noise floors of these renders, and fail the test. The mean image values must also
//! agree within 1% (4 standard errors of the combined means are well under 0.5%).

use crate::common;
use common::compare::{pixel_compare, surface_batches};
use common::*;
use photonmap::render::aov::Term;

fn compare(scene: &str, reference_name: &str, terms: &[Term], spp: u32) {
    let res = pixel_compare(
        scene,
        &surface_batches(&load_scene(scene), terms, spp, &[]),
        reference_name,
    );
    assert!(res.passed(), "{reference_name}: {res:?}");
}

// The same comparisons with a small error put in must fail: tests/sensitivity.rs.

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
