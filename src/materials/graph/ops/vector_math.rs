//! The Vector Math node.
//!
//! | parameter | meaning |
//! | --- | --- |
//! | `op` | [`VectorMathOp`], RNA `operation` |
//! | `a`, `b`, `c` | the three Vector inputs (`c` is used by Multiply Add, Wrap (min) and Faceforward) |
//! | `scale` | the Scale input (Scale; the IOR ratio of Refract) |
//!
//! Output: [`VectorMathOutput`]. Dot Product, Distance and Length produce the
//! Value output (the Vector output is then zero); every other operation
//! produces the Vector output (the Value output is then zero).

use super::math::{compatible_signf, max_c, min_c, safe_divide, safe_powf};
use glam::Vec3;

/// Vector Math operation (RNA `ShaderNodeVectorMath.operation`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VectorMathOp {
    Add,
    Subtract,
    Multiply,
    Divide,
    MultiplyAdd,
    CrossProduct,
    Project,
    Reflect,
    Refract,
    Faceforward,
    DotProduct,
    Distance,
    Length,
    Scale,
    Normalize,
    Absolute,
    Power,
    Sign,
    Minimum,
    Maximum,
    Floor,
    Ceil,
    Fraction,
    Modulo,
    Wrap,
    Snap,
    Sine,
    Cosine,
    Tangent,
}

impl VectorMathOp {
    /// Every operation, in Blender's menu order.
    pub const ALL: [VectorMathOp; 29] = [
        Self::Add,
        Self::Subtract,
        Self::Multiply,
        Self::Divide,
        Self::MultiplyAdd,
        Self::CrossProduct,
        Self::Project,
        Self::Reflect,
        Self::Refract,
        Self::Faceforward,
        Self::DotProduct,
        Self::Distance,
        Self::Length,
        Self::Scale,
        Self::Normalize,
        Self::Absolute,
        Self::Power,
        Self::Sign,
        Self::Minimum,
        Self::Maximum,
        Self::Floor,
        Self::Ceil,
        Self::Fraction,
        Self::Modulo,
        Self::Wrap,
        Self::Snap,
        Self::Sine,
        Self::Cosine,
        Self::Tangent,
    ];

    /// Blender's RNA identifier.
    pub fn blender_name(self) -> &'static str {
        use VectorMathOp::*;
        match self {
            Add => "ADD",
            Subtract => "SUBTRACT",
            Multiply => "MULTIPLY",
            Divide => "DIVIDE",
            MultiplyAdd => "MULTIPLY_ADD",
            CrossProduct => "CROSS_PRODUCT",
            Project => "PROJECT",
            Reflect => "REFLECT",
            Refract => "REFRACT",
            Faceforward => "FACEFORWARD",
            DotProduct => "DOT_PRODUCT",
            Distance => "DISTANCE",
            Length => "LENGTH",
            Scale => "SCALE",
            Normalize => "NORMALIZE",
            Absolute => "ABSOLUTE",
            Power => "POWER",
            Sign => "SIGN",
            Minimum => "MINIMUM",
            Maximum => "MAXIMUM",
            Floor => "FLOOR",
            Ceil => "CEIL",
            Fraction => "FRACTION",
            Modulo => "MODULO",
            Wrap => "WRAP",
            Snap => "SNAP",
            Sine => "SINE",
            Cosine => "COSINE",
            Tangent => "TANGENT",
        }
    }

    /// From Blender's RNA identifier (`"CROSS_PRODUCT"`, ...).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .copied()
            .find(|op| op.blender_name() == identifier)
    }

    /// Whether the operation produces the Value output (else the Vector one).
    pub fn outputs_value(self) -> bool {
        matches!(self, Self::DotProduct | Self::Distance | Self::Length)
    }
}

/// The two outputs of the Vector Math node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VectorMathOutput {
    pub vector: Vec3,
    pub value: f32,
}

fn per_component(a: Vec3, b: Vec3, f: impl Fn(f32, f32) -> f32) -> Vec3 {
    Vec3::new(f(a.x, b.x), f(a.y, b.y), f(a.z, b.z))
}

fn len(a: Vec3) -> f32 {
    a.dot(a).sqrt()
}

fn safe_normalize(a: Vec3) -> Vec3 {
    let t = len(a);
    if t != 0.0 {
        a * (1.0 / t)
    } else {
        a
    }
}

fn project(v: Vec3, onto: Vec3) -> Vec3 {
    let len_squared = onto.dot(onto);
    if len_squared != 0.0 {
        (v.dot(onto) / len_squared) * onto
    } else {
        Vec3::ZERO
    }
}

