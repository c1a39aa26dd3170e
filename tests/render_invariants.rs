//! Invariants of a render: determinism across thread counts, the sum rule, zero terms.

mod common;
use common::*;
use photonmap::render::aov::{Term, TermMask};

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
/// spheres themselves (the sum rule is checked on the written file, below).
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

/// The sum rule on the file a user gets: the beauty read back from the CLI's multilayer EXR
/// (`R,G,B`) is, bit for bit, the sum of the terms read back from the same file
/// (`<term>.R/G/B`, added in the order of `Term::ALL`), on a scene where every term is
/// non-zero.
#[test]
fn written_exr_beauty_is_the_sum_of_its_terms() {
    use photonmap::cli::{write_outputs, RenderArgs};
    use photonmap::io::exr::read_rgb_layers;
    let desc = every_term_scene();
    let out = render(&desc, 2, 7, 0);
    let dir = std::env::temp_dir().join(format!("photonmap-sum-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut args = RenderArgs::defaults();
    args.output = dir.join("sum.exr");
    write_outputs(&args, &out).expect("writes");
    let (layers, _) = read_rgb_layers(&args.output).expect("reads back");
    let beauty = &layers[""];
    let mut nonzero = 0;
    for i in 0..beauty.data.len() {
        let mut s = [0.0f32; 3];
        for t in Term::ALL {
            let v = layers[t.name()].data[i];
            for c in 0..3 {
                s[c] += v[c];
            }
        }
        assert_eq!(
            beauty.data[i].map(f32::to_bits),
            s.map(f32::to_bits),
            "pixel {i}: beauty {:?}, terms sum to {s:?}",
            beauty.data[i]
        );
        nonzero += (s[0] > 0.0) as usize;
    }
    assert!(nonzero > beauty.data.len() / 2);
    for t in Term::ALL {
        assert!(
            layers[t.name()].mean().max_element() > 0.0,
            "{} empty in the file",
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
                filter: photonmap::render::film::Filter::Box,
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
    let mut settings = photonmap::render::Quality::Draft.settings();
    settings.seed = 7;
    settings.spp = 2;
    settings.photons.gather = 33;
    settings.terms = TermMask::NONE.with(Term::Direct).with(Term::Caustic);
    let out = photonmap::render::Renderer::new(&scene)
        .settings(settings)
        .render()
        .expect("render succeeds");
    let json = serde_json::to_value(&out.stats).expect("stats serialise");
    let s = &json["settings"];
    assert_eq!(s["seed"], 7);
    assert_eq!(s["spp"], 2);
    assert_eq!(s["photons"]["gather"], 33);
    assert_eq!(s["photons"]["global"], 50_000);
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
        let mut s = photonmap::render::Quality::Draft.settings();
        s.spp = 1;
        s.mode = mode;
        s.photons.global = 2000;
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
