//! The Mix node.
//!
//! | parameter | meaning |
//! | --- | --- |
//! | data type | [`MixDataType`], RNA `data_type`: [`mix_float`], [`mix_vector`] / [`mix_vector_non_uniform`] (per [`MixFactorMode`], RNA `factor_mode`), [`mix_color`] |
//! | `mode` | [`BlendMode`], RNA `blend_type` (Color only) |
//! | `fac` | the Factor input (a `Vec3` for a non-uniform vector factor) |
//! | `a`, `b` | the A and B inputs |
//! | `clamp_factor` | RNA `clamp_factor`: clamp the factor to [0, 1] first |
//! | `clamp_result` | RNA `clamp_result`: clamp the colour result to [0, 1] (Color only) |
//!
//! The blend formulas are Cycles' (`svm_mix_*`); with factor outside [0, 1]
//! they extrapolate exactly as Cycles does.

use super::color::{hsv_to_rgb, rgb_to_hsv};
use super::math::{max_c, min_c, saturate};
use glam::Vec3;

/// Data type of the Mix node (RNA `data_type`; Rotation is not supported).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MixDataType {
    Float,
    Vector,
    Rgba,
}

impl MixDataType {
    pub fn from_blender(identifier: &str) -> Option<Self> {
        match identifier {
            "FLOAT" => Some(Self::Float),
            "VECTOR" => Some(Self::Vector),
            "RGBA" => Some(Self::Rgba),
            _ => None,
        }
    }
}

/// Factor mode of a vector Mix (RNA `factor_mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MixFactorMode {
    Uniform,
    NonUniform,
}

impl MixFactorMode {
    pub fn from_blender(identifier: &str) -> Option<Self> {
        match identifier {
            "UNIFORM" => Some(Self::Uniform),
            "NON_UNIFORM" => Some(Self::NonUniform),
            _ => None,
        }
    }
}

/// Colour blend mode (RNA `blend_type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BlendMode {
    Mix,
    Darken,
    Multiply,
    Burn,
    Lighten,
    Screen,
    Dodge,
    Add,
    Overlay,
    SoftLight,
    LinearLight,
    Difference,
    Exclusion,
    Subtract,
    Divide,
    Hue,
    Saturation,
    Color,
    Value,
}

impl BlendMode {
    /// Every mode, in Blender's menu order.
    pub const ALL: [BlendMode; 19] = [
        Self::Mix,
        Self::Darken,
        Self::Multiply,
        Self::Burn,
        Self::Lighten,
        Self::Screen,
        Self::Dodge,
        Self::Add,
        Self::Overlay,
        Self::SoftLight,
        Self::LinearLight,
        Self::Difference,
        Self::Exclusion,
        Self::Subtract,
        Self::Divide,
        Self::Hue,
        Self::Saturation,
        Self::Color,
        Self::Value,
    ];

    /// Blender's RNA identifier.
    pub fn blender_name(self) -> &'static str {
        use BlendMode::*;
        match self {
            Mix => "MIX",
            Darken => "DARKEN",
            Multiply => "MULTIPLY",
            Burn => "BURN",
            Lighten => "LIGHTEN",
            Screen => "SCREEN",
            Dodge => "DODGE",
            Add => "ADD",
            Overlay => "OVERLAY",
            SoftLight => "SOFT_LIGHT",
            LinearLight => "LINEAR_LIGHT",
            Difference => "DIFFERENCE",
            Exclusion => "EXCLUSION",
            Subtract => "SUBTRACT",
            Divide => "DIVIDE",
            Hue => "HUE",
            Saturation => "SATURATION",
            Color => "COLOR",
            Value => "VALUE",
        }
    }

    pub fn from_blender(identifier: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .copied()
            .find(|m| m.blender_name() == identifier)
    }
}

fn interp(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    a + t * (b - a)
}

fn map3(a: Vec3, b: Vec3, f: impl Fn(f32, f32) -> f32) -> Vec3 {
    Vec3::new(f(a.x, b.x), f(a.y, b.y), f(a.z, b.z))
}

fn saturate3(c: Vec3) -> Vec3 {
    Vec3::new(saturate(c.x), saturate(c.y), saturate(c.z))
}

