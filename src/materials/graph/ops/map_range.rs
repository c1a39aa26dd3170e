//! The Map Range node.
//!
//! | field | meaning |
//! | --- | --- |
//! | `interpolation` | [`MapRangeInterpolation`], RNA `interpolation_type` |
//! | `clamp` | RNA `clamp`: clamp the result to the target range |
//! | `from_min`, `from_max` | source range |
//! | `to_min`, `to_max` | target range |
//! | `steps` | number of steps (Stepped only) |
//!
//! [`MapRange<f32>`] is the Float data type, [`MapRange<Vec3>`] the Vector
//! one (RNA `data_type` `FLOAT_VECTOR`, every parameter per component).
//!
//! Float: an empty source range gives 0; with `clamp` Cycles appends a Clamp
//! node (Range type, bounds `to_min`, `to_max`), applied whatever the
//! interpolation. Vector: divisions are safe (0 for an empty range) and
//! `clamp` is ignored for Smooth Step and Smoother Step, as in Cycles.

use super::math::{clamp_c, safe_divide};
use glam::Vec3;

/// Interpolation of Map Range (RNA `interpolation_type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MapRangeInterpolation {
    Linear,
    Stepped,
    SmoothStep,
    SmootherStep,
}

impl MapRangeInterpolation {
    /// From Blender's RNA identifier (`"LINEAR"`, `"STEPPED"`, `"SMOOTHSTEP"`, `"SMOOTHERSTEP"`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        match identifier {
            "LINEAR" => Some(Self::Linear),
            "STEPPED" => Some(Self::Stepped),
            "SMOOTHSTEP" => Some(Self::SmoothStep),
            "SMOOTHERSTEP" => Some(Self::SmootherStep),
            _ => None,
        }
    }
}

/// A Map Range node's settings and range inputs; `T` is `f32` or `Vec3`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapRange<T> {
    pub interpolation: MapRangeInterpolation,
    pub clamp: bool,
    pub from_min: T,
    pub from_max: T,
    pub to_min: T,
    pub to_max: T,
    pub steps: T,
}

fn smoothstep(edge0: f32, edge1: f32, x: f32) -> f32 {
    if x < edge0 {
        0.0
    } else if x >= edge1 {
        1.0
    } else {
        let t = (x - edge0) / (edge1 - edge0);
        (3.0 - 2.0 * t) * (t * t)
    }
}

fn smootherstep(edge0: f32, edge1: f32, x: f32) -> f32 {
    let x = clamp_c(safe_divide(x - edge0, edge1 - edge0), 0.0, 1.0);
    x * x * x * (x * (x * 6.0 - 15.0) + 10.0)
}

fn stepped(factor: f32, steps: f32) -> f32 {
    if steps > 0.0 {
        (factor * (steps + 1.0)).floor() / steps
    } else {
        0.0
    }
}

fn clamp_range(value: f32, a: f32, b: f32) -> f32 {
    if a > b {
        clamp_c(value, b, a)
    } else {
        clamp_c(value, a, b)
    }
}

impl MapRange<f32> {
    /// Map `value` (the Value input) to the Result output.
    pub fn eval(&self, value: f32) -> f32 {
        let (fmin, fmax) = (self.from_min, self.from_max);
        let result = if fmax != fmin {
            let factor = match self.interpolation {
                MapRangeInterpolation::Linear => (value - fmin) / (fmax - fmin),
                MapRangeInterpolation::Stepped => {
                    stepped((value - fmin) / (fmax - fmin), self.steps)
                }
                MapRangeInterpolation::SmoothStep => {
                    if fmin > fmax {
                        1.0 - smoothstep(fmax, fmin, value)
                    } else {
                        smoothstep(fmin, fmax, value)
                    }
                }
                MapRangeInterpolation::SmootherStep => {
                    if fmin > fmax {
                        1.0 - smootherstep(fmax, fmin, value)
                    } else {
                        smootherstep(fmin, fmax, value)
                    }
                }
            };
            self.to_min + factor * (self.to_max - self.to_min)
        } else {
            0.0
        };
        if self.clamp {
            clamp_range(result, self.to_min, self.to_max)
        } else {
            result
        }
    }
}

