//! Tests of the settings schema.

use super::*;
use crate::render::map_key;
use clap::CommandFactory;

/// The settings of the `render` command's flags `flags`.
fn command_line(flags: &[String]) -> RenderSettings {
    let mut argv = vec![
        "photonmap".to_string(),
        "render".into(),
        "-o".into(),
        "x.exr".into(),
    ];
    argv.extend(flags.iter().cloned());
    let cli = crate::cli::Cli::parse_args(argv).unwrap_or_else(|e| panic!("{flags:?}: {e}"));
    let crate::cli::Command::Render(a) = cli.command else {
        unreachable!("`render` parses as the render command")
    };
    a.options
}

/// Every field is a flag of the `render` command named after it, with the field's default.
#[test]
fn every_field_is_a_flag_of_the_same_name_and_default() {
    let cmd = crate::cli::Cli::command();
    let render = cmd.find_subcommand("render").expect("render command");
    let defaults = RenderSettings::default().to_json();
    for f in RenderSettings::fields() {
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
                let parsed: RenderSettings =
                    serde_json::from_value(serde_json::json!({ f.name: d })).unwrap();
                let flag = format!("--{}={v}", f.name.replace('_', "-"));
                assert_eq!(command_line(&[flag]), parsed, "{}", f.name);
            }
            more => panic!("{}: several defaults {more:?}", f.name),
        }
        assert!(!f.doc.is_empty() && !f.spec.label.is_empty(), "{}", f.name);
    }
}

