//! Photon maps kept, saved and loaded (`render::map_file`), and Jensen frames in tiles
//! (`render::tile`): a saved set renders the same bits as the render that built it; a set
//! of another scene, a truncated file or one of another version is a clear error; a frame
//! rendered in tiles over one set is the frame rendered whole, to the bit.

use crate::common;
use common::*;
use photonmap::command::{render_request, RenderRequest};
use photonmap::render::film::Film;
use photonmap::render::map_file::{self, MapSet, OnMismatch};
use photonmap::render::settings::FilterName;
use photonmap::render::stratified::Rect;
use photonmap::render::tile::{self, TileOutput, TileStage};
use photonmap::render::{RenderOutput, RenderSettings, Renderer};
use photonmap::scene::{Scene, SceneDesc};
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn small(name: &str) -> SceneDesc {
    let mut desc = load_scene(name);
    desc.film.width = 32;
    desc.film.height = 24;
    desc
}

fn settings(threads: usize) -> RenderSettings {
    RenderSettings {
        spp: 4,
        seed: 11,
        threads,
        filter: FilterName::Box,
        photons: 4_000,
        caustic_photons: 2_000,
        volume_photons: 2_000,
        final_gather_rays: 16,
        ..Default::default()
    }
}

fn bits(film: &Film) -> Vec<u32> {
    film.terms
        .iter()
        .chain(std::iter::once(&film.error))
        .flat_map(|img| img.data.iter().flatten().map(|v| v.to_bits()))
        .collect()
}

fn run(desc: &SceneDesc, s: RenderSettings, reuse: Option<Arc<MapSet>>) -> RenderOutput {
    render_request(RenderRequest {
        reuse,
        keep_maps: true,
        ..RenderRequest::new(desc, s)
    })
    .expect("renders")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pm_mapfile_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The camera moved sideways by `dx`.
fn moved(desc: &SceneDesc, dx: f32) -> SceneDesc {
    let mut d = desc.clone();
    d.camera.transform[0][3] += dx;
    d
}

/// Saved and loaded maps render the same bits as the render that built them (the cache
/// was filled for this view, so it is reused as it is), for any thread count; the stats
/// say where they came from.
#[test]
fn a_saved_set_renders_the_same_bits() {
    for name in ["cornell_spheres", "fog_glass", "fog_glass isotropic"] {
        let mut desc = small(name.split(' ').next().unwrap());
        if name.ends_with("isotropic") {
            // Isotropic fog: the set holds the volume map's precomputed points too.
            desc.media.iter_mut().for_each(|m| m.g = 0.0);
        }
        let path = tmp(&format!("{}.pmaps", name.replace(' ', "_")));
        let mut s = settings(2);
        s.save_photon_maps = Some(path.clone());
        let first = run(&desc, s, None);
        let st = first.stats.photon_map_reuse.as_ref().unwrap();
        assert_eq!((st.maps.as_str(), st.cache.as_str()), ("built", "filled"));
        assert_eq!(st.saved_to.as_deref(), Some(path.to_str().unwrap()));

        let mut s = settings(1);
        s.load_photon_maps = Some(path.clone());
        let again = run(&desc, s, None);
        assert!(
            bits(&again.film) == bits(&first.film),
            "{name}: loaded maps differ"
        );
        let st = again.stats.photon_map_reuse.as_ref().unwrap();
        assert_eq!((st.maps.as_str(), st.cache.as_str()), ("loaded", "reused"));
        assert_eq!(st.cache_records_added, 0);
        assert_eq!(again.stats.photons_stored, first.stats.photons_stored);
        let reads = |o: &RenderOutput| o.stats.work.volume_point_reads;
        assert_eq!(reads(&again), reads(&first));
        assert_eq!(
            reads(&first) > 0,
            name.ends_with("isotropic"),
            "{name}: point reads"
        );

        // Another view: the cache is extended for it, deterministically.
        let other = moved(&desc, 0.05);
        let mut s = settings(2);
        s.load_photon_maps = Some(path.clone());
        let a = run(&other, s.clone(), None);
        s.threads = 1;
        let b = run(&other, s, None);
        assert!(bits(&a.film) == bits(&b.film));
        let st = a.stats.photon_map_reuse.as_ref().unwrap();
        assert_eq!(st.cache, "extended");
        assert!(st.cache_records_reused > 0);
    }
}

/// Maps of another scene are an error that says what differs, or rebuilt when asked; the
/// camera is not part of the key.
#[test]
fn a_set_of_another_scene_is_an_error_naming_what_differs() {
    let desc = small("cornell_spheres");
    let path = tmp("key.pmaps");
    let mut s = settings(0);
    s.save_photon_maps = Some(path.clone());
    run(&desc, s, None);
    let set = MapSet::from_bytes(&std::fs::read(&path).unwrap(), &path).unwrap();

    let key = |d: &SceneDesc, s: &RenderSettings| map_file::key_parts(d, s);
    let base = settings(0);
    assert_eq!(key(&moved(&desc, 0.3), &base), key(&desc, &base));
    let mut brighter = desc.clone();
    let mut l = serde_json::to_value(&brighter.lights[0]).unwrap();
    let power = l["power"].as_f64().unwrap();
    l["power"] = serde_json::json!(power * 1.01);
    brighter.lights[0] = serde_json::from_value(l).unwrap();
    let e = map_file::check_key(&set, &key(&brighter, &base), "key.pmaps")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("lights differ") && e.contains("key.pmaps"),
        "{e}"
    );
    let mut other_seed = base.clone();
    other_seed.seed += 1;
    let e = map_file::check_key(&set, &key(&desc, &other_seed), "k")
        .unwrap_err()
        .to_string();
    assert!(e.contains("seed differ"), "{e}");
    let mut more = base.clone();
    more.photons += 1;
    let e = map_file::check_key(&set, &key(&desc, &more), "k")
        .unwrap_err()
        .to_string();
    assert!(e.contains("photon settings differ"), "{e}");
    let mut moved_mesh = desc.clone();
    moved_mesh.meshes[0].positions[0][0] += 1e-3;
    let e = map_file::check_key(&set, &key(&moved_mesh, &base), "k")
        .unwrap_err()
        .to_string();
    assert!(e.contains("geometry differ"), "{e}");

    // Through a render: an error naming the setting, or a rebuild when asked.
    let mut s = settings(0);
    s.load_photon_maps = Some(path.clone());
    let e = render_request(RenderRequest::new(&brighter, s.clone()))
        .err()
        .expect("a mismatched key is an error")
        .to_string();
    assert!(
        e.contains("`load_photon_maps`") && e.contains("lights differ"),
        "{e}"
    );
    s.photon_maps_mismatch = OnMismatch::Rebuild;
    let out = render_request(RenderRequest::new(&brighter, s)).unwrap();
    let st = out.stats.photon_map_reuse.unwrap();
    assert_eq!(st.maps, "built");
    assert!(st.rebuilt_because.unwrap().contains("lights differ"));
}

