//! Invariants of a render: determinism across thread counts, the sum rule, zero terms.

mod common;
use common::*;
use photonmap::render::aov::{Term, TermMask};

#[test]
fn bit_identical_for_one_and_two_threads() {
    let mut desc = photonmap::scene::default_scene();
    desc.film.width = 48;
    desc.film.height = 40;
    let a = render(&desc, 4, 42, 1);
    let b = render(&desc, 4, 42, 2);
    for t in Term::ALL {
        let (x, y) = (&a.film.term(t).data, &b.film.term(t).data);
        assert!(
            x.iter()
                .zip(y)
                .all(|(p, q)| p.map(f32::to_bits) == q.map(f32::to_bits)),
            "{} differs",
            t.name()
        );
    }
    let c = render(&desc, 4, 43, 2);
    assert_ne!(
        a.film.term(Term::Direct).data,
        c.film.term(Term::Direct).data,
        "the seed matters"
    );
}

#[test]
fn combined_is_the_exact_sum_and_terms_are_finite() {
    let mut desc = photonmap::scene::default_scene();
    desc.film.width = 32;
    desc.film.height = 32;
    let out = render(&desc, 4, 1, 0);
    let combined = out.film.combined();
    for i in 0..combined.data.len() {
        let mut s = [0.0f32; 3];
        for t in Term::ALL {
            let v = out.film.term(t).data[i];
            assert!(
                v.iter().all(|c| c.is_finite() && *c >= 0.0),
                "{} pixel {i}: {v:?}",
                t.name()
            );
            for c in 0..3 {
                s[c] += v[c];
            }
        }
        assert_eq!(combined.data[i], s);
    }
    // The default scene shows emission (the light), direct light, and specular (the spheres).
    // The default scene shows every surface term: the light, direct light, interreflection,
    // the caustic under the glass sphere, and the spheres themselves.
    for t in [
        Term::Direct,
        Term::Indirect,
        Term::Caustic,
        Term::Specular,
        Term::Emission,
    ] {
        assert!(
            out.film.term(t).mean().max_element() > 0.0,
            "{} is empty",
            t.name()
        );
        assert!(
            !out.stats.skipped.iter().any(|s| s.term == t.name()),
            "{} reported as skipped",
            t.name()
        );
    }
    // No media: the volume term is zeros, and the stats say why.
    assert_eq!(out.film.term(Term::Volume).mean().max_element(), 0.0);
    assert!(out.stats.skipped.iter().any(|s| s.term == "volume"));
    assert_eq!(out.stats.non_finite_samples, 0);
}

/// Model only what the scene requires: no specular surface, no caustic map; indirect light
/// off, no global map; and the stats say why.
#[test]
fn maps_are_built_only_when_needed() {
    let mut desc = load_scene("cornell_diffuse");
    desc.film.width = 16;
    desc.film.height = 16;
    let out = render(&desc, 1, 0, 0);
    let caustic = out
        .stats
        .photon_maps
        .iter()
        .find(|m| m.map == "caustic")
        .unwrap();
    assert!(
        !caustic.built
            && caustic
                .skipped_because
                .as_deref()
                .unwrap()
                .contains("no specular"),
        "{caustic:?}"
    );
    assert!(out
        .stats
        .photon_maps
        .iter()
        .any(|m| m.map == "global" && m.built && m.stored > 0));

    let only_direct = TermMask::ALL.without(Term::Indirect);
    let out = render_terms(&desc, 1, 0, 0, only_direct);
    let global = out
        .stats
        .photon_maps
        .iter()
        .find(|m| m.map == "global")
        .unwrap();
    assert!(
        !global.built && global.skipped_because.is_some(),
        "{global:?}"
    );
    assert!(out.stats.skipped.iter().any(|s| s.term == "indirect"));
}

#[test]
fn scene_translated_far_from_the_origin_renders_the_same() {
    // 1e5 units away: robust ray offsets keep self-intersection out (images agree within noise).
    let base = load_scene("cornell_diffuse");
    let mut far = base.clone();
    let d = [1.0e5f32, -0.7e5, 0.4e5];
    let shift = |m: &mut [[f32; 4]; 4]| {
        for r in 0..3 {
            m[r][3] += d[r];
        }
    };
    shift(&mut far.camera.transform);
    for m in far.meshes.iter_mut() {
        shift(&mut m.transform);
    }
    for l in far.lights.iter_mut() {
        if let photonmap::scene::desc::LightDesc::Rect { transform, .. } = l {
            shift(transform);
        }
    }
    let a = render(&base, 16, 5, 0).film.term(Term::Direct).mean();
    let b = render(&far, 16, 5, 0).film.term(Term::Direct).mean();
    for c in 0..3 {
        assert!(
            (a[c] / b[c] - 1.0).abs() < 0.03,
            "channel {c}: {} vs {}",
            a[c],
            b[c]
        );
    }
}
