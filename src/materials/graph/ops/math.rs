//! The Math node.
//!
//! | parameter | meaning |
//! | --- | --- |
//! | `op` | [`MathOp`], RNA `operation` |
//! | `a`, `b`, `c` | the three Value inputs (unused ones are ignored) |
//! | `use_clamp` | RNA `use_clamp`: clamp the result to [0, 1] |
//!
//! Output: Value. Division, logarithm, square roots, powers, modulo, snap,
//! wrap and ping-pong are "safe" as in Cycles: a zero divisor gives 0, a
//! negative base with a non-integer exponent gives 0, and so on.

/// `(a < b) ? a : b`, Cycles' `min` (NaN in `a` gives `b`).
#[inline]
pub(crate) fn min_c(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

/// `(a > b) ? a : b`, Cycles' `max` (NaN in `a` gives `b`).
#[inline]
pub(crate) fn max_c(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

/// Cycles' `clamp`: `min(max(a, lo), hi)`.
#[inline]
pub(crate) fn clamp_c(a: f32, lo: f32, hi: f32) -> f32 {
    min_c(max_c(a, lo), hi)
}

/// Cycles' `saturatef`.
#[inline]
pub(crate) fn saturate(a: f32) -> f32 {
    clamp_c(a, 0.0, 1.0)
}

#[inline]
pub(crate) fn safe_divide(a: f32, b: f32) -> f32 {
    if b != 0.0 {
        a / b
    } else {
        0.0
    }
}

/// C's `(int)f`, saturating (and 0 for NaN) instead of undefined.
#[inline]
pub(crate) fn float_to_int(f: f32) -> i32 {
    f as i32
}

#[inline]
pub(crate) fn fract(x: f32) -> f32 {
    x - x.floor()
}

fn compatible_powf(x: f32, y: f32) -> f32 {
    if y == 0.0 {
        return 1.0;
    }
    if x == 0.0 {
        return 0.0;
    }
    x.powf(y)
}

pub(crate) fn safe_powf(a: f32, b: f32) -> f32 {
    if a < 0.0 && b != float_to_int(b) as f32 {
        return 0.0;
    }
    compatible_powf(a, b)
}

fn safe_logf(a: f32, b: f32) -> f32 {
    if a <= 0.0 || b <= 0.0 {
        return 0.0;
    }
    safe_divide(a.ln(), b.ln())
}

fn safe_modulo(a: f32, b: f32) -> f32 {
    if b != 0.0 {
        a % b
    } else {
        0.0
    }
}

fn safe_floored_modulo(a: f32, b: f32) -> f32 {
    if b != 0.0 {
        a - (a / b).floor() * b
    } else {
        0.0
    }
}

fn wrapf(value: f32, max: f32, min: f32) -> f32 {
    let range = max - min;
    if range != 0.0 {
        value - range * ((value - min) / range).floor()
    } else {
        min
    }
}

fn pingpongf(a: f32, b: f32) -> f32 {
    if b != 0.0 {
        (fract((a - b) / (b * 2.0)) * b * 2.0 - b).abs()
    } else {
        0.0
    }
}

fn smoothminf(a: f32, b: f32, k: f32) -> f32 {
    if k != 0.0 {
        let h = (k - (a - b).abs()).max(0.0) / k;
        a.min(b) - h * h * h * k * (1.0 / 6.0)
    } else {
        a.min(b)
    }
}

/// Sign that is 0 for ±0 (and 1 for NaN), as Cycles' `compatible_signf`.
pub(crate) fn compatible_signf(f: f32) -> f32 {
    if f == 0.0 {
        0.0
    } else if f < 0.0 {
        -1.0
    } else {
        1.0
    }
}

fn compatible_atan2(y: f32, x: f32) -> f32 {
    if x == 0.0 && y == 0.0 {
        0.0
    } else {
        y.atan2(x)
    }
}

fn inverse_sqrt(f: f32) -> f32 {
    if f > 0.0 {
        1.0 / f.sqrt()
    } else {
        0.0
    }
}

/// Math node operation (RNA `ShaderNodeMath.operation`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MathOp {
    Add,
    Subtract,
    Multiply,
    Divide,
    MultiplyAdd,
    Power,
    Logarithm,
    Sqrt,
    InverseSqrt,
    Absolute,
    Exponent,
    Minimum,
    Maximum,
    LessThan,
    GreaterThan,
    Sign,
    Compare,
    SmoothMin,
    SmoothMax,
    Round,
    Floor,
    Ceil,
    Trunc,
    Fract,
    Modulo,
    FlooredModulo,
    Wrap,
    Snap,
    PingPong,
    Sine,
    Cosine,
    Tangent,
    Arcsine,
    Arccosine,
    Arctangent,
    Arctan2,
    Sinh,
    Cosh,
    Tanh,
    Radians,
    Degrees,
}

impl MathOp {
    /// Every operation, in Blender's menu order.
    pub const ALL: [MathOp; 41] = [
        MathOp::Add,
        MathOp::Subtract,
        MathOp::Multiply,
        MathOp::Divide,
        MathOp::MultiplyAdd,
        MathOp::Power,
        MathOp::Logarithm,
        MathOp::Sqrt,
        MathOp::InverseSqrt,
        MathOp::Absolute,
        MathOp::Exponent,
        MathOp::Minimum,
        MathOp::Maximum,
        MathOp::LessThan,
        MathOp::GreaterThan,
        MathOp::Sign,
        MathOp::Compare,
        MathOp::SmoothMin,
        MathOp::SmoothMax,
        MathOp::Round,
        MathOp::Floor,
        MathOp::Ceil,
        MathOp::Trunc,
        MathOp::Fract,
        MathOp::Modulo,
        MathOp::FlooredModulo,
        MathOp::Wrap,
        MathOp::Snap,
        MathOp::PingPong,
        MathOp::Sine,
        MathOp::Cosine,
        MathOp::Tangent,
        MathOp::Arcsine,
        MathOp::Arccosine,
        MathOp::Arctangent,
        MathOp::Arctan2,
        MathOp::Sinh,
        MathOp::Cosh,
        MathOp::Tanh,
        MathOp::Radians,
        MathOp::Degrees,
    ];

    /// Blender's RNA identifier.
    pub fn blender_name(self) -> &'static str {
        use MathOp::*;
        match self {
            Add => "ADD",
            Subtract => "SUBTRACT",
            Multiply => "MULTIPLY",
            Divide => "DIVIDE",
            MultiplyAdd => "MULTIPLY_ADD",
            Power => "POWER",
            Logarithm => "LOGARITHM",
            Sqrt => "SQRT",
            InverseSqrt => "INVERSE_SQRT",
            Absolute => "ABSOLUTE",
            Exponent => "EXPONENT",
            Minimum => "MINIMUM",
            Maximum => "MAXIMUM",
            LessThan => "LESS_THAN",
            GreaterThan => "GREATER_THAN",
            Sign => "SIGN",
            Compare => "COMPARE",
            SmoothMin => "SMOOTH_MIN",
            SmoothMax => "SMOOTH_MAX",
            Round => "ROUND",
            Floor => "FLOOR",
            Ceil => "CEIL",
            Trunc => "TRUNC",
            Fract => "FRACT",
            Modulo => "MODULO",
            FlooredModulo => "FLOORED_MODULO",
            Wrap => "WRAP",
            Snap => "SNAP",
            PingPong => "PINGPONG",
            Sine => "SINE",
            Cosine => "COSINE",
            Tangent => "TANGENT",
            Arcsine => "ARCSINE",
            Arccosine => "ARCCOSINE",
            Arctangent => "ARCTANGENT",
            Arctan2 => "ARCTAN2",
            Sinh => "SINH",
            Cosh => "COSH",
            Tanh => "TANH",
            Radians => "RADIANS",
            Degrees => "DEGREES",
        }
    }

    /// From Blender's RNA identifier (`"MULTIPLY_ADD"`, ...).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .copied()
            .find(|op| op.blender_name() == identifier)
    }
}