/// A truncated file, a corrupt one, another kind of file and a file of another format
/// version: each is an error naming the file and what is wrong.
#[test]
fn damaged_files_are_clear_errors() {
    let desc = small("cornell_spheres");
    let path = tmp("damaged.pmaps");
    let mut s = settings(0);
    s.save_photon_maps = Some(path.clone());
    run(&desc, s, None);
    let good = std::fs::read(&path).unwrap();
    let parts = map_file::key_parts(&desc, &settings(0));
    let load = |bytes: &[u8]| {
        let p = tmp("bad.pmaps");
        std::fs::write(&p, bytes).unwrap();
        MapSet::load(&p, &parts).err().map(|e| e.to_string())
    };
    assert_eq!(load(&good), None);
    let e = load(&good[..good.len() / 2]).unwrap();
    assert!(
        e.contains("bad.pmaps") && e.contains("truncated photon-map file"),
        "{e}"
    );
    let mut other = good.clone();
    let version = map_file::MAP_FILE.version;
    other[8..12].copy_from_slice(&(version + 1).to_le_bytes());
    let e = load(&other).unwrap();
    assert!(
        e.contains(&format!(
            "photon-map file of format version {}",
            version + 1
        )) && e.contains(&format!("reads version {version}")),
        "{e}"
    );
    let mut flipped = good.clone();
    let mid = flipped.len() / 2;
    flipped[mid] ^= 0x10;
    let e = load(&flipped).unwrap();
    assert!(e.contains("corrupt photon-map file: checksum"), "{e}");
    let e = load(b"P3\n1 1\n255\n0 0 0\n").unwrap();
    assert!(e.contains("not a photonmap photon-map file"), "{e}");
    let e = MapSet::load(Path::new("/nonexistent/maps.pmaps"), &parts)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("/nonexistent/maps.pmaps"), "{e}");
}

