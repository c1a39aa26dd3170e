//! Loading of the Blender-produced reference values in `testdata/` and the
//! comparison used by the texture tests.
//!
//! Tolerance: |ours - Blender| <= 1e-4 * max(1, |Blender|).  Both sides work
//! in single precision but differ in operation order (Blender's SIMD
//! interpolation, fused multiply-adds), which moves results by a few ULPs per
//! operation, a few 1e-6 after a dozen octaves; the references are rounded to
//! 7 significant digits (5e-7 relative).  1e-4 leaves a wide margin over that
//! while any change of a constant, a gradient, a hash or a branch shows up as
//! errors of 1e-2 or more at some of the 64 points.

use glam::Vec4;
use serde_json::Value;
use std::collections::BTreeMap;

/// One file of reference values: the sample points and the cases.
#[derive(serde::Deserialize)]
pub struct Reference {
    /// Sample points (x, y, z, w); Vector = xyz, W = w.
    pub points: Vec<[f32; 4]>,
    /// Parameter combinations and Blender's outputs for them.
    pub cases: Vec<Case>,
}

/// One parameter combination.
#[derive(serde::Deserialize)]
pub struct Case {
    /// Node properties (enums, booleans, integers).
    pub props: BTreeMap<String, Value>,
    /// Socket values other than Vector and W.
    pub inputs: BTreeMap<String, Value>,
    /// Output socket name to one value (float or colour/vector) per point.
    pub outputs: BTreeMap<String, Vec<Value>>,
}

impl Reference {
    pub fn load(json: &str) -> Self {
        serde_json::from_str(json).expect("reference JSON")
    }
}

impl Case {
    pub fn prop_str(&self, key: &str) -> &str {
        self.props.get(key).and_then(Value::as_str).expect(key)
    }
    pub fn prop_bool(&self, key: &str) -> bool {
        self.props.get(key).and_then(Value::as_bool).expect(key)
    }
    pub fn prop_f32(&self, key: &str) -> f32 {
        self.props.get(key).and_then(Value::as_f64).expect(key) as f32
    }
    pub fn input(&self, key: &str) -> f32 {
        self.inputs.get(key).and_then(Value::as_f64).expect(key) as f32
    }
    pub fn input_vec3(&self, key: &str) -> glam::Vec3 {
        let a = self.inputs.get(key).and_then(Value::as_array).expect(key);
        let c = |i: usize| a.get(i).and_then(Value::as_f64).expect(key) as f32;
        glam::Vec3::new(c(0), c(1), c(2))
    }
    pub fn describe(&self) -> String {
        format!("props {:?} inputs {:?}", self.props, self.inputs)
    }
}

fn values(v: &Value) -> Vec<Option<f32>> {
    match v {
        Value::Array(a) => a.iter().map(|x| x.as_f64().map(|f| f as f32)).collect(),
        other => vec![other.as_f64().map(|f| f as f32)],
    }
}

/// Compares `eval` at every reference point with every output Blender
/// produced for `case`; panics listing the mismatches.
pub fn check_case<F>(r: &Reference, case: &Case, eval: F)
where
    F: Fn(Vec4) -> Vec<(&'static str, Vec<f32>)>,
{
    let mut failures = Vec::new();
    let mut checked = 0;
    for (i, p) in r.points.iter().enumerate() {
        let ours = eval(Vec4::from_array(*p));
        for (name, expected) in &case.outputs {
            let Some((_, got)) = ours.iter().find(|(n, _)| n == name) else {
                panic!("output {name} not produced ({})", case.describe());
            };
            let want = values(&expected[i]);
            assert_eq!(want.len(), got.len(), "{name} arity");
            for (k, (w, g)) in want.iter().zip(got).enumerate() {
                checked += 1;
                let ok = match w {
                    Some(w) => (g - w).abs() <= 1e-4 * w.abs().max(1.0),
                    None => !g.is_finite(),
                };
                if !ok {
                    failures.push(format!(
                        "  point {i} {p:?} {name}[{k}]: ours {g} blender {w:?}"
                    ));
                }
            }
        }
    }
    assert!(checked > 0, "nothing compared ({})", case.describe());
    if !failures.is_empty() {
        let n = failures.len();
        failures.truncate(12);
        panic!(
            "{n} mismatches for {}:\n{}",
            case.describe(),
            failures.join("\n")
        );
    }
}