/// The Math node's formula (Cycles `svm_math`), without the optional clamp.
pub fn math(op: MathOp, a: f32, b: f32, c: f32) -> f32 {
    use std::f32::consts::PI;
    use MathOp::*;
    match op {
        Add => a + b,
        Subtract => a - b,
        Multiply => a * b,
        Divide => safe_divide(a, b),
        Power => safe_powf(a, b),
        Logarithm => safe_logf(a, b),
        Sqrt => max_c(a, 0.0).sqrt(),
        InverseSqrt => inverse_sqrt(a),
        Absolute => a.abs(),
        Radians => a * (PI / 180.0),
        Degrees => a * (180.0 / PI),
        Minimum => a.min(b),
        Maximum => a.max(b),
        LessThan => f32::from(u8::from(a < b)),
        GreaterThan => f32::from(u8::from(a > b)),
        Round => (a + 0.5).floor(),
        Floor => a.floor(),
        Ceil => a.ceil(),
        Fract => a - a.floor(),
        Modulo => safe_modulo(a, b),
        FlooredModulo => safe_floored_modulo(a, b),
        Trunc => {
            if a >= 0.0 {
                a.floor()
            } else {
                a.ceil()
            }
        }
        Snap => safe_divide(a, b).floor() * b,
        Wrap => wrapf(a, b, c),
        PingPong => pingpongf(a, b),
        Sine => a.sin(),
        Cosine => a.cos(),
        Tangent => a.tan(),
        Sinh => a.sinh(),
        Cosh => a.cosh(),
        Tanh => a.tanh(),
        Arcsine => clamp_c(a, -1.0, 1.0).asin(),
        Arccosine => clamp_c(a, -1.0, 1.0).acos(),
        Arctangent => a.atan(),
        Arctan2 => compatible_atan2(a, b),
        Sign => compatible_signf(a),
        Exponent => a.exp(),
        Compare => {
            if a == b || (a - b).abs() <= c.max(f32::EPSILON) {
                1.0
            } else {
                0.0
            }
        }
        MultiplyAdd => a * b + c,
        SmoothMin => smoothminf(a, b, c),
        SmoothMax => -smoothminf(-a, -b, c),
    }
}

