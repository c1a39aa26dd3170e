//! The schema's vocabulary: what kind of value a setting takes, its choices, its range and
//! panel ([`Spec`]), and the value types of the settings that are not plain numbers.

use super::{parse_bytes, Quality, RenderMode};
pub use crate::render::aov::Cryptomatte;
use crate::render::film::Filter;
use clap::ValueEnum;
use serde::{Deserialize, Serialize};

/// The value a setting takes, for front ends that build widgets from the schema.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    Int,
    Float,
    Bool,
    /// One of named choices.
    Enum,
    /// A byte count: an integer, or a string with a binary suffix (`512M`, `8G`).
    Size,
    /// A file path.
    Path,
}

/// One choice of an enumerated setting. A variant's doc comment `Label: description` gives
/// both; without a short label before `: `, the label is the capitalised name.
#[derive(Clone, Debug, Serialize)]
pub struct Choice {
    pub name: String,
    pub label: String,
    pub doc: String,
}

impl Choice {
    fn new(name: &str, help: &str) -> Choice {
        let (label, doc) = match help.split_once(": ") {
            Some((l, d)) if l.len() <= 24 => (l.to_string(), d.to_string()),
            _ => {
                let mut c = name.chars();
                let cap = c.next().map(|f| f.to_uppercase().chain(c).collect());
                (cap.unwrap_or_default(), help.to_string())
            }
        };
        Choice {
            name: name.to_string(),
            label,
            doc,
        }
    }
}

/// The type of a setting's field, as the schema names it.
pub trait OptionValue {
    /// The setting may be left unset (`None`).
    const OPTIONAL: bool = false;
    fn kind() -> Kind;
    fn choices() -> Vec<Choice> {
        Vec::new()
    }
    /// The value as a number, for range checks; `None` for non-numbers and unset values.
    fn number(&self) -> Option<f64> {
        None
    }
}

macro_rules! numeric {
    ($kind:ident: $($t:ty),*) => {$(
        impl OptionValue for $t {
            fn kind() -> Kind { Kind::$kind }
            fn number(&self) -> Option<f64> { Some(*self as f64) }
        }
    )*};
}
numeric!(Int: u32, u64, usize);

impl OptionValue for std::path::PathBuf {
    fn kind() -> Kind {
        Kind::Path
    }
}
numeric!(Float: f32, f64);

impl OptionValue for bool {
    fn kind() -> Kind {
        Kind::Bool
    }
}

impl<T: OptionValue> OptionValue for Option<T> {
    const OPTIONAL: bool = true;
    fn kind() -> Kind {
        T::kind()
    }
    fn choices() -> Vec<Choice> {
        T::choices()
    }
    fn number(&self) -> Option<f64> {
        self.as_ref().and_then(T::number)
    }
}

macro_rules! enumerated {
    ($($t:ty),*) => {$(
        impl OptionValue for $t {
            fn kind() -> Kind { Kind::Enum }
            fn choices() -> Vec<Choice> {
                <$t as ValueEnum>::value_variants()
                    .iter()
                    .filter_map(|v| v.to_possible_value())
                    .map(|p| {
                        let help = p.get_help().map(|h| h.to_string()).unwrap_or_default();
                        Choice::new(p.get_name(), &help)
                    })
                    .collect()
            }
        }
    )*};
}
enumerated!(
    Quality,
    RenderMode,
    FilterName,
    PhotonPower,
    OnMismatch,
    Cryptomatte
);

/// Pixel reconstruction filters by name (their widths are the core's).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum FilterName {
    /// Box: uniform over the pixel (Cycles' Box filter of width 1 px).
    Box,
    /// Tent: a triangle of radius 1 px.
    Tent,
    /// Gaussian: standard deviation 0.5 px, truncated at 3 sigma.
    Gaussian,
}

impl FilterName {
    pub fn filter(self) -> Filter {
        match self {
            FilterName::Box => Filter::Box,
            FilterName::Tent => Filter::Tent { radius: 1.0 },
            FilterName::Gaussian => Filter::gaussian(0.5),
        }
    }
}

/// How a stored photon's power is encoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum PhotonPower {
    /// RGBE: 20-byte photons, the power in Ward's shared exponent.
    Rgbe,
    /// Float: 28-byte photons, the power unquantised.
    F32,
}

impl PhotonPower {
    /// The encoding's name: `rgbe` or `f32`.
    pub fn name(self) -> &'static str {
        match self {
            PhotonPower::Rgbe => "rgbe",
            PhotonPower::F32 => "f32",
        }
    }
}

/// A byte count, read from an integer or from a size such as `512M` or `8G`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(transparent)]
pub struct Bytes(pub u64);

