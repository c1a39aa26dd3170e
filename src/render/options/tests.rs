//! Tests of the settings schema.

use super::*;
use clap::{CommandFactory, Parser};

/// Every field is a flag of the `render` command named after it, with the field's default.
#[test]
fn every_field_is_a_flag_of_the_same_name_and_default() {
    let cmd = crate::cli::Cli::command();
    let render = cmd.find_subcommand("render").expect("render command");
    let defaults = serde_json::to_value(RenderOptions::default()).unwrap();
    for f in RenderOptions::fields() {
        let arg = render
            .get_arguments()
            .find(|a| a.get_id() == f.name)
            .unwrap_or_else(|| panic!("no flag for {}", f.name));
        assert_eq!(arg.get_long(), Some(f.name.replace('_', "-").as_str()));
        let flag_default: Vec<String> = arg
            .get_default_values()
            .iter()
            .map(|v| v.to_string_lossy().into_owned())
            .collect();
        let d = &defaults[f.name];
        if !arg.get_action().takes_values() {
            assert_eq!(d, false, "{}: a switch is off by default", f.name);
            continue;
        }
        match flag_default.as_slice() {
            [] => assert!(d.is_null(), "{}: {d}", f.name),
            [v] => {
                let parsed: RenderOptions =
                    serde_json::from_value(serde_json::json!({ f.name: d })).unwrap();
                let cli = crate::cli::Cli::try_parse_from([
                    "photonmap",
                    "render",
                    "-o",
                    "x.exr",
                    &format!("--{}={v}", f.name.replace('_', "-")),
                ])
                .unwrap();
                let crate::cli::Command::Render(a) = cli.command else {
                    unreachable!("`render` parses as the render command")
                };
                assert_eq!(a.options, parsed, "{}", f.name);
            }
            more => panic!("{}: several defaults {more:?}", f.name),
        }
        assert!(!f.doc.is_empty() && !f.spec.label.is_empty(), "{}", f.name);
    }
}

#[test]
fn the_default_options_render_the_medium_preset() {
    let s = RenderOptions::default().settings();
    let m = Quality::Medium.settings();
    assert_eq!(s.spp, m.spp);
    assert_eq!(s.photons, m.photons);
    for q in Quality::ALL {
        let a = RenderOptions::preset(q).settings();
        let b = RenderOptions {
            quality: q,
            ..RenderOptions::default()
        }
        .settings();
        assert_eq!(format!("{a:?}"), format!("{b:?}"), "{q:?}");
    }
}

/// The options recorded from a render's settings give those settings again.
#[test]
fn settings_round_trip_through_options() {
    let o = RenderOptions::from_json(
        r#"{"quality": "draft", "spp": 3, "radius": 0.25, "filter": "tent", "mode": "sppm",
            "alpha": 0.5, "photon_power": "f32", "memory_limit": 12345, "threads": 1}"#,
    )
    .unwrap();
    let s = o.settings();
    let again = RenderOptions::from_settings(&s);
    assert_eq!(format!("{:?}", again.settings()), format!("{s:?}"));
    let text = serde_json::to_string(&again).unwrap();
    let back = RenderOptions::from_json(&text).unwrap();
    assert_eq!(format!("{:?}", back.settings()), format!("{s:?}"));
}

#[test]
fn keywords_are_read_by_name_and_bad_ones_named() {
    let o = RenderOptions::from_json(
        r#"{"spp": 4, "quality": "draft", "memory_limit": "8G", "radius": null,
            "filter": "box", "photon_power": "f32", "irradiance_cache": false}"#,
    )
    .unwrap();
    assert_eq!(o.spp, Some(4));
    assert_eq!(o.quality, Quality::Draft);
    assert_eq!(o.memory_limit, Some(Bytes(8 << 30)));
    assert!(o.settings().photons.f32_power && !o.settings().photons.irradiance_cache);
    let err = |t: &str| RenderOptions::from_json(t).unwrap_err().to_string();
    assert!(err(r#"{"spps": 4}"#).contains("`spps`"));
    assert!(err(r#"{"spp": "many"}"#).contains("`spp`"));
    assert!(err(r#"{"spp": 0}"#).contains("`spp`: must be at least 1"));
    assert!(err(r#"{"alpha": 1.0}"#).contains("`alpha`: must be in (0, 1)"));
    assert!(err(r#"{"radius": -1}"#).contains("`radius`: must be a finite number > 0"));
    assert!(err(r#"{"quality": "best"}"#).contains("`quality`"));
    assert!(err(r#"{"memory_limit": "8X"}"#).contains("`memory_limit`"));
    assert!(err(r#"{"time_budget": -1}"#).contains("`time_budget`"));
}

#[test]
fn the_schema_lists_every_field_once_with_its_default() {
    let schema = RenderOptions::schema();
    let list = schema.as_array().unwrap();
    assert_eq!(list.len(), RenderOptions::fields().len());
    let get = |n: &str| list.iter().find(|f| f["name"] == n).unwrap().clone();
    assert_eq!(get("spp")["default"], Quality::Medium.spp());
    assert_eq!(get("quality")["choices"].as_array().unwrap().len(), 4);
    assert_eq!(get("memory_limit")["type"], "size");
    assert_eq!(get("alpha")["modes"], serde_json::json!(["sppm", "pppm"]));
    assert_eq!(get("save_photon_maps")["type"], "path");
    assert_eq!(get("initial_radius")["modes"], serde_json::json!(["pppm"]));
    assert_eq!(get("radius")["unit"], "distance");
}

/// The options given nothing (the command without flags, Python without keywords) give the
/// settings of a `Renderer` given none, field for field (the memory limit aside: the options
/// read the machine's available memory).
#[test]
fn no_options_give_the_default_settings() {
    let mut s = RenderOptions::default().settings();
    s.memory_limit = None;
    assert_eq!(
        format!("{s:?}"),
        format!("{:?}", crate::render::RenderSettings::default())
    );
}