/// A quality preset is the settings of its name given alone, through the keywords and the
/// flags; it changes the preset fields and no other; the default is `medium`.
#[test]
fn presets_are_values_of_the_settings() {
    assert_eq!(
        RenderSettings::preset(Quality::Medium),
        RenderSettings::default()
    );
    assert_eq!(
        RenderSettings::from_json("{}").unwrap(),
        RenderSettings::default()
    );
    let base = RenderSettings::default().to_json();
    for q in Quality::ALL {
        let p = RenderSettings::preset(q);
        assert_eq!(p.quality, q);
        let json = format!(r#"{{"quality": "{}"}}"#, q.name());
        assert_eq!(RenderSettings::from_json(&json).unwrap(), p, "{q:?}");
        assert_eq!(
            command_line(&[format!("--quality={}", q.name())]),
            p,
            "{q:?}"
        );
        let v = p.to_json();
        for f in RenderSettings::fields() {
            if !f.spec.preset && f.name != "quality" {
                assert_eq!(v[f.name], base[f.name], "{q:?} sets {}", f.name);
            }
        }
    }
    assert_ne!(
        RenderSettings::preset(Quality::Draft).spp,
        RenderSettings::preset(Quality::High).spp
    );
}

/// A setting given (keyword or flag) is kept over the preset; the preset fields not given
/// take the preset's values.
#[test]
fn given_settings_win_over_the_preset() {
    let draft = RenderSettings::preset(Quality::Draft);
    let k = RenderSettings::from_json(r#"{"quality": "draft", "spp": 3, "gather": null}"#).unwrap();
    let c = command_line(&["--spp=3".into(), "--quality=draft".into()]);
    for s in [&k, &c] {
        assert_eq!(s.spp, 3);
        assert_eq!(s.photons, draft.photons);
        assert_eq!(s.cache_tolerance, draft.cache_tolerance);
    }
    assert_eq!(k, c);
    // A flag given at the default preset's value is still given.
    let h = command_line(&["--quality=high".into(), "--spp=32".into()]);
    assert_eq!(
        (h.spp, h.photons),
        (32, RenderSettings::preset(Quality::High).photons)
    );
}

/// A value for every schema field other than its default, as a keyword's JSON.
fn changed_value(f: &Field, default: &serde_json::Value) -> serde_json::Value {
    use serde_json::json;
    match (&f.kind, default) {
        (Kind::Bool, d) => json!(!d.as_bool().unwrap_or(false)),
        (Kind::Enum, d) => {
            let other = f
                .choices
                .iter()
                .find(|c| json!(c.name) != *d)
                .expect("choices");
            json!(other.name)
        }
        (Kind::Int, d) => json!(d.as_u64().unwrap_or(0) + 1),
        (Kind::Float, d) => match d.as_f64() {
            Some(v) if v != 0.0 => json!(v * 0.5),
            _ => json!(1.0),
        },
        (Kind::Size, _) => json!("8G"),
        (Kind::Path, _) => json!("maps.pmap"),
    }
}

/// Every setting round-trips through the keywords, the flags and the settings a render
/// records, and changes the render key unless it is one of `map_key::NOT_IN_IMAGE`, and the
/// photon-map key unless it is one of those or of `map_key::NOT_IN_MAPS`. No list names the
/// settings: a new field is covered as it is added.
#[test]
fn every_setting_round_trips_and_is_in_the_keys() {
    let desc = crate::scene::default_scene();
    let base = RenderSettings::default();
    let defaults = base.to_json();
    let keys = |s: &RenderSettings| map_key::keys(&desc, s);
    let k0 = keys(&base);
    for f in RenderSettings::fields() {
        let v = changed_value(&f, &defaults[f.name]);
        let json = serde_json::json!({ f.name: v }).to_string();
        let s = RenderSettings::from_json(&json).unwrap_or_else(|e| panic!("{json}: {e}"));
        assert_ne!(s.to_json()[f.name], defaults[f.name], "{json}");
        let flag = f.name.replace('_', "-");
        let arg = match &v {
            serde_json::Value::Bool(true) if f.spec.preset => format!("--{flag}=on"),
            serde_json::Value::Bool(false) => format!("--{flag}=off"),
            serde_json::Value::Bool(true) => format!("--{flag}"),
            serde_json::Value::String(t) => format!("--{flag}={t}"),
            n => format!("--{flag}={n}"),
        };
        assert_eq!(command_line(&[arg]), s, "{}", f.name);
        let again = RenderSettings::from_json(&s.options_json().to_string()).unwrap();
        assert_eq!(again, s, "{}", f.name);
        let k = keys(&s);
        // `quality` is named in neither key; its preset's values are.
        let in_image = !map_key::NOT_IN_IMAGE.contains(&f.name) || f.name == "quality";
        let in_maps = in_image && !map_key::NOT_IN_MAPS.contains(&f.name);
        assert_eq!(k.render != k0.render, in_image, "{}: render key", f.name);
        assert_eq!(k.maps != k0.maps, in_maps, "{}: photon-map key", f.name);
    }
    for name in map_key::NOT_IN_IMAGE.iter().chain(&map_key::NOT_IN_MAPS) {
        assert!(defaults.get(*name).is_some(), "{name} is a setting");
    }
}

#[test]
fn keywords_are_read_by_name_and_bad_ones_named() {
    let o = RenderSettings::from_json(
        r#"{"spp": 4, "quality": "draft", "memory_limit": "8G", "radius": null,
            "filter": "box", "photon_power": "f32", "irradiance_cache": false}"#,
    )
    .unwrap();
    assert_eq!(o.spp, 4);
    assert_eq!(o.quality, Quality::Draft);
    assert_eq!(o.memory_limit, Some(Bytes(8 << 30)));
    assert!(o.f32_power() && !o.irradiance_cache);
    let err = |t: &str| RenderSettings::from_json(t).unwrap_err().to_string();
    assert!(err(r#"{"spps": 4}"#).contains("`spps`"));
    assert!(err(r#"{"spp": "many"}"#).contains("`spp`"));
    assert!(err(r#"{"spp": 0}"#).contains("`spp`: must be at least 1"));
    assert!(err(r#"{"alpha": 1.0}"#).contains("`alpha`: must be in (0, 1)"));
    assert!(err(r#"{"radius": -1}"#).contains("`radius`: must be a finite number > 0"));
    assert!(err(r#"{"quality": "best"}"#).contains("`quality`"));
    assert!(err(r#"{"memory_limit": "8X"}"#).contains("`memory_limit`"));
    assert!(err(r#"{"time_budget": -1}"#).contains("`time_budget`"));
    // The engine's own fields are no keywords.
    assert!(err(r#"{"terms": []}"#).contains("`terms`"));
    assert!(err(r#"{"max_bounces": 3}"#).contains("`max_bounces`"));
}

#[test]
fn the_schema_lists_every_field_once_with_its_default() {
    let schema = RenderSettings::schema();
    let list = schema.as_array().unwrap();
    assert_eq!(list.len(), RenderSettings::fields().len());
    let get = |n: &str| list.iter().find(|f| f["name"] == n).unwrap().clone();
    assert_eq!(get("spp")["default"], RenderSettings::default().spp);
    assert_eq!(get("quality")["choices"].as_array().unwrap().len(), 4);
    assert_eq!(get("memory_limit")["type"], "size");
    assert_eq!(get("alpha")["modes"], serde_json::json!(["sppm", "pppm"]));
    assert_eq!(get("save_photon_maps")["type"], "path");
    assert_eq!(get("initial_radius")["modes"], serde_json::json!(["pppm"]));
    assert_eq!(get("radius")["unit"], "distance");
    assert!(get("spp")["preset"].as_bool().unwrap());
    assert!(list.iter().all(|f| f["name"] != "terms"));
    assert_eq!(get("progressive")["switch"], true);
    assert_eq!(get("adaptive_sampling")["switch"], false);
}
