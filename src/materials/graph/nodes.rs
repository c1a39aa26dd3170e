//! Converter and texture nodes: their sockets, and how they run. Socket names are Blender's
//! identifiers in snake case; properties are read from `params` by their Blender names.

mod parse;

use super::ops;
use super::program::EvalCtx;
use super::tex;
use glam::Vec3;
use glam::Vec4;

/// A converter or texture node with its properties.
#[derive(Clone, Debug, PartialEq)]
pub enum NodeOp {
    /// A float read as a colour or vector (all three components).
    Splat,
    /// Invert: inputs fac, color; output color.
    Invert,
    Noise(tex::NoiseTexture),
    Voronoi(tex::VoronoiTexture),
    WhiteNoise(tex::WhiteNoiseTexture),
    Checker(tex::CheckerTexture),
    Brick(tex::BrickTexture),
    Gradient(tex::GradientTexture),
    Wave(tex::WaveTexture),
    Magic(tex::MagicTexture),
    Math {
        op: ops::MathOp,
        clamp: bool,
    },
    VectorMath(ops::VectorMathOp),
    VectorRotate {
        kind: ops::RotateType,
        invert: bool,
    },
    Mix {
        data: ops::MixDataType,
        blend: ops::BlendMode,
        non_uniform: bool,
        clamp_factor: bool,
        clamp_result: bool,
    },
    MapRange {
        interpolation: ops::MapRangeInterpolation,
        clamp: bool,
        vector: bool,
    },
    Clamp(ops::ClampType),
    ColorRamp(Box<ops::ramp::BakedColorRamp>),
    RgbCurves(Box<ops::RgbCurves>),
    FloatCurve(Box<ops::FloatCurve>),
    HueSaturation,
    BrightContrast,
    Gamma,
    RgbToBw,
    SeparateColor(ops::ColorMode),
    CombineColor(ops::ColorMode),
    Blackbody,
    Wavelength,
}

