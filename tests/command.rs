//! The render and merge commands (`photonmap::command`), as the development binary and the
//! Python package's `photonmap` command run them: a pppm frame rendered in blocks of passes
//! and merged reports what the frame rendered whole reports (the same keys, the same
//! settings), and writes the same bits.

use crate::common;

use clap::Parser;
use common::data;
use photonmap::cli::{Cli, Command, MergeArgs, RenderArgs};
use photonmap::command::exr::read_rgb_layers;
use photonmap::command::{self, Frontend};
use photonmap::render::RenderStats;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn render(scene: &Path, out: &Path, extra: &[&str]) {
    let (scene, out) = (scene.to_string_lossy(), out.to_string_lossy());
    let mut argv = vec!["photonmap", "render", &scene, "-o", &out];
    argv.extend_from_slice(&[
        "--width",
        "32",
        "--height",
        "24",
        "--mode",
        "pppm",
        "--spp",
        "6",
        "--photons",
        "5000",
        "--seed",
        "3",
        // The default is the memory available when the render starts, which varies.
        "--memory-limit",
        "8G",
        "--quiet",
    ]);
    argv.extend_from_slice(extra);
    let args: RenderArgs = match Cli::try_parse_from(&argv)
        .expect("the command parses")
        .command
    {
        Command::Render(a) => a,
        Command::Merge(_) => unreachable!("`render` parses as the render command"),
    };
    if let Err(f) = command::run_render(&args, Frontend::default()) {
        panic!("{argv:?}: {f}");
    }
}

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("the stats are written"))
        .expect("the stats are JSON")
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("photonmap-command-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("a temporary directory");
    d
}

#[test]
fn a_merged_pppm_frame_reports_what_the_whole_frame_does() {
    let d = dir("merge");
    let scene = data("scenes/cornell_spheres.json");
    render(
        &scene,
        &d.join("whole.exr"),
        &["--stats", &d.join("whole.json").to_string_lossy()],
    );
    render(&scene, &d.join("a.ppart"), &["--pass-range", "0:3"]);
    render(&scene, &d.join("b.ppart"), &["--pass-range", "3:6"]);
    let merge = MergeArgs {
        partials: vec![d.join("a.ppart"), d.join("b.ppart")],
        output: d.join("merged.exr"),
        png: None,
        stats: Some(d.join("merged.json")),
        quiet: true,
    };
    let merged = command::run_merge(&merge).expect("the blocks merge");
    assert_eq!(merged.passes(), 6);

    let (whole_img, _) = read_rgb_layers(d.join("whole.exr")).expect("reads");
    let (merged_img, _) = read_rgb_layers(d.join("merged.exr")).expect("reads");
    for (layer, img) in &whole_img {
        let bits = |i: &photonmap::render::film::Image| {
            i.data
                .iter()
                .flat_map(|p| p.map(f32::to_bits))
                .collect::<Vec<_>>()
        };
        assert!(
            bits(img) == bits(&merged_img[layer]),
            "layer `{layer}` differs"
        );
    }

    let (whole, merged) = (json(&d.join("whole.json")), json(&d.join("merged.json")));
    let keys = |v: &Value| v.as_object().unwrap().keys().cloned().collect::<Vec<_>>();
    assert_eq!(keys(&merged), keys(&whole));
    assert_eq!(merged["settings"], whole["settings"]);
    assert_eq!(merged["options"], whole["options"]);
    for k in [
        "version",
        "mode",
        "seed",
        "width",
        "height",
        "spp",
        "camera_rays",
        "photons_stored",
        "irradiance_cache_records",
        "non_finite_samples",
        "aov_memory_bytes",
        "bytes_per_photon",
        "bytes_per_triangle",
    ] {
        assert_eq!(merged[k], whole[k], "{k}");
    }
    // The last pass's photon maps, as the whole render reports them (timings aside).
    let maps = |v: &Value| {
        v["photon_maps"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| {
                (
                    m["map"].clone(),
                    m["stored"].clone(),
                    m["skipped_because"].clone(),
                )
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(maps(&merged), maps(&whole));
    for k in [
        "passes",
        "pass_ranges",
        "alpha",
        "initial_radius",
        "initial_radius_source",
        "final_radius",
        "photons_per_pass",
        "photons_emitted",
    ] {
        assert_eq!(merged["pppm"][k], whole["pppm"][k], "pppm.{k}");
    }
    assert_eq!(merged["pppm"]["partials"], 2);
    // The partial sums carry nothing of the scene or the machine: those figures are null.
    for k in RenderStats::SCENE_FIGURES {
        assert!(merged[*k].is_null(), "{k}: {}", merged[*k]);
        assert!(!whole[*k].is_null(), "{k}");
    }
    std::fs::remove_dir_all(&d).ok();
}