fn refract(incident: Vec3, normal: Vec3, eta: f32) -> Vec3 {
    let d = normal.dot(incident);
    let k = 1.0 - eta * eta * (1.0 - d * d);
    if k < 0.0 {
        return Vec3::ZERO;
    }
    eta * incident - (eta * d + k.sqrt()) * normal
}

/// The Vector Math node (Cycles `svm_vector_math`).
pub fn vector_math(op: VectorMathOp, a: Vec3, b: Vec3, c: Vec3, scale: f32) -> VectorMathOutput {
    use VectorMathOp::*;
    let vector = match op {
        Add => a + b,
        Subtract => a - b,
        Multiply => a * b,
        Divide => per_component(a, b, safe_divide),
        CrossProduct => a.cross(b),
        Project => project(a, b),
        Reflect => {
            let n = safe_normalize(b);
            a - 2.0 * n * a.dot(n)
        }
        Refract => refract(a, safe_normalize(b), scale),
        Faceforward => {
            if c.dot(b) < 0.0 {
                a
            } else {
                -a
            }
        }
        MultiplyAdd => a * b + c,
        Scale => a * scale,
        Normalize => safe_normalize(a),
        Snap => per_component(a, b, safe_divide).floor() * b,
        Floor => a.floor(),
        Ceil => a.ceil(),
        // The SIMD kernels compute fmod as a - trunc(a / b) * b.
        Modulo => per_component(a, b, |a, b| {
            if b == 0.0 {
                0.0
            } else {
                a - (a / b).trunc() * b
            }
        }),
        // wrap(value, max, min) = floored_fmod(value - min, max - min) + min.
        Wrap => {
            let range = b - c;
            per_component(a - c, range, |x, r| {
                if r == 0.0 {
                    0.0
                } else {
                    x - (x / r).floor() * r
                }
            }) + c
        }
        Fraction => a - a.floor(),
        Absolute => a.abs(),
        Power => per_component(a, b, safe_powf),
        Sign => Vec3::new(
            compatible_signf(a.x),
            compatible_signf(a.y),
            compatible_signf(a.z),
        ),
        Minimum => per_component(a, b, min_c),
        Maximum => per_component(a, b, max_c),
        Sine => Vec3::new(a.x.sin(), a.y.sin(), a.z.sin()),
        Cosine => Vec3::new(a.x.cos(), a.y.cos(), a.z.cos()),
        Tangent => Vec3::new(a.x.tan(), a.y.tan(), a.z.tan()),
        DotProduct | Distance | Length => Vec3::ZERO,
    };
    let value = match op {
        DotProduct => a.dot(b),
        Distance => len(a - b),
        Length => len(a),
        _ => 0.0,
    };
    VectorMathOutput { vector, value }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::graph::ops::testutil::*;

    #[test]
    fn identifiers_round_trip() {
        for op in VectorMathOp::ALL {
            assert_eq!(VectorMathOp::from_blender(op.blender_name()), Some(op));
        }
    }

    #[test]
    fn matches_cycles() {
        let data = parse(include_str!("testdata/vector_math.json"));
        let a = vectors(&data["inputs"]["a"]);
        let b = vectors(&data["inputs"]["b"]);
        let c = vectors(&data["inputs"]["c"]);
        let s = floats(&data["inputs"]["scale"]);
        let mut bad = Vec::new();
        let mut count = 0;
        for case in data["cases"].as_array().expect("cases") {
            let name = case["op"].as_str().expect("op");
            let op = VectorMathOp::from_blender(name).expect("known op");
            count += 1;
            if op.outputs_value() {
                for (i, r) in f32s(&case["value"]).into_iter().enumerate() {
                    let ours = vector_math(op, a[i], b[i], c[i], s[i]).value;
                    if !close(ours, r) {
                        bad.push(format!("{name} #{i}: {ours} vs {r:?}"));
                    }
                }
            } else {
                for (i, r) in vec3s(&case["vector"]).into_iter().enumerate() {
                    let ours = vector_math(op, a[i], b[i], c[i], s[i]).vector;
                    if !close3(ours, r) {
                        bad.push(format!(
                            "{name} #{i} ({}, {}, {}, {}): {ours} vs {r:?}",
                            a[i], b[i], c[i], s[i]
                        ));
                    }
                }
            }
        }
        assert_eq!(count, VectorMathOp::ALL.len());
        assert!(
            bad.is_empty(),
            "{} mismatches:\n{}",
            bad.len(),
            bad.join("\n")
        );
    }

    #[test]
    fn non_finite_inputs_do_not_panic() {
        let n = Vec3::splat(f32::NAN);
        let i = Vec3::splat(f32::INFINITY);
        for op in VectorMathOp::ALL {
            let _ = vector_math(op, n, i, n, f32::NAN);
            let _ = vector_math(op, i, Vec3::ZERO, i, f32::INFINITY);
        }
    }
}