/// The Math node: [`math`], then with `use_clamp` the clamp to [0, 1] that
/// Cycles inserts after the node.
pub fn math_node(op: MathOp, a: f32, b: f32, c: f32, use_clamp: bool) -> f32 {
    let v = math(op, a, b, c);
    if use_clamp {
        clamp_c(v, 0.0, 1.0)
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::graph::ops::testutil::*;

    #[test]
    fn identifiers_round_trip() {
        for op in MathOp::ALL {
            assert_eq!(MathOp::from_blender(op.blender_name()), Some(op));
        }
        assert_eq!(MathOp::from_blender("NOPE"), None);
    }

    #[test]
    fn matches_cycles() {
        let data = parse(include_str!("testdata/math.json"));
        let a = floats(&data["inputs"]["a"]);
        let b = floats(&data["inputs"]["b"]);
        let c = floats(&data["inputs"]["c"]);
        let mut bad = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for case in data["cases"].as_array().expect("cases") {
            let name = case["op"].as_str().expect("op");
            let op = MathOp::from_blender(name).expect("known op");
            seen.insert(op);
            let clamp = case["use_clamp"].as_bool().expect("bool");
            for (i, r) in f32s(&case["value"]).into_iter().enumerate() {
                let ours = math_node(op, a[i], b[i], c[i], clamp);
                if !close(ours, r) {
                    bad.push(format!(
                        "{name} clamp={clamp} ({}, {}, {}): {ours} vs {r:?}",
                        a[i], b[i], c[i]
                    ));
                }
            }
        }
        assert_eq!(
            seen.len(),
            MathOp::ALL.len(),
            "every operation has a reference"
        );
        assert!(
            bad.is_empty(),
            "{} mismatches:\n{}",
            bad.len(),
            bad.join("\n")
        );
    }

    #[test]
    fn non_finite_inputs_do_not_panic() {
        for op in MathOp::ALL {
            for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
                let _ = math_node(op, x, x, x, true);
                let _ = math_node(op, 1.0, x, 0.5, false);
            }
        }
    }
}
