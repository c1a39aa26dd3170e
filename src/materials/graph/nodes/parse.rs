//! The converter and texture nodes read from the IR: each node's operation from its
//! `params`, and its sockets.

use super::NodeOp;
use crate::error::Result;
use crate::materials::graph::ops;
use crate::materials::graph::spec::{Dflt, NodeSpec, ParamReader, Ty};
use crate::materials::graph::tex::{self, Dimensions};
use glam::Vec4;

const VECTOR: (&str, Ty, Dflt) = ("vector", Ty::Vector, Dflt::Generated);

impl NodeOp {
    /// The node of IR type `kind`, if it is one of these; `None` for other types.
    pub fn parse(kind: &str, p: &ParamReader) -> Result<Option<(NodeOp, NodeSpec)>> {
        use Dflt::*;
        use Ty::*;
        let spec = NodeSpec::new;
        let color_fac = [("color", Color), ("fac", Float)];
        Ok(Some(match kind {
            "invert" => (
                NodeOp::Invert,
                spec(
                    &[("fac", Float, F(1.0)), ("color", Color, V([0.0; 3]))],
                    &[("color", Color)],
                ),
            ),
            "noise_texture" => (
                NodeOp::Noise(tex::NoiseTexture {
                    dimensions: p.enum_or("noise_dimensions", "3D", Dimensions::from_blender)?,
                    noise_type: p.enum_or("noise_type", "FBM", tex::NoiseType::from_blender)?,
                    normalize: p.bool_or("normalize", true)?,
                }),
                spec(
                    &[
                        VECTOR,
                        ("w", Float, F(0.0)),
                        ("scale", Float, F(5.0)),
                        ("detail", Float, F(2.0)),
                        ("roughness", Float, F(0.5)),
                        ("lacunarity", Float, F(2.0)),
                        ("offset", Float, F(0.0)),
                        ("gain", Float, F(1.0)),
                        ("distortion", Float, F(0.0)),
                    ],
                    &[("fac", Float), ("color", Color)],
                ),
            ),
            "voronoi_texture" => (
                NodeOp::Voronoi(tex::VoronoiTexture {
                    dimensions: p.enum_or("voronoi_dimensions", "3D", Dimensions::from_blender)?,
                    feature: p.enum_or("feature", "F1", tex::VoronoiFeature::from_blender)?,
                    metric: p.enum_or("distance", "EUCLIDEAN", tex::VoronoiMetric::from_blender)?,
                    normalize: p.bool_or("normalize", false)?,
                }),
                spec(
                    &[
                        VECTOR,
                        ("w", Float, F(0.0)),
                        ("scale", Float, F(5.0)),
                        ("detail", Float, F(0.0)),
                        ("roughness", Float, F(0.5)),
                        ("lacunarity", Float, F(2.0)),
                        ("smoothness", Float, F(1.0)),
                        ("exponent", Float, F(0.5)),
                        ("randomness", Float, F(1.0)),
                    ],
                    &[
                        ("distance", Float),
                        ("color", Color),
                        ("position", Vector),
                        ("w", Float),
                        ("radius", Float),
                    ],
                ),
            ),
            "white_noise_texture" => (
                NodeOp::WhiteNoise(tex::WhiteNoiseTexture {
                    dimensions: p.enum_or("noise_dimensions", "3D", Dimensions::from_blender)?,
                }),
                spec(
                    &[VECTOR, ("w", Float, F(0.0))],
                    &[("value", Float), ("color", Color)],
                ),
            ),
            "checker_texture" => (
                NodeOp::Checker(tex::CheckerTexture),
                spec(
                    &[
                        VECTOR,
                        ("color1", Color, V([0.8; 3])),
                        ("color2", Color, V([0.2; 3])),
                        ("scale", Float, F(5.0)),
                    ],
                    &color_fac,
                ),
            ),
            "brick_texture" => (
                NodeOp::Brick(tex::BrickTexture {
                    offset: p.f32_or("offset", 0.5)?,
                    offset_frequency: p.u32_or("offset_frequency", 2)?.min(99) as i32,
                    squash: p.f32_or("squash", 1.0)?,
                    squash_frequency: p.u32_or("squash_frequency", 2)?.min(99) as i32,
                }),
                spec(
                    &[
                        VECTOR,
                        ("color1", Color, V([0.8; 3])),
                        ("color2", Color, V([0.2; 3])),
                        ("mortar", Color, V([0.0; 3])),
                        ("scale", Float, F(5.0)),
                        ("mortar_size", Float, F(0.02)),
                        ("mortar_smooth", Float, F(0.1)),
                        ("bias", Float, F(0.0)),
                        ("brick_width", Float, F(0.5)),
                        ("row_height", Float, F(0.25)),
                    ],
                    &color_fac,
                ),
            ),
            "gradient_texture" => (
                NodeOp::Gradient(tex::GradientTexture {
                    gradient_type: p.enum_or(
                        "gradient_type",
                        "LINEAR",
                        tex::GradientType::from_blender,
                    )?,
                }),
                spec(&[VECTOR], &color_fac),
            ),
            "wave_texture" => (
                NodeOp::Wave(tex::WaveTexture {
                    wave_type: p.enum_or("wave_type", "BANDS", tex::WaveType::from_blender)?,
                    bands_direction: p.enum_or(
                        "bands_direction",
                        "X",
                        tex::BandsDirection::from_blender,
                    )?,
                    rings_direction: p.enum_or(
                        "rings_direction",
                        "X",
                        tex::RingsDirection::from_blender,
                    )?,
                    profile: p.enum_or("wave_profile", "SIN", tex::WaveProfile::from_blender)?,
                }),
                spec(
                    &[
                        VECTOR,
                        ("scale", Float, F(5.0)),
                        ("distortion", Float, F(0.0)),
                        ("detail", Float, F(2.0)),
                        ("detail_scale", Float, F(1.0)),
                        ("detail_roughness", Float, F(0.5)),
                        ("phase_offset", Float, F(0.0)),
                    ],
                    &color_fac,
                ),
            ),
            "magic_texture" => (
                NodeOp::Magic(tex::MagicTexture {
                    depth: p.u32_or("turbulence_depth", 2)?.min(10) as i32,
                }),
                spec(
                    &[
                        VECTOR,
                        ("scale", Float, F(5.0)),
                        ("distortion", Float, F(1.0)),
                    ],
                    &color_fac,
                ),
            ),
            "math" => (
                NodeOp::Math {
                    op: p.enum_or("operation", "ADD", ops::MathOp::from_blender)?,
                    clamp: p.bool_or("use_clamp", false)?,
                },
                spec(
                    &[
                        ("value", Float, F(0.5)),
                        ("value_001", Float, F(0.5)),
                        ("value_002", Float, F(0.5)),
                    ],
                    &[("value", Float)],
                ),
            ),
            "vector_math" => (
                NodeOp::VectorMath(p.enum_or(
                    "operation",
                    "ADD",
                    ops::VectorMathOp::from_blender,
                )?),
                spec(
                    &[
                        ("vector", Vector, V([0.0; 3])),
                        ("vector_001", Vector, V([0.0; 3])),
                        ("vector_002", Vector, V([0.0; 3])),
                        ("scale", Float, F(1.0)),
                    ],
                    &[("vector", Vector), ("value", Float)],
                ),
            ),
            "mix" => {
                let data = p.enum_or("data_type", "FLOAT", ops::MixDataType::from_blender)?;
                let non_uniform = data == ops::MixDataType::Vector
                    && p.str_or("factor_mode", "UNIFORM")? == "NON_UNIFORM";
                let (ty, dflt) = match data {
                    ops::MixDataType::Float => (Float, F(0.0)),
                    ops::MixDataType::Vector => (Vector, V([0.0; 3])),
                    ops::MixDataType::Rgba => (Color, V([0.5; 3])),
                };
                let fac = if non_uniform {
                    ("factor", Vector, V([0.5; 3]))
                } else {
                    ("factor", Float, F(0.5))
                };
                (
                    NodeOp::Mix {
                        data,
                        blend: p.enum_or("blend_type", "MIX", ops::BlendMode::from_blender)?,
                        non_uniform,
                        clamp_factor: p.bool_or("clamp_factor", true)?,
                        clamp_result: p.bool_or("clamp_result", false)?,
                    },
                    spec(&[fac, ("a", ty, dflt), ("b", ty, dflt)], &[("result", ty)]),
                )
            }
            "map_range" => {
                let vector = p.str_or("data_type", "FLOAT")? == "FLOAT_VECTOR";
                let op = NodeOp::MapRange {
                    interpolation: p.enum_or(
                        "interpolation_type",
                        "LINEAR",
                        ops::MapRangeInterpolation::from_blender,
                    )?,
                    clamp: p.bool_or("clamp", true)?,
                    vector,
                };
                if vector {
                    (
                        op,
                        spec(
                            &[
                                ("vector", Vector, V([0.0; 3])),
                                ("from_min_float3", Vector, V([0.0; 3])),
                                ("from_max_float3", Vector, V([1.0; 3])),
                                ("to_min_float3", Vector, V([0.0; 3])),
                                ("to_max_float3", Vector, V([1.0; 3])),
                                ("steps_float3", Vector, V([4.0; 3])),
                            ],
                            &[("vector", Vector)],
                        ),
                    )
                } else {
                    (
                        op,
                        spec(
                            &[
                                ("value", Float, F(1.0)),
                                ("from_min", Float, F(0.0)),
                                ("from_max", Float, F(1.0)),
                                ("to_min", Float, F(0.0)),
                                ("to_max", Float, F(1.0)),
                                ("steps", Float, F(4.0)),
                            ],
                            &[("result", Float)],
                        ),
                    )
                }
            }
            "clamp" => (
                NodeOp::Clamp(p.enum_or("clamp_type", "MINMAX", ops::ClampType::from_blender)?),
                spec(
                    &[
                        ("value", Float, F(1.0)),
                        ("min", Float, F(0.0)),
                        ("max", Float, F(1.0)),
                    ],
                    &[("result", Float)],
                ),
            ),
            "color_ramp" => (
                NodeOp::ColorRamp(Box::new(color_ramp(p)?.bake())),
                spec(
                    &[("fac", Float, F(0.5))],
                    &[("color", Color), ("alpha", Float)],
                ),
            ),
            "rgb_curves" => {
                let c = curves(p, 4)?;
                (
                    NodeOp::RgbCurves(Box::new(ops::RgbCurves::new(&c[3], &c[0], &c[1], &c[2]))),
                    spec(
                        &[("fac", Float, F(1.0)), ("color", Color, V([1.0; 3]))],
                        &[("color", Color)],
                    ),
                )
            }
            "float_curve" => {
                let c = curves(p, 1)?;
                (
                    NodeOp::FloatCurve(Box::new(ops::FloatCurve::new(&c[0]))),
                    spec(
                        &[("factor", Float, F(1.0)), ("value", Float, F(1.0))],
                        &[("value", Float)],
                    ),
                )
            }
            "hue_saturation" => (
                NodeOp::HueSaturation,
                spec(
                    &[
                        ("hue", Float, F(0.5)),
                        ("saturation", Float, F(1.0)),
                        ("value", Float, F(1.0)),
                        ("fac", Float, F(1.0)),
                        ("color", Color, V([0.8; 3])),
                    ],
                    &[("color", Color)],
                ),
            ),
            "bright_contrast" => (
                NodeOp::BrightContrast,
                spec(
                    &[
                        ("color", Color, V([1.0; 3])),
                        ("bright", Float, F(0.0)),
                        ("contrast", Float, F(0.0)),
                    ],
                    &[("color", Color)],
                ),
            ),
            "gamma" => (
                NodeOp::Gamma,
                spec(
                    &[("color", Color, V([1.0; 3])), ("gamma", Float, F(1.0))],
                    &[("color", Color)],
                ),
            ),
            "rgb_to_bw" => (
                NodeOp::RgbToBw,
                spec(&[("color", Color, V([0.5; 3]))], &[("val", Float)]),
            ),
            "separate_color" => (
                NodeOp::SeparateColor(p.enum_or("mode", "RGB", ops::ColorMode::from_blender)?),
                spec(
                    &[("color", Color, V([0.8; 3]))],
                    &[("red", Float), ("green", Float), ("blue", Float)],
                ),
            ),
            "combine_color" => (
                NodeOp::CombineColor(p.enum_or("mode", "RGB", ops::ColorMode::from_blender)?),
                spec(
                    &[
                        ("red", Float, F(0.0)),
                        ("green", Float, F(0.0)),
                        ("blue", Float, F(0.0)),
                    ],
                    &[("color", Color)],
                ),
            ),
            "blackbody" => (
                NodeOp::Blackbody,
                spec(&[("temperature", Float, F(1500.0))], &[("color", Color)]),
            ),
            "vector_rotate" => (
                NodeOp::VectorRotate {
                    kind: p.enum_or(
                        "rotation_type",
                        "AXIS_ANGLE",
                        ops::RotateType::from_blender,
                    )?,
                    invert: p.bool_or("invert", false)?,
                },
                spec(
                    &[
                        ("vector", Vector, V([0.0; 3])),
                        ("center", Vector, V([0.0; 3])),
                        ("axis", Vector, V([0.0, 0.0, 1.0])),
                        ("angle", Float, F(0.0)),
                        ("rotation", Vector, V([0.0; 3])),
                    ],
                    &[("vector", Vector)],
                ),
            ),
            "wavelength" => (
                NodeOp::Wavelength,
                spec(&[("wavelength", Float, F(500.0))], &[("color", Color)]),
            ),
            _ => return Ok(None),
        }))
    }
}

