//! Participating media against Mitsuba 3's `volpath` (references made by
//! `scripts/make_references.py`, scenes by `scripts/make_media_scenes.py`).
//!
//! - `fog_spot_single` isolates direct light and single scattering (Mitsuba max_depth 2): ours
//!   renders direct + volume + emission with no volume photons, so the volume term is single
//!   scattering only. Per-pixel relMSE against the noise-only prediction, as for the surface
//!   references (`tests/reference_mitsuba.rs`).
//! - The full scenes compare 8x8-pixel block means (the path-traced references are noisy and
//!   heavy-tailed around caustics) and image means. thick_sphere tests each block by a t-test
//!   against its noise (ours from the spread of 8 seeds, the reference's from its stderr EXR;
//!   `common::compare::media_blocks`). fog_spot and fog_glass are judged by their block
//!   relMSE (`common::compare::media_limits`), which weighs a dim block's error by its
//!   reference value squared plus 1e-2: their block t-tests find dim blocks of the fog's
//!   multiply scattered glow well above Mitsuba's (fog_spot: 3 of 256 blocks, up to 1.22x,
//!   t 15.2 against a critical 5.9; fog_glass with clear glass: 9 of 256, up to 1.70x).

use crate::common;
use common::compare::{
    media_blocks, media_full, pixel_compare, single_scattering_batches, t_critical,
};
use common::*;

/// The Student t quantiles the block tests use, against printed tables.
#[test]
fn t_quantiles_match_the_tables() {
    for (alpha, dof, table) in [
        (0.05, 7.0, 2.365),
        (0.01, 3.0, 5.841),
        (0.001, 15.0, 4.073),
        (0.05, 1e7, 1.960),
    ] {
        let t = t_critical(alpha, dof);
        assert!(
            (t - table).abs() < 1e-3,
            "t({alpha}, {dof}) = {t}, table {table}"
        );
    }
}

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

/// Every 8x8 block within its noise (t-tests at a family-wise false-alarm rate of 10^-3),
/// and the image mean within 1.5%.
#[test]
fn thick_sphere_full_matches_mitsuba() {
    let res = media_blocks(
        "thick_sphere",
        &load_scene("thick_sphere"),
        "thick_sphere",
        &[],
    );
    assert!(res.passed(), "thick_sphere: {res:?}");
}

#[test]
fn fog_glass_volume_caustic_matches_mitsuba() {
    full("fog_glass");
}
