//! Invariants of a render: determinism across thread counts, the sum rule, zero terms.

use crate::common;
use common::*;
use photonmap::render::aov::{Term, TermMask};
use photonmap::render::settings::FilterName;

/// The default scene (glass and mirror spheres, the light in view) in a thin world fog, with a
/// block of a subsurface material on the floor: every term of the sum is non-zero.
fn every_term_scene() -> photonmap::scene::SceneDesc {
    let mut desc = photonmap::scene::default_scene();
    desc.film.width = 48;
    desc.film.height = 40;
    let wax: photonmap::scene::desc::MaterialDesc = serde_json::from_value(serde_json::json!({
        "type": "principled", "name": "wax", "base_color": [0.9, 0.7, 0.5], "roughness": 0.3,
        "subsurface": {"radius": [0.1, 0.05, 0.03]}}))
    .expect("a valid material");
    desc.materials.push(wax);
    let block = photonmap::geometry::shapes::cuboid(
        glam::Vec3::new(-0.2, -1.0, 0.2),
        glam::Vec3::new(0.2, -0.7, 0.6),
    );
    desc.meshes.push(photonmap::scene::desc::MeshDesc {
        name: "wax_block".into(),
        positions: block.positions.iter().map(|p| p.to_array()).collect(),
        indices: block.indices.clone(),
        material: desc.materials.len() as u32 - 1,
        ..Default::default()
    });
    desc.media.push(photonmap::scene::desc::MediumDesc {
        name: "haze".into(),
        sigma_a: [0.02; 3],
        sigma_s: [0.08; 3],
        g: 0.3,
        density: None,
    });
    desc.world_medium = Some(0);
    desc
}

/// The same seed gives the same image, bit for bit, with 1, 3 and 8 threads (photon pass,
/// irradiance cache, volume map and camera pass alike), on a scene where every term is
/// non-zero.
#[test]
fn bit_identical_for_any_thread_count() {
    let desc = every_term_scene();
    let a = render(&desc, 2, 42, 1);
    for t in Term::ALL {
        assert!(
            a.film.term(t).mean().max_element() > 0.0,
            "{} is empty",
            t.name()
        );
    }
    for threads in [3, 8] {
        let b = render(&desc, 2, 42, threads);
        for t in Term::ALL {
            let (x, y) = (&a.film.term(t).data, &b.film.term(t).data);
            assert!(
                x.iter()
                    .zip(y)
                    .all(|(p, q)| p.map(f32::to_bits) == q.map(f32::to_bits)),
                "{} differs with {threads} threads",
                t.name()
            );
        }
    }
    let c = render(&desc, 2, 43, 3);
    assert_ne!(
        a.film.term(Term::Direct).data,
        c.film.term(Term::Direct).data,
        "the seed matters"
    );
}

