//! Inputs found by the fuzz targets of `fuzz/` (see README, "Fuzzing"), replayed the way the
//! targets run them: JSON text -> `scene_json::from_str` -> build -> an 8x8 render at 1 spp
//! with ~100 photons per map. None may panic; a render that succeeds has every AOV pixel
//! finite and >= 0. Files under `tests/data/fuzz/` are JSON scene inputs (the name says what
//! each one found; an `ir_builder` input is stored as the scene it generated); the seed corpus
//! of `fuzz/corpus/` runs too.

use photonmap::io::scene_json;
use photonmap::photon::trace::BATCH;
use photonmap::render::aov::Term;
use photonmap::render::settings::Bytes;
use photonmap::render::settings::FilterName;
use photonmap::render::{RenderOutput, RenderSettings, Renderer};
use photonmap::scene::desc::FilmDesc;
use photonmap::scene::{Scene, SceneDesc};
use std::path::PathBuf;

/// The settings of `fuzz/src/lib.rs`.
fn tiny_settings() -> RenderSettings {
    RenderSettings {
        spp: 1,
        seed: 7,
        threads: 1,
        max_specular_depth: 4,
        filter: FilterName::Box,
        photons: 100,
        caustic_photons: 100,
        volume_photons: 100,
        gather: 16,
        final_gather_rays: 4,
        max_bounces: 16,
        memory_limit: Some(Bytes(256 << 20)),
        ..Default::default()
    }
}

fn tiny_render(label: &str, desc: &SceneDesc) -> Option<RenderOutput> {
    let mut desc = desc.clone();
    desc.film = FilmDesc {
        width: 8,
        height: 8,
        transparent: false,
    };
    let scene = Scene::build(&desc).ok()?;
    let out = Renderer::new(&scene)
        .settings(tiny_settings())
        .render()
        .ok()?;
    for t in Term::ALL {
        for (i, p) in out.film.term(t).data.iter().enumerate() {
            assert!(
                p.iter().all(|c| c.is_finite() && *c >= 0.0),
                "{label}: {} pixel {i} = {p:?}",
                t.name()
            );
        }
    }
    for (i, a) in out.film.alpha.iter().enumerate() {
        assert!((0.0..=1.0).contains(a), "{label}: alpha of pixel {i} = {a}");
    }
    Some(out)
}

/// What the `scene_json` target does with one input.
fn replay(label: &str, bytes: &[u8]) -> Option<RenderOutput> {
    let text = std::str::from_utf8(bytes).ok()?;
    let desc = scene_json::from_str(text).ok()?;
    tiny_render(label, &desc)
}

fn files(dir: &str, prefix: &str) -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(dir);
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    v.retain(|p| {
        p.file_name()
            .and_then(|n| n.to_str())
            .is_some_and(|n| n.starts_with(prefix))
    });
    v.sort();
    v
}

#[test]
fn seed_corpus_renders_finite() {
    let seeds = files("fuzz/corpus/scene_json", "seed_");
    assert!(seeds.len() >= 5, "{seeds:?}");
    for p in seeds {
        let label = p.display().to_string();
        let bytes = std::fs::read(&p).unwrap();
        assert!(replay(&label, &bytes).is_some(), "{label} renders");
    }
}

#[test]
fn stored_fuzz_inputs_do_not_panic() {
    for p in files("tests/data/fuzz", "") {
        let label = p.display().to_string();
        let bytes = std::fs::read(&p).unwrap();
        replay(&label, &bytes);
    }
}

/// `ir_builder` timed out (10 s limit, 13 s wall under `nice -n 19` on a busy machine, 1.3 s
/// of CPU) on a closed box (an inside-out cube) of a mirror with reflectance up to 8 around a
/// point light: Russian roulette never absorbs and mirrors store nothing, so each map traces
/// its emission cap of paths, each to `max_bounces`. The cost is bounded by that cap.
#[test]
fn mirror_box_with_gain_stops_at_the_emission_cap() {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/fuzz/slow_mirror_box_with_gain.json");
    let out = replay("slow_mirror_box_with_gain", &std::fs::read(p).unwrap()).expect("renders");
    let built: Vec<_> = out.stats.photon_maps.iter().filter(|m| m.built).collect();
    assert_eq!(built.len(), 2, "global and caustic maps");
    for m in built {
        assert_eq!(m.stored, 0, "{}", m.map);
        // max(100 x max_emitted_factor, 100 000) paths, in whole batches.
        assert_eq!(m.emitted, 100_000u64.div_ceil(BATCH) * BATCH, "{}", m.map);
    }
}

/// `ir_builder` crash: an environment texture with negative texels (and no geometry) gave
/// negative `emission` pixels, and negative weights to the environment's sampling
/// distribution. Texels now count as at least 0, as in material colours.
#[test]
fn negative_environment_texels_count_as_zero() {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/fuzz/negative_environment_texel.json");
    let out = replay("negative_environment_texel", &std::fs::read(p).unwrap()).expect("renders");
    let emission = &out.film.term(Term::Emission).data;
    assert!(emission.iter().flatten().all(|v| *v >= 0.0));
    assert!(
        emission.iter().flatten().any(|v| *v > 0.0),
        "the environment is seen"
    );
}