impl NodeOp {
    /// The IR types of these nodes.
    pub const TYPES: &'static [&'static str] = &[
        "invert",
        "noise_texture",
        "voronoi_texture",
        "white_noise_texture",
        "checker_texture",
        "brick_texture",
        "gradient_texture",
        "wave_texture",
        "magic_texture",
        "math",
        "vector_math",
        "vector_rotate",
        "mix",
        "map_range",
        "clamp",
        "color_ramp",
        "rgb_curves",
        "float_curve",
        "hue_saturation",
        "bright_contrast",
        "gamma",
        "rgb_to_bw",
        "separate_color",
        "combine_color",
        "blackbody",
        "wavelength",
    ];

    /// Runs the node on its inputs (in socket order) into `out`.
    pub fn run(&self, inp: &[Vec3], out: &mut [Vec3; 8], _ctx: &EvalCtx) {
        let x = |k: usize| inp.get(k).map_or(0.0, |v| v.x);
        let v = |k: usize| inp.get(k).copied().unwrap_or(Vec3::ZERO);
        let f = |a: f32| Vec3::new(a, 0.0, 0.0);
        match self {
            NodeOp::Splat => out[0] = Vec3::splat(x(0)),
            NodeOp::Invert => out[0] = ops::invert(x(0), v(1)),
            NodeOp::Math { op, clamp } => out[0] = f(ops::math_node(*op, x(0), x(1), x(2), *clamp)),
            NodeOp::VectorMath(op) => {
                let o = ops::vector_math(*op, v(0), v(1), v(2), x(3));
                out[0] = o.vector;
                out[1] = f(o.value);
            }
            NodeOp::Mix {
                data,
                blend,
                non_uniform,
                clamp_factor,
                clamp_result,
            } => {
                out[0] = match data {
                    ops::MixDataType::Float => f(ops::mix_float(x(0), x(1), x(2), *clamp_factor)),
                    ops::MixDataType::Vector if *non_uniform => {
                        ops::mix_vector_non_uniform(v(0), v(1), v(2), *clamp_factor)
                    }
                    ops::MixDataType::Vector => ops::mix_vector(x(0), v(1), v(2), *clamp_factor),
                    ops::MixDataType::Rgba => {
                        ops::mix_color(*blend, x(0), v(1), v(2), *clamp_factor, *clamp_result)
                    }
                };
            }
            NodeOp::MapRange {
                interpolation,
                clamp,
                vector,
            } => {
                if *vector {
                    let m = ops::MapRange {
                        interpolation: *interpolation,
                        clamp: *clamp,
                        from_min: v(1),
                        from_max: v(2),
                        to_min: v(3),
                        to_max: v(4),
                        steps: v(5),
                    };
                    out[0] = m.eval(v(0));
                } else {
                    let m = ops::MapRange {
                        interpolation: *interpolation,
                        clamp: *clamp,
                        from_min: x(1),
                        from_max: x(2),
                        to_min: x(3),
                        to_max: x(4),
                        steps: x(5),
                    };
                    out[0] = f(m.eval(x(0)));
                }
            }
            NodeOp::Clamp(t) => out[0] = f(ops::clamp_node(*t, x(0), x(1), x(2))),
            NodeOp::ColorRamp(r) => {
                let c: Vec4 = r.eval(x(0));
                out[0] = c.truncate();
                out[1] = f(c.w);
            }
            NodeOp::RgbCurves(c) => out[0] = c.eval(x(0), v(1)),
            NodeOp::FloatCurve(c) => out[0] = f(c.eval(x(0), x(1))),
            NodeOp::HueSaturation => {
                out[0] = ops::hue_saturation_value(x(0), x(1), x(2), x(3), v(4))
            }
            NodeOp::BrightContrast => out[0] = ops::bright_contrast(v(0), x(1), x(2)),
            NodeOp::Gamma => out[0] = ops::gamma(v(0), x(1)),
            NodeOp::RgbToBw => out[0] = f(ops::rgb_to_bw(v(0))),
            NodeOp::SeparateColor(m) => {
                let c = ops::separate_color(*m, v(0));
                out[0] = f(c.x);
                out[1] = f(c.y);
                out[2] = f(c.z);
            }
            NodeOp::CombineColor(m) => out[0] = ops::combine_color(*m, Vec3::new(x(0), x(1), x(2))),
            NodeOp::VectorRotate { kind, invert } => {
                out[0] = ops::vector_rotate(*kind, *invert, v(0), v(1), v(2), x(3), v(4));
            }
            NodeOp::Blackbody => out[0] = ops::blackbody(x(0)),
            NodeOp::Wavelength => out[0] = ops::wavelength(x(0)),

            NodeOp::Noise(t) => {
                let o = t.eval(&tex::NoiseInputs {
                    vector: v(0),
                    w: x(1),
                    scale: x(2),
                    detail: x(3),
                    roughness: x(4),
                    lacunarity: x(5),
                    offset: x(6),
                    gain: x(7),
                    distortion: x(8),
                });
                out[0] = f(o.fac);
                out[1] = o.color;
            }
            NodeOp::Voronoi(t) => {
                let o = t.eval(&tex::VoronoiInputs {
                    vector: v(0),
                    w: x(1),
                    scale: x(2),
                    detail: x(3),
                    roughness: x(4),
                    lacunarity: x(5),
                    smoothness: x(6),
                    exponent: x(7),
                    randomness: x(8),
                });
                out[0] = f(o.distance);
                out[1] = o.color;
                out[2] = o.position;
                out[3] = f(o.w);
                out[4] = f(o.radius);
            }
            NodeOp::WhiteNoise(t) => {
                let o = t.eval(v(0), x(1));
                out[0] = f(o.value);
                out[1] = o.color;
            }
            NodeOp::Checker(t) => {
                let o = t.eval(&tex::CheckerInputs {
                    vector: v(0),
                    color1: v(1),
                    color2: v(2),
                    scale: x(3),
                });
                out[0] = o.color;
                out[1] = f(o.fac);
            }
            NodeOp::Brick(t) => {
                let o = t.eval(&tex::BrickInputs {
                    vector: v(0),
                    color1: v(1),
                    color2: v(2),
                    mortar: v(3),
                    scale: x(4),
                    mortar_size: x(5),
                    mortar_smooth: x(6),
                    bias: x(7),
                    brick_width: x(8),
                    row_height: x(9),
                });
                out[0] = o.color;
                out[1] = f(o.fac);
            }
            NodeOp::Gradient(t) => {
                let o = t.eval(v(0));
                out[0] = o.color;
                out[1] = f(o.fac);
            }
            NodeOp::Wave(t) => {
                let o = t.eval(&tex::WaveInputs {
                    vector: v(0),
                    scale: x(1),
                    distortion: x(2),
                    detail: x(3),
                    detail_scale: x(4),
                    detail_roughness: x(5),
                    phase_offset: x(6),
                });
                out[0] = o.color;
                out[1] = f(o.fac);
            }
            NodeOp::Magic(t) => {
                let o = t.eval(&tex::MagicInputs {
                    vector: v(0),
                    scale: x(1),
                    distortion: x(2),
                });
                out[0] = o.color;
                out[1] = f(o.fac);
            }
        }
    }
}
