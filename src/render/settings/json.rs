//! The settings as JSON: read from the Python keywords (and the partial sums' record), checked
//! against the schema's ranges, and written for the schema, the stats and the presets.

use super::*;

impl RenderSettings {
    /// Reads settings from a JSON object of keywords. A `null` value is the default; a preset
    /// field not given takes the `quality` preset's value; an unknown keyword or a bad value
    /// is an error that names it.
    pub fn from_json(text: &str) -> Result<RenderSettings> {
        let bad = |setting: &str, message: String| Error::InvalidSetting {
            setting: setting.into(),
            message,
        };
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| bad("settings", e.to_string()))?;
        let serde_json::Value::Object(map) = value else {
            return Err(bad("settings", "expected an object of settings".into()));
        };
        let names: Vec<&str> = Self::fields().iter().map(|f| f.name).collect();
        let mut given = serde_json::Map::new();
        for (k, v) in map {
            if !names.contains(&k.as_str()) {
                return Err(Error::UnknownSetting {
                    setting: k,
                    known: names.join(", "),
                });
            }
            if v.is_null() {
                continue;
            }
            // One key at a time, so that a bad value's error names its setting.
            let one = serde_json::Value::Object([(k.clone(), v.clone())].into_iter().collect());
            serde_json::from_value::<RenderSettings>(one).map_err(|e| bad(&k, strip_serde(e)))?;
            given.insert(k, v);
        }
        let names_given: Vec<String> = given.keys().cloned().collect();
        let mut s: RenderSettings = serde_json::from_value(serde_json::Value::Object(given))
            .map_err(|e| bad("settings", e.to_string()))?;
        s.apply_preset(|name| names_given.iter().any(|g| g == name));
        s.validate()?;
        Ok(s)
    }

    /// Checks every value against its range in the schema; the error names the setting.
    pub fn validate(&self) -> Result<()> {
        let fields = Self::fields();
        for (name, value) in self.numbers() {
            let (Some(v), Some(f)) = (value, fields.iter().find(|f| f.name == name)) else {
                continue;
            };
            if let Some(message) = f.spec.out_of_range(v, &f.kind) {
                return Err(Error::InvalidSetting {
                    setting: name.into(),
                    message,
                });
            }
        }
        if let Some(b) = self.time_budget {
            check_budget(b).map_err(|message| Error::InvalidSetting {
                setting: "time_budget".into(),
                message,
            })?;
        }
        Ok(())
    }

    /// The schema as JSON: one object per setting, in field order, with its name, command-line
    /// flag (and whether it is a switch, which takes no value), label, documentation, type (and choices), default (a preset field's is the
    /// default preset's value), range, unit, group and the mode or switch it applies under.
    pub fn schema() -> serde_json::Value {
        let defaults = RenderSettings::default().to_json();
        let cmd = RenderSettings::augment_args(clap::Command::new("photonmap"));
        let switch = |name: &str| {
            cmd.get_arguments()
                .find(|a| a.get_id() == name)
                .is_some_and(|a| !a.get_action().takes_values())
        };
        let fields: Vec<serde_json::Value> = Self::fields()
            .into_iter()
            .map(|f| {
                serde_json::json!({
                    "name": f.name,
                    "flag": format!("--{}", f.name.replace('_', "-")),
                    "switch": switch(f.name),
                    "label": f.spec.label,
                    "doc": f.doc,
                    "type": f.kind,
                    "choices": f.choices,
                    "optional": f.optional,
                    "default": defaults[f.name],
                    "min": f.spec.min,
                    "min_open": f.spec.min_open,
                    "max": f.spec.max,
                    "max_open": f.spec.max_open,
                    "soft_max": f.spec.soft_max,
                    "unit": f.spec.unit,
                    "preset": f.spec.preset,
                    "group": f.spec.group,
                    "modes": f.spec.modes,
                    "requires": f.spec.requires,
                })
            })
            .collect();
        serde_json::Value::Array(fields)
    }

    /// The settings as JSON, each `f32` written as its shortest decimal (0.1, not the
    /// 0.100000001 of widening it to `f64`).
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::to_string(self)
            .and_then(|t| serde_json::from_str(&t))
            .unwrap_or_else(|e| unreachable!("settings serialise: {e}"))
    }

    /// The schema fields as JSON, named as the keywords: `photonmap.render(scene, **this)`
    /// and `from_json` give these settings again (the internal fields aside).
    pub fn options_json(&self) -> serde_json::Value {
        let all = self.to_json();
        let map = Self::fields()
            .into_iter()
            .map(|f| (f.name.to_string(), all[f.name].clone()))
            .collect();
        serde_json::Value::Object(map)
    }

    /// The preset fields of `quality`'s settings, by name (Python's `preset()`).
    pub fn preset_json(quality: Quality) -> serde_json::Value {
        let all = RenderSettings::preset(quality).to_json();
        let map = Self::fields()
            .into_iter()
            .filter(|f| f.spec.preset)
            .map(|f| (f.name.to_string(), all[f.name].clone()))
            .collect();
        serde_json::Value::Object(map)
    }
}

/// serde's message without its position in the one-key document (`at line 1 column 9`).
fn strip_serde(e: serde_json::Error) -> String {
    let s = e.to_string();
    match s.find(" at line ") {
        Some(i) => s[..i].to_string(),
        None => s,
    }
}