/// Saving or loading maps in a progressive mode, or loading under a time budget, is an
/// error naming the setting.
#[test]
fn maps_are_saved_in_the_jensen_mode_only() {
    let desc = small("cornell_diffuse");
    let mut s = settings(0);
    s.mode = photonmap::render::settings::RenderMode::Pppm;
    s.save_photon_maps = Some(tmp("p.pmaps"));
    let e = render_request(RenderRequest::new(&desc, s))
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("`save_photon_maps`") && e.contains("jensen mode only"),
        "{e}"
    );
    let mut s = settings(0);
    s.load_photon_maps = Some(tmp("p.pmaps"));
    s.time_budget = Some(5.0);
    let e = render_request(RenderRequest::new(&desc, s))
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("`load_photon_maps`") && e.contains("time_budget"),
        "{e}"
    );
}

/// A frame in 2x2 tiles over one set of maps, with and without adaptive sampling (two
/// stages), and with other thread counts: the bits of the frame rendered whole.
#[test]
fn tiles_render_the_bits_of_the_whole_frame() {
    for name in ["cornell_spheres", "fog_glass"] {
        let desc = small(name);
        for adaptive in [true, false] {
            let mut s = settings(2);
            s.adaptive_sampling = adaptive;
            s.spp = 8;
            s.max_spp = 32;
            s.noise_threshold = 0.05;
            let whole = run(&desc, s.clone(), None);
            if adaptive {
                assert!(whole.stats.adaptive.unwrap().pixels_refined > 0);
            }
            let maps = render_request(RenderRequest {
                maps_only: true,
                ..RenderRequest::new(&desc, s.clone())
            })
            .unwrap()
            .photon_maps
            .unwrap();
            // Through the file form, as a farm would ship it.
            let maps = Arc::new(MapSet::from_bytes(&maps.to_bytes(), Path::new("m")).unwrap());
            let scene = Scene::build(&desc).unwrap();
            let keys = map_file::keys(&desc, &s);
            let tiles = tile::split(32, 24, 2, 2);
            let renderer = |threads: usize| {
                let mut t = s.clone();
                t.threads = threads;
                Renderer::new(&scene)
                    .settings(t)
                    .keys(keys)
                    .reuse_photon_maps(maps.clone())
            };
            let mut state = Vec::new();
            let mut rounds = None;
            if tile::two_stages(&s) {
                let (mut means, mut errors) = (
                    vec![Default::default(); 32 * 24],
                    vec![Default::default(); 32 * 24],
                );
                for (i, r) in tiles.iter().enumerate() {
                    let TileOutput::First {
                        means: m,
                        errors: e,
                        state: st,
                    } = renderer(1 + i % 2)
                        .render_tile(*r, TileStage::First)
                        .unwrap()
                    else {
                        panic!("first stage")
                    };
                    for (j, (mv, ev)) in m.into_iter().zip(e).enumerate() {
                        let (x, y) = (r.x + j % r.width, r.y + j / r.width);
                        means[y * 32 + x] = mv;
                        errors[y * 32 + x] = ev;
                    }
                    state.push(Some(st));
                }
                rounds = tile::adaptive_rounds(&s, &means, &errors, 32, 24).unwrap();
            } else {
                state = vec![None; tiles.len()];
            }
            let mut film = Film::new(32, 24);
            for (i, r) in tiles.iter().enumerate() {
                let tile_rounds = rounds.as_ref().map(|all: &Vec<u32>| {
                    let mut v = Vec::new();
                    for y in r.y..r.y + r.height {
                        v.extend_from_slice(&all[y * 32 + r.x..y * 32 + r.x + r.width]);
                    }
                    v
                });
                let stage = TileStage::Finish {
                    rounds: tile_rounds,
                    state: state[i].take(),
                };
                let TileOutput::Finished { film: f, .. } =
                    renderer(2 - i % 2).render_tile(*r, stage).unwrap()
                else {
                    panic!("finish stage")
                };
                tile::place(&mut film, *r, &f).unwrap();
            }
            assert!(
                bits(&film) == bits(&whole.film),
                "{name}, adaptive {adaptive}: tiles differ from the whole frame"
            );
        }
    }
}

/// A tile without the frame's maps, or outside the image, is an error.
#[test]
fn tiles_need_the_frames_maps() {
    let desc = small("cornell_diffuse");
    let scene = Scene::build(&desc).unwrap();
    let r = Rect {
        x: 0,
        y: 0,
        width: 8,
        height: 8,
    };
    let e = Renderer::new(&scene)
        .settings(settings(0))
        .render_tile(r, TileStage::First)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("photon maps"), "{e}");
    let e = Renderer::new(&scene)
        .settings(settings(0))
        .render_tile(Rect { x: 30, ..r }, TileStage::First)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("outside the 32x24 image"), "{e}");
}
