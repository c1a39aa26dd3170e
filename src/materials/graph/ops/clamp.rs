//! The Clamp node.
//!
//! | parameter | meaning |
//! | --- | --- |
//! | `clamp_type` | [`ClampType`], RNA `clamp_type` |
//! | `value`, `min`, `max` | the Value, Min and Max inputs |
//!
//! Min Max clamps as `min(max(value, min), max)` (so `max` wins when
//! `min > max`); Range swaps the bounds when `min > max`.

use super::math::clamp_c;

/// Clamp type (RNA `clamp_type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ClampType {
    MinMax,
    Range,
}

impl ClampType {
    /// From Blender's RNA identifier (`"MINMAX"`, `"RANGE"`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        match identifier {
            "MINMAX" => Some(Self::MinMax),
            "RANGE" => Some(Self::Range),
            _ => None,
        }
    }
}

/// The Clamp node.
pub fn clamp_node(clamp_type: ClampType, value: f32, min: f32, max: f32) -> f32 {
    if clamp_type == ClampType::Range && min > max {
        clamp_c(value, max, min)
    } else {
        clamp_c(value, min, max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::graph::ops::testutil::*;

    #[test]
    fn matches_cycles() {
        let data = parse(include_str!("testdata/clamp.json"));
        let v = floats(&data["inputs"]["value"]);
        let mut bad = Vec::new();
        for case in data["cases"].as_array().expect("cases") {
            let t =
                ClampType::from_blender(case["clamp_type"].as_str().expect("type")).expect("type");
            let lo = case["min"].as_f64().expect("min") as f32;
            let hi = case["max"].as_f64().expect("max") as f32;
            for (i, r) in f32s(&case["result"]).into_iter().enumerate() {
                let ours = clamp_node(t, v[i], lo, hi);
                if !close(ours, r) {
                    bad.push(format!("{t:?} [{lo}, {hi}] {}: {ours} vs {r:?}", v[i]));
                }
            }
        }
        assert!(
            bad.is_empty(),
            "{} mismatches:\n{}",
            bad.len(),
            bad.join("\n")
        );
    }
}