impl OptionValue for Bytes {
    fn kind() -> Kind {
        Kind::Size
    }
}

impl<'de> Deserialize<'de> for Bytes {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Raw {
            N(u64),
            S(String),
        }
        match Raw::deserialize(d).map_err(|_| {
            serde::de::Error::custom("expected a number of bytes or a size such as 512M or 8G")
        })? {
            Raw::N(n) => Ok(Bytes(n)),
            Raw::S(s) => parse_bytes(&s).map(Bytes).map_err(serde::de::Error::custom),
        }
    }
}

pub(super) fn parse_bytes_arg(s: &str) -> std::result::Result<Bytes, String> {
    parse_bytes(s).map(Bytes)
}

pub(super) fn parse_time_budget(s: &str) -> std::result::Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a number of seconds (0 = off)"))?;
    check_budget(v)?;
    Ok(v)
}

pub(super) fn parse_on_off(s: &str) -> std::result::Result<bool, String> {
    match s {
        "on" | "true" | "1" => Ok(true),
        "off" | "false" | "0" => Ok(false),
        _ => Err(format!("expected on or off, got `{s}`")),
    }
}

/// The panel a setting shows in (Blender) and the group it is listed under.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Group {
    Quality,
    Photons,
    Gathering,
    /// The optional AOVs (compositing passes) and denoising.
    Passes,
}

/// What the schema says of one setting besides its type, documentation and default.
#[derive(Clone, Copy, Debug)]
pub struct Spec {
    /// Short label (Blender's property name).
    pub label: &'static str,
    pub group: Group,
    /// Smallest value; `min_open` excludes it.
    pub min: Option<f64>,
    pub min_open: bool,
    /// Largest value; `max_open` excludes it.
    pub max: Option<f64>,
    pub max_open: bool,
    /// Largest value a slider offers (larger ones can be typed).
    pub soft_max: Option<f64>,
    /// `distance` (scene units) or `seconds`.
    pub unit: Option<&'static str>,
    /// A quality preset sets this field.
    pub preset: bool,
    /// The setting applies in these modes only (empty: in every mode).
    pub modes: &'static [RenderMode],
    /// The setting applies only while this boolean setting is on.
    pub requires: Option<&'static str>,
}

impl Spec {
    pub(super) const BASE: Spec = Spec {
        label: "",
        group: Group::Quality,
        min: None,
        min_open: false,
        max: None,
        max_open: false,
        soft_max: None,
        unit: None,
        preset: false,
        modes: &[],
        requires: None,
    };

    /// Why `v` is out of range, if it is.
    pub(super) fn out_of_range(&self, v: f64, kind: &Kind) -> Option<String> {
        let low = self.min.is_some_and(|m| v < m || (self.min_open && v == m));
        let high = self.max.is_some_and(|m| v > m || (self.max_open && v == m));
        if v.is_finite() && !low && !high {
            return None;
        }
        let fmt = |b: f64| format!("{b}");
        Some(match (self.min, self.max) {
            (Some(a), Some(b)) => format!(
                "must be in {}{}, {}{}",
                if self.min_open { "(" } else { "[" },
                fmt(a),
                fmt(b),
                if self.max_open { ")" } else { "]" }
            ),
            (Some(a), None) if *kind == Kind::Int => format!("must be at least {}", fmt(a)),
            (Some(a), None) => format!(
                "must be a finite number {} {}",
                if self.min_open { ">" } else { ">=" },
                fmt(a)
            ),
            _ => "must be a finite number".to_string(),
        })
    }
}

/// One setting of the schema, as `settings_schema()` exports it.
pub struct Field {
    pub name: &'static str,
    pub doc: String,
    pub kind: Kind,
    pub choices: Vec<Choice>,
    pub optional: bool,
    pub spec: Spec,
}

/// Checks a time budget's value (`time_budget`).
pub fn check_budget(seconds: f64) -> Result<(), String> {
    if !seconds.is_finite() || seconds < 0.0 {
        return Err(format!(
            "`{seconds}` is not a time budget: expected a finite number of seconds >= 0 (0 = off)"
        ));
    }
    Ok(())
}

/// What to do when loaded photon maps do not match the render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum OnMismatch {
    /// Error: stop with an error that says what differs.
    #[default]
    Error,
    /// Rebuild: build the maps again (and save them where asked), noting why in the stats.
    Rebuild,
}

/// Photon-map files of a render (Jensen's mode).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MapFiles {
    /// Save the photon maps and the irradiance cache to this file.
    pub save: Option<std::path::PathBuf>,
    /// Load them from this file instead of building them.
    pub load: Option<std::path::PathBuf>,
    pub on_mismatch: OnMismatch,
}
