//! Participating media against Mitsuba 3's `volpath` (references made by
//! `scripts/make_references.py`, scenes by `scripts/make_media_scenes.py`).
//!
//! - `fog_spot_single` isolates direct light and single scattering (Mitsuba max_depth 2): ours
//!   renders direct + volume + emission with no volume photons, so the volume term is single
//!   scattering only. Per-pixel relMSE against the noise-only prediction, as for the surface
//!   references (`tests/reference_mitsuba.rs`).
//! - The full scenes compare 8x8-pixel block means (the path-traced references are noisy and
//!   heavy-tailed around caustics) and image means. The figures
//!   and limits are `common::compare::media_limits`'s.

mod common;
use common::compare::{media_full, pixel_compare, single_scattering_batches};
use common::*;

// The same comparisons with a small error put in must fail: tests/sensitivity.rs.

#[test]
fn fog_spot_direct_and_single_scattering_match_mitsuba() {
    let batches = single_scattering_batches(&load_scene("fog_spot"), &[]);
    let res = pixel_compare("fog_spot", &batches, "fog_spot_single");
    assert!(res.passed(), "fog_spot_single: {res:?}");
}

fn full(scene: &str) {
    let res = media_full(scene, &load_scene(scene), scene, &[]);
    assert!(res.passed(), "{scene}: {res:?}");
}

#[test]
fn fog_spot_full_matches_mitsuba() {
    full("fog_spot");
}

#[test]
fn thick_sphere_full_matches_mitsuba() {
    full("thick_sphere");
}

#[test]
fn fog_glass_volume_caustic_matches_mitsuba() {
    full("fog_glass");
}