/// Every term is finite and non-negative, and the default scene shows every surface term:
/// the light, direct light, interreflection, the caustic under the glass sphere, and the
/// spheres themselves (the sum rule is checked against terms rendered alone, below).
#[test]
fn terms_are_finite_and_the_default_scene_shows_each() {
    let mut desc = photonmap::scene::default_scene();
    desc.film.width = 32;
    desc.film.height = 32;
    let out = render(&desc, 4, 1, 0);
    for t in Term::ALL {
        for (i, v) in out.film.term(t).data.iter().enumerate() {
            assert!(
                v.iter().all(|c| c.is_finite() && *c >= 0.0),
                "{} pixel {i}: {v:?}",
                t.name()
            );
        }
    }
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

/// Model only what the scene requires, counted: without media and without specular surfaces
/// no ray-marching step is taken and neither the volume nor the caustic map is read (where
/// the scene has them, the same counters are non-zero); no specular surface, no caustic map;
/// indirect light off, no global map; and the stats say why.
#[test]
fn maps_are_built_only_when_needed() {
    let busy = render(&every_term_scene(), 1, 0, 0).stats.work;
    assert!(
        busy.march_steps > 0 && busy.volume_lookups > 0 && busy.caustic_lookups > 0,
        "{busy:?}"
    );
    let mut desc = load_scene("cornell_diffuse");
    desc.film.width = 16;
    desc.film.height = 16;
    let out = render(&desc, 1, 0, 0);
    assert_eq!(
        out.stats.work,
        photonmap::render::work::WorkStats::default(),
        "work the scene does not need"
    );
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

/// A scene whose surfaces all only emit (the "values" scenes: an Emission plane filling the
/// view) stores no photon: its global and caustic maps are not traced, and say why. Traced,
/// the photon pass emitted `max_emitted_factor` times the photons asked for, all of them lost,
/// which was 94% of such a render's time. The image is the one a render without photons makes.
#[test]
fn emitters_alone_trace_no_photons() {
    use photonmap::scene::desc::{ColorInput, MaterialDesc};
    let mut desc = load_scene("cornell_spheres");
    desc.film.width = 16;
    desc.film.height = 16;
    for (i, m) in desc.materials.iter_mut().enumerate() {
        *m = MaterialDesc::Emission {
            name: format!("glow {i}"),
            color: ColorInput::Value([0.2 + 0.1 * i as f32, 0.5, 0.3]),
            strength: 1.0,
        };
    }
    let out = render(&desc, 2, 3, 0);
    for name in ["global", "caustic"] {
        let m = out
            .stats
            .photon_maps
            .iter()
            .find(|m| m.map == name)
            .unwrap();
        assert!(
            !m.built
                && m.emitted == 0
                && m.skipped_because
                    .as_deref()
                    .unwrap()
                    .contains("no surface of the scene scatters"),
            "{m:?}"
        );
    }
    let scene = photonmap::scene::Scene::build(&desc).unwrap();
    let none = photonmap::render::Renderer::new(&scene)
        .settings(photonmap::render::RenderSettings {
            spp: 2,
            seed: 3,
            photons: 0,
            caustic_photons: 0,
            filter: FilterName::Box,
            ..Default::default()
        })
        .render()
        .unwrap();
    assert_eq!(out.film.combined().data, none.film.combined().data);
    assert!(out.film.combined().mean().max_element() > 0.1);

    // One scattering surface back, and the global map is traced again.
    desc.materials[0] = MaterialDesc::Diffuse {
        name: "white".into(),
        color: ColorInput::Value([0.8; 3]),
    };
    let out = render(&desc, 1, 3, 0);
    let g = out
        .stats
        .photon_maps
        .iter()
        .find(|m| m.map == "global")
        .unwrap();
    assert!(g.built && g.stored > 0, "{g:?}");
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

/// An 8x8 block's mean per channel, and its squared standard error from the `error` AOV
/// (a box filter puts each sample in one pixel, so pixels are independent and the block's
/// variance is the sum of its pixels' over 64²).
fn block_stats(
    img: &photonmap::render::film::Image,
    err: &photonmap::render::film::Image,
) -> Vec<([f64; 3], [f64; 3])> {
    let (bw, bh) = (img.width / 8, img.height / 8);
    let mut out = Vec::with_capacity(bw * bh);
    for by in 0..bh {
        for bx in 0..bw {
            let (mut m, mut v) = ([0.0f64; 3], [0.0f64; 3]);
            for y in by * 8..by * 8 + 8 {
                for x in bx * 8..bx * 8 + 8 {
                    let (p, e) = (img.get(x, y), err.get(x, y));
                    for c in 0..3 {
                        m[c] += p[c] as f64 / 64.0;
                        v[c] += (e[c] as f64).powi(2) / (64.0 * 64.0);
                    }
                }
            }
            out.push((m, v));
        }
    }
    out
}

/// The sum rule against independent renders: each term rendered on its own (only its
/// estimators run, with their own random numbers), the terms added up, equals the render of
/// every term together, per 8x8 block and channel, within the noise of the renders
/// (z-test, the standard errors from each render's `error` AOV). On a scene where every term
/// is non-zero. The photon maps are the same in every render (each map is traced from the
/// seed alone), so what differs is the camera samples' noise, which the `error` AOV measures.
///
/// `specular` and `subsurface` are rendered together with the photon terms (`indirect`,
/// `caustic`, `volume`), of which only their own term is taken: the estimators at the end of
/// a specular chain or a subsurface walk read those terms' maps, which a render of the term
/// alone does not build (rendered alone, specular keeps about 55% of the full render's and
/// subsurface about 35%: the mask also decides which maps exist). Their noise is then taken
/// as that render's whole `error`, which is larger than theirs alone: conservative there.
///
/// Threshold: |z| < 4.5 in every one of the 30 x 3 block channels, a family-wise false-alarm
/// rate under 10^-3 for Gaussian block means.
#[test]
fn terms_rendered_alone_sum_to_the_full_render() {
    let desc = every_term_scene();
    let settings = |terms: TermMask| photonmap::render::RenderSettings {
        spp: 16,
        seed: 7,
        threads: 0,
        terms,
        filter: FilterName::Box,
        adaptive_sampling: false,
        ..Default::default()
    };
    let full = render_settings(&desc, settings(TermMask::ALL));
    let full_blocks = block_stats(&full.film.combined(), &full.film.error);
    let mut sum: Vec<([f64; 3], [f64; 3])> = vec![([0.0; 3], [0.0; 3]); full_blocks.len()];
    let photon_terms = [Term::Indirect, Term::Caustic, Term::Volume];
    for t in Term::ALL {
        let mut mask = TermMask::NONE.with(t);
        if matches!(t, Term::Specular | Term::Subsurface) {
            mask = photon_terms.iter().fold(mask, |m, p| m.with(*p));
        }
        let alone = render_settings(&desc, settings(mask));
        assert!(
            alone.film.term(t).mean().max_element() > 0.0,
            "{} is empty",
            t.name()
        );
        for (acc, (m, v)) in sum
            .iter_mut()
            .zip(block_stats(alone.film.term(t), &alone.film.error))
        {
            for c in 0..3 {
                acc.0[c] += m[c];
                acc.1[c] += v[c];
            }
        }
    }
    let mut worst = (0.0f64, 0usize, 0usize);
    let mut z2 = 0.0;
    for (i, ((m, v), (fm, fv))) in sum.iter().zip(&full_blocks).enumerate() {
        for c in 0..3 {
            // A floor for blocks without noise (the light seen whole): f32 rounding.
            let sigma = (v[c] + fv[c]).sqrt().max(1e-6 * fm[c].abs());
            let z = (m[c] - fm[c]) / sigma;
            z2 += z * z;
            if z.abs() > worst.0.abs() {
                worst = (z, i, c);
            }
        }
    }
    let (z, i, c) = worst;
    eprintln!(
        "sum of the terms alone vs the full render: worst z {z:.2} (block {i}, channel {c}: \
         {:.5} vs {:.5}), rms z {:.3} over {} block channels",
        sum[i].0[c],
        full_blocks[i].0[c],
        (z2 / (3 * sum.len()) as f64).sqrt(),
        3 * sum.len()
    );
    assert!(
        z.abs() < 4.5,
        "block {i} channel {c}: the terms rendered alone sum to {:.5}, the full render \
         has {:.5} (z = {z:.2})",
        sum[i].0[c],
        full_blocks[i].0[c]
    );
}

/// The multilayer EXR the CLI writes holds the film: the beauty (`R,G,B`) is the film's
/// combined image and each `<term>.R/G/B` layer the film's term, bit for bit.
#[test]
fn written_exr_holds_the_film() {
    use photonmap::cli::RenderArgs;
    use photonmap::command::exr::read_rgb_layers;
    use photonmap::command::output::write_outputs;
    let desc = every_term_scene();
    let out = render(&desc, 2, 7, 0);
    let dir = std::env::temp_dir().join(format!("photonmap-exr-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut args = RenderArgs::defaults();
    args.output = dir.join("film.exr");
    write_outputs(&args, &out, None).expect("writes");
    let (layers, _) = read_rgb_layers(&args.output).expect("reads back");
    let same = |a: &photonmap::render::film::Image, b: &photonmap::render::film::Image| {
        a.data.len() == b.data.len()
            && a.data
                .iter()
                .zip(&b.data)
                .all(|(p, q)| p.map(f32::to_bits) == q.map(f32::to_bits))
    };
    assert!(
        same(&layers[""], &out.film.combined()),
        "the beauty differs"
    );
    for t in Term::ALL {
        assert!(
            out.film.term(t).mean().max_element() > 0.0,
            "{} is empty",
            t.name()
        );
        assert!(
            same(&layers[t.name()], out.film.term(t)),
            "{} differs",
            t.name()
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A light hidden from the camera (Blender's Ray Visibility > Camera off) is not drawn but
/// lights the scene as before: the emission term loses exactly the light, and the direct
/// term is the same bit for bit (without adaptive sampling, whose rounds follow the image,
/// the light's pixels included).
#[test]
fn a_light_hidden_from_the_camera_still_lights_the_scene() {
    let mut desc = photonmap::scene::default_scene();
    desc.film.width = 32;
    desc.film.height = 32;
    let render = |desc: &photonmap::scene::SceneDesc, spp, seed, threads| {
        render_settings(
            desc,
            photonmap::render::RenderSettings {
                spp,
                seed,
                threads,
                filter: photonmap::render::settings::FilterName::Box,
                adaptive_sampling: false,
                ..Default::default()
            },
        )
    };
    let seen = render(&desc, 2, 5, 0);
    for l in desc.lights.iter_mut() {
        if let photonmap::scene::desc::LightDesc::Rect { camera_visible, .. } = l {
            *camera_visible = false;
        }
    }
    let hidden = render(&desc, 2, 5, 0);
    assert!(seen.film.term(Term::Emission).mean().max_element() > 0.0);
    assert_eq!(hidden.film.term(Term::Emission).mean().max_element(), 0.0);
    assert_eq!(
        seen.film.term(Term::Direct).data,
        hidden.film.term(Term::Direct).data
    );
}

/// The stats record the settings the render was given, named as in the core.
#[test]
fn stats_record_the_settings() {
    let mut desc = photonmap::scene::default_scene();
    desc.film.width = 16;
    desc.film.height = 12;
    let scene = photonmap::scene::Scene::build(&desc).expect("scene builds");
    let mut settings = photonmap::render::RenderSettings::preset(photonmap::render::Quality::Draft);
    settings.seed = 7;
    settings.spp = 2;
    settings.gather = 33;
    settings.terms = TermMask::NONE.with(Term::Direct).with(Term::Caustic);
    let out = photonmap::render::Renderer::new(&scene)
        .settings(settings)
        .render()
        .expect("render succeeds");
    let json = serde_json::to_value(&out.stats).expect("stats serialise");
    let s = &json["settings"];
    assert_eq!(s["seed"], 7);
    assert_eq!(s["spp"], 2);
    assert_eq!(s["gather"], 33);
    assert_eq!(s["photons"], 50_000);
    assert_eq!(s["filter"], "gaussian");
    assert_eq!(s["mode"], "jensen");
    assert_eq!(s["terms"], serde_json::json!(["direct", "caustic"]));
}

/// Both modes give a skipped term the same reason: a scene without specular surfaces has no
/// caustic term in Jensen's mode or the progressive one, and says why in the same words.
#[test]
fn both_modes_say_the_same_about_skipped_terms() {
    let mut desc = load_scene("cornell_diffuse");
    desc.film.width = 8;
    desc.film.height = 8;
    let scene = photonmap::scene::Scene::build(&desc).expect("scene builds");
    let reasons = |mode| {
        let mut s = photonmap::render::RenderSettings::preset(photonmap::render::Quality::Draft);
        s.spp = 1;
        s.mode = mode;
        s.photons = 2000;
        let out = photonmap::render::Renderer::new(&scene)
            .settings(s)
            .render()
            .expect("render succeeds");
        let mut v: Vec<(String, String)> = out
            .stats
            .skipped
            .iter()
            .map(|k| (k.term.to_string(), k.reason.clone()))
            .collect();
        v.sort();
        v
    };
    use photonmap::render::settings::RenderMode;
    let jensen = reasons(RenderMode::Jensen);
    assert_eq!(jensen, reasons(RenderMode::Sppm));
    assert!(jensen.contains(&(
        "caustic".to_string(),
        "the scene has no specular or transmissive surfaces".to_string()
    )));
    assert!(jensen.iter().any(|(t, _)| t == "volume"));
}