/// The Color Ramp of a node's `params`: `stops` as `[position, r, g, b, a]` rows,
/// `interpolation`, `color_mode`, `hue_interpolation` (Blender's identifiers).
fn color_ramp(p: &ParamReader) -> Result<ops::ColorRamp> {
    let rows = p.rows("stops", 5)?;
    if rows.is_empty() {
        return Err(p.err("stops", "a ColorRamp needs at least one stop"));
    }
    let stops = rows
        .iter()
        .map(|r| ops::ColorStop {
            position: r[0],
            color: Vec4::new(r[1], r[2], r[3], r[4]),
        })
        .collect();
    Ok(ops::ColorRamp::new(
        stops,
        p.enum_or(
            "interpolation",
            "LINEAR",
            ops::RampInterpolation::from_blender,
        )?,
        p.enum_or("color_mode", "RGB", ops::RampColorMode::from_blender)?,
        p.enum_or(
            "hue_interpolation",
            "NEAR",
            ops::HueInterpolation::from_blender,
        )?,
    ))
}

/// The `n` curves of a curve node's `params`: `curves` as lists of `[x, y, handle]` points
/// (handle 0 auto, 1 auto-clamped, 2 vector), `clip` the table's x range, `extend`.
fn curves(p: &ParamReader, n: usize) -> Result<Vec<ops::CurveMap>> {
    let Some(list) = p.node.params.get("curves").and_then(|v| v.as_array()) else {
        return Err(p.err("curves", format!("must be a list of {n} curves")));
    };
    if list.len() != n {
        return Err(p.err("curves", format!("must be a list of {n} curves")));
    }
    let (lo, hi) = match p.node.params.get("clip").and_then(|v| v.as_array()) {
        Some(a) if a.len() == 2 => (
            a[0].as_f64().unwrap_or(0.0) as f32,
            a[1].as_f64().unwrap_or(1.0) as f32,
        ),
        _ => (0.0, 1.0),
    };
    let extend = p.enum_or("extend", "EXTRAPOLATED", ops::CurveExtend::from_blender)?;
    let mut out = Vec::with_capacity(n);
    for (k, c) in list.iter().enumerate() {
        let bad = || {
            p.err(
                &format!("curves/{k}"),
                "must be a list of [x, y, handle] points",
            )
        };
        let pts = c.as_array().ok_or_else(bad)?;
        let mut points = Vec::with_capacity(pts.len());
        for pt in pts {
            let a = pt.as_array().filter(|a| a.len() == 3).ok_or_else(bad)?;
            let num = |i: usize| a[i].as_f64().filter(|x| x.is_finite()).map(|x| x as f32);
            let (Some(x), Some(y), Some(h)) = (num(0), num(1), num(2)) else {
                return Err(bad());
            };
            let handle = match h as i32 {
                1 => ops::HandleType::AutoClamped,
                2 => ops::HandleType::Vector,
                _ => ops::HandleType::Auto,
            };
            points.push(ops::CurvePoint::new(x, y, handle));
        }
        if points.is_empty() {
            return Err(bad());
        }
        out.push(ops::CurveMap::with_clip_x(&points, extend, lo, hi));
    }
    Ok(out)
}