/// One blend mode with factor `t` as given (Cycles `svm_mix`).
pub fn blend(mode: BlendMode, t: f32, c1: Vec3, c2: Vec3) -> Vec3 {
    use BlendMode::*;
    let tm = 1.0 - t;
    match mode {
        Mix => interp(c1, c2, t),
        Add => interp(c1, c1 + c2, t),
        Multiply => interp(c1, c1 * c2, t),
        Screen => Vec3::ONE - (Vec3::splat(tm) + t * (Vec3::ONE - c2)) * (Vec3::ONE - c1),
        Overlay => map3(c1, c2, |a, b| {
            if a < 0.5 {
                a * (tm + 2.0 * t * b)
            } else {
                1.0 - (tm + 2.0 * t * (1.0 - b)) * (1.0 - a)
            }
        }),
        Subtract => interp(c1, c1 - c2, t),
        Divide => map3(c1, c2, |a, b| if b != 0.0 { tm * a + t * a / b } else { a }),
        Difference => interp(c1, (c1 - c2).abs(), t),
        Exclusion => {
            let r = interp(c1, c1 + c2 - 2.0 * c1 * c2, t);
            Vec3::new(max_c(r.x, 0.0), max_c(r.y, 0.0), max_c(r.z, 0.0))
        }
        Darken => interp(c1, map3(c1, c2, min_c), t),
        Lighten => interp(c1, map3(c1, c2, max_c), t),
        Dodge => map3(c1, c2, |a, b| {
            if a == 0.0 {
                return a;
            }
            let tmp = 1.0 - t * b;
            if tmp <= 0.0 {
                return 1.0;
            }
            let q = a / tmp;
            if q > 1.0 {
                1.0
            } else {
                q
            }
        }),
        Burn => map3(c1, c2, |a, b| {
            let tmp = tm + t * b;
            if tmp <= 0.0 {
                return 0.0;
            }
            let q = 1.0 - (1.0 - a) / tmp;
            // Not f32::clamp: NaN must come out as it does in Cycles.
            #[allow(clippy::manual_clamp)]
            if q < 0.0 {
                0.0
            } else if q > 1.0 {
                1.0
            } else {
                q
            }
        }),
        Hue => {
            let hsv2 = rgb_to_hsv(c2);
            if hsv2.y != 0.0 {
                let mut hsv = rgb_to_hsv(c1);
                hsv.x = hsv2.x;
                interp(c1, hsv_to_rgb(hsv), t)
            } else {
                c1
            }
        }
        Saturation => {
            let mut hsv = rgb_to_hsv(c1);
            if hsv.y != 0.0 {
                let hsv2 = rgb_to_hsv(c2);
                hsv.y = tm * hsv.y + t * hsv2.y;
                hsv_to_rgb(hsv)
            } else {
                c1
            }
        }
        Value => {
            let mut hsv = rgb_to_hsv(c1);
            let hsv2 = rgb_to_hsv(c2);
            hsv.z = tm * hsv.z + t * hsv2.z;
            hsv_to_rgb(hsv)
        }
        Color => {
            let hsv2 = rgb_to_hsv(c2);
            if hsv2.y != 0.0 {
                let mut hsv = rgb_to_hsv(c1);
                hsv.x = hsv2.x;
                hsv.y = hsv2.y;
                interp(c1, hsv_to_rgb(hsv), t)
            } else {
                c1
            }
        }
        SoftLight => {
            let scr = Vec3::ONE - (Vec3::ONE - c2) * (Vec3::ONE - c1);
            tm * c1 + t * ((Vec3::ONE - c1) * c2 * c1 + c1 * scr)
        }
        LinearLight => c1 + t * (2.0 * c2 + Vec3::splat(-1.0)),
    }
}

/// The Mix node, Color data type.
pub fn mix_color(
    mode: BlendMode,
    fac: f32,
    a: Vec3,
    b: Vec3,
    clamp_factor: bool,
    clamp_result: bool,
) -> Vec3 {
    let t = if clamp_factor { saturate(fac) } else { fac };
    let r = blend(mode, t, a, b);
    if clamp_result {
        saturate3(r)
    } else {
        r
    }
}

