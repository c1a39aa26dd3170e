//! Converter and texture nodes: their sockets, and how they run. Socket names are Blender's
//! identifiers in snake case; properties are read from `params` by their Blender names.

use super::program::EvalCtx;
use super::spec::{Dflt, NodeSpec, ParamReader, Ty};
use super::tex::{self, Dimensions};
use crate::error::Result;
use glam::Vec3;

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
}

const VECTOR: (&str, Ty, Dflt) = ("vector", Ty::Vector, Dflt::Generated);

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
    ];

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
            _ => return Ok(None),
        }))
    }

    /// Runs the node on its inputs (in socket order) into `out`.
    pub fn run(&self, inp: &[Vec3], out: &mut [Vec3; 8], _ctx: &EvalCtx) {
        let x = |k: usize| inp.get(k).map_or(0.0, |v| v.x);
        let v = |k: usize| inp.get(k).copied().unwrap_or(Vec3::ZERO);
        let f = |a: f32| Vec3::new(a, 0.0, 0.0);
        match self {
            NodeOp::Splat => out[0] = Vec3::splat(x(0)),
            NodeOp::Invert => out[0] = v(1).lerp(Vec3::ONE - v(1), x(0)),
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