impl MapRange<Vec3> {
    /// Map `value` (the Vector input) to the Vector output.
    pub fn eval(&self, value: Vec3) -> Vec3 {
        let div = |a: Vec3, b: Vec3| {
            Vec3::new(
                safe_divide(a.x, b.x),
                safe_divide(a.y, b.y),
                safe_divide(a.z, b.z),
            )
        };
        let f = div(value - self.from_min, self.from_max - self.from_min);
        let sat = |v: Vec3| {
            Vec3::new(
                clamp_c(v.x, 0.0, 1.0),
                clamp_c(v.y, 0.0, 1.0),
                clamp_c(v.z, 0.0, 1.0),
            )
        };
        let factor = match self.interpolation {
            MapRangeInterpolation::Linear => f,
            MapRangeInterpolation::Stepped => Vec3::new(
                stepped(f.x, self.steps.x),
                stepped(f.y, self.steps.y),
                stepped(f.z, self.steps.z),
            ),
            MapRangeInterpolation::SmoothStep => {
                let f = sat(f);
                (Vec3::splat(3.0) - 2.0 * f) * (f * f)
            }
            MapRangeInterpolation::SmootherStep => {
                let f = sat(f);
                f * f * f * (f * (f * 6.0 - Vec3::splat(15.0)) + Vec3::splat(10.0))
            }
        };
        let result = self.to_min + factor * (self.to_max - self.to_min);
        let use_clamp = self.clamp
            && matches!(
                self.interpolation,
                MapRangeInterpolation::Linear | MapRangeInterpolation::Stepped
            );
        if use_clamp {
            Vec3::new(
                clamp_range(result.x, self.to_min.x, self.to_max.x),
                clamp_range(result.y, self.to_min.y, self.to_max.y),
                clamp_range(result.z, self.to_min.z, self.to_max.z),
            )
        } else {
            result
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::graph::ops::testutil::*;

    fn num(v: &serde_json::Value) -> f32 {
        v.as_f64().expect("number") as f32
    }

    fn vec(v: &serde_json::Value) -> Vec3 {
        let a = v.as_array().expect("vector");
        Vec3::new(num(&a[0]), num(&a[1]), num(&a[2]))
    }

    #[test]
    fn matches_cycles() {
        let data = parse(include_str!("testdata/map_range.json"));
        let values = floats(&data["inputs"]["value"]);
        let vectors_in = vectors(&data["inputs"]["vector"]);
        let mut bad = Vec::new();
        for case in data["cases"].as_array().expect("cases") {
            let interp =
                MapRangeInterpolation::from_blender(case["interpolation"].as_str().expect("i"))
                    .expect("interpolation");
            let clamp = case["clamp"].as_bool().expect("clamp");
            if case["data_type"] == "FLOAT" {
                let m = MapRange {
                    interpolation: interp,
                    clamp,
                    from_min: num(&case["from_min"]),
                    from_max: num(&case["from_max"]),
                    to_min: num(&case["to_min"]),
                    to_max: num(&case["to_max"]),
                    steps: num(&case["steps"]),
                };
                for (i, r) in f32s(&case["result"]).into_iter().enumerate() {
                    let ours = m.eval(values[i]);
                    if !close(ours, r) {
                        bad.push(format!("{m:?} {}: {ours} vs {r:?}", values[i]));
                    }
                }
            } else {
                let m = MapRange {
                    interpolation: interp,
                    clamp,
                    from_min: vec(&case["from_min"]),
                    from_max: vec(&case["from_max"]),
                    to_min: vec(&case["to_min"]),
                    to_max: vec(&case["to_max"]),
                    steps: vec(&case["steps"]),
                };
                for (i, r) in vec3s(&case["result"]).into_iter().enumerate() {
                    let ours = m.eval(vectors_in[i]);
                    if !close3(ours, r) {
                        bad.push(format!("{m:?} {}: {ours} vs {r:?}", vectors_in[i]));
                    }
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
