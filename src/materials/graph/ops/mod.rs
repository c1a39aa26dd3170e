//! Converter nodes, as Cycles evaluates them.
//!
//! Pure functions over `f32` and [`glam::Vec3`] / [`glam::Vec4`] that reproduce
//! the shader-graph converter nodes of Blender's Cycles (SVM kernel), value for
//! value up to float rounding: the same formulas, the same operation order, the
//! same guards against division by zero, and the same pre-processing Cycles does
//! on the host (the clamp node inserted for Math "Clamp" and Map Range "Clamp",
//! the 257-entry tables baked for Color Ramp, Float Curve and RGB Curves).
//!
//! Colours are scene-linear Rec.709 `Vec3` (Cycles drops colour alpha between
//! nodes); only Color Ramp outputs an alpha.
//!
//! Every enum has `from_blender`, taking Blender's RNA identifier
//! (e.g. `"MULTIPLY_ADD"`). No function panics, whatever the input
//! (NaN and infinities included).
//!
//! | module | nodes |
//! | --- | --- |
//! | [`math`] | Math |
//! | [`vector_math`] | Vector Math |
//! | [`vector_rotate`] | Vector Rotate |
//! | [`mix`] | Mix (Float, Vector, Color with every blend mode) |
//! | [`color`] | Hue/Saturation/Value, Brightness/Contrast, Gamma, Invert, RGB to BW, Separate/Combine Color |
//! | [`blackbody`] | Blackbody |
//! | [`wavelength`] | Wavelength |
//! | [`map_range`] | Map Range (float and vector) |
//! | [`clamp`] | Clamp |
//! | [`ramp`] | Color Ramp |
//! | [`curves`] | Float Curve, RGB Curves |

pub mod blackbody;
pub mod clamp;
pub mod color;
pub mod curves;
pub mod map_range;
pub mod math;
pub mod mix;
pub mod ramp;
pub mod vector_math;
pub mod vector_rotate;
pub mod wavelength;

pub use blackbody::blackbody;
pub use clamp::{clamp_node, ClampType};
pub use color::{
    bright_contrast, combine_color, gamma, hsl_to_rgb, hsv_to_rgb, hue_saturation_value, invert,
    rgb_to_bw, rgb_to_hsl, rgb_to_hsv, separate_color, ColorMode,
};
pub use curves::{CurveExtend, CurveMap, CurvePoint, FloatCurve, HandleType, RgbCurves};
pub use map_range::{MapRange, MapRangeInterpolation};
pub use math::{math, math_node, MathOp};
pub use mix::{
    blend, mix_color, mix_float, mix_vector, mix_vector_non_uniform, BlendMode, MixDataType,
    MixFactorMode,
};
pub use ramp::{ColorRamp, ColorStop, HueInterpolation, RampColorMode, RampInterpolation};
pub use vector_math::{vector_math, VectorMathOp, VectorMathOutput};
pub use vector_rotate::{vector_rotate, RotateType};
pub use wavelength::wavelength;

/// Helpers shared by the unit tests: reading the Blender references.
#[cfg(test)]
pub(crate) mod testutil {
    use glam::Vec3;
    use serde_json::Value;

    /// Relative tolerance against Blender's values, with an absolute floor
    /// of the same size for values below 1.
    ///
    /// The references carry 7 significant digits (rounding ≤ 5e-7 relative);
    /// Cycles' C++ kernel and this code may differ by a few ulp in libm
    /// functions (sin, pow, exp...) and by contraction into fused
    /// multiply-adds; inputs stay within ±10, so cancellation amplifies those
    /// to at most a few 1e-6. Every formula error seen while writing this
    /// code was ≥ 1e-3.
    pub const TOL: f32 = 1e-5;

    pub fn parse(text: &str) -> Value {
        serde_json::from_str(text).expect("test data is valid JSON")
    }

    pub fn f32s(v: &Value) -> Vec<Option<f32>> {
        v.as_array()
            .expect("array")
            .iter()
            .map(|x| x.as_f64().map(|x| x as f32))
            .collect()
    }

    pub fn floats(v: &Value) -> Vec<f32> {
        f32s(v)
            .into_iter()
            .map(|x| x.expect("finite input"))
            .collect()
    }

    pub fn vec3s(v: &Value) -> Vec<Option<Vec3>> {
        v.as_array()
            .expect("array")
            .iter()
            .map(|row| {
                let c = f32s(row);
                match (c[0], c[1], c[2]) {
                    (Some(x), Some(y), Some(z)) => Some(Vec3::new(x, y, z)),
                    _ => None,
                }
            })
            .collect()
    }

    pub fn vectors(v: &Value) -> Vec<Vec3> {
        vec3s(v)
            .into_iter()
            .map(|x| x.expect("finite input"))
            .collect()
    }

    /// Whether `ours` matches the reference (None: Blender gave a non-finite value).
    pub fn close(ours: f32, reference: Option<f32>) -> bool {
        match reference {
            None => !ours.is_finite(),
            Some(r) => (ours - r).abs() <= TOL * r.abs().max(1.0),
        }
    }

    pub fn close3(ours: Vec3, reference: Option<Vec3>) -> bool {
        match reference {
            None => !ours.is_finite(),
            Some(r) => (0..3).all(|i| close(ours[i], Some(r[i]))),
        }
    }
}