/// The Mix node, Float data type.
pub fn mix_float(fac: f32, a: f32, b: f32, clamp_factor: bool) -> f32 {
    let t = if clamp_factor { saturate(fac) } else { fac };
    a * (1.0 - t) + b * t
}

/// The Mix node, Vector data type with a uniform factor.
pub fn mix_vector(fac: f32, a: Vec3, b: Vec3, clamp_factor: bool) -> Vec3 {
    let t = if clamp_factor { saturate(fac) } else { fac };
    a * (Vec3::ONE - Vec3::splat(t)) + b * t
}

/// The Mix node, Vector data type with a per-component factor.
pub fn mix_vector_non_uniform(fac: Vec3, a: Vec3, b: Vec3, clamp_factor: bool) -> Vec3 {
    let t = if clamp_factor { saturate3(fac) } else { fac };
    a * (Vec3::ONE - t) + b * t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::graph::ops::testutil::*;

    #[test]
    fn identifiers_round_trip() {
        for m in BlendMode::ALL {
            assert_eq!(BlendMode::from_blender(m.blender_name()), Some(m));
        }
        assert_eq!(MixDataType::from_blender("RGBA"), Some(MixDataType::Rgba));
        assert_eq!(
            MixFactorMode::from_blender("NON_UNIFORM"),
            Some(MixFactorMode::NonUniform)
        );
    }

    #[test]
    fn matches_cycles() {
        let data = parse(include_str!("testdata/mix.json"));
        let inp = &data["inputs"];
        let fac = floats(&inp["factor"]);
        let facv = vectors(&inp["factor_vector"]);
        let af = floats(&inp["a_float"]);
        let bf = floats(&inp["b_float"]);
        let a = vectors(&inp["a"]);
        let b = vectors(&inp["b"]);
        let mut bad = Vec::new();
        let mut modes = std::collections::HashSet::new();
        for case in data["cases"].as_array().expect("cases") {
            let dt =
                MixDataType::from_blender(case["data_type"].as_str().expect("dt")).expect("dt");
            let cf = case["clamp_factor"].as_bool().expect("bool");
            if dt == MixDataType::Float {
                for (i, r) in f32s(&case["result"]).into_iter().enumerate() {
                    let ours = mix_float(fac[i], af[i], bf[i], cf);
                    if !close(ours, r) {
                        bad.push(format!("float #{i}: {ours} vs {r:?}"));
                    }
                }
                continue;
            }
            let fm = case["factor_mode"]
                .as_str()
                .and_then(MixFactorMode::from_blender);
            let mode = case["blend_type"]
                .as_str()
                .and_then(BlendMode::from_blender);
            let cr = case["clamp_result"].as_bool().unwrap_or(false);
            if let Some(m) = mode {
                modes.insert(m);
            }
            for (i, r) in vec3s(&case["result"]).into_iter().enumerate() {
                let ours = match (dt, fm, mode) {
                    (MixDataType::Vector, Some(MixFactorMode::Uniform), _) => {
                        mix_vector(fac[i], a[i], b[i], cf)
                    }
                    (MixDataType::Vector, Some(MixFactorMode::NonUniform), _) => {
                        mix_vector_non_uniform(facv[i], a[i], b[i], cf)
                    }
                    (MixDataType::Rgba, _, Some(m)) => mix_color(m, fac[i], a[i], b[i], cf, cr),
                    other => panic!("unexpected case {other:?}"),
                };
                if !close3(ours, r) {
                    bad.push(format!(
                        "{dt:?} {fm:?} {mode:?} cf={cf} cr={cr} #{i} fac={} a={} b={}: {ours} vs {r:?}",
                        fac[i], a[i], b[i]
                    ));
                }
            }
        }
        assert_eq!(modes.len(), BlendMode::ALL.len());
        assert!(
            bad.is_empty(),
            "{} mismatches:\n{}",
            bad.len(),
            bad.join("\n")
        );
    }

    #[test]
    fn non_finite_inputs_do_not_panic() {
        for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let v = Vec3::new(x, 0.0, 1.0);
            for m in BlendMode::ALL {
                let _ = mix_color(m, x, v, v, false, true);
            }
            let _ = mix_float(x, x, 1.0, true);
            let _ = mix_vector_non_uniform(v, v, v, true);
        }
    }
}
