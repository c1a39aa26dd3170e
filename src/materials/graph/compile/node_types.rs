//! The node types the compiler knows: what each compiles to (an operation, a constant, a
//! closure leaf, Mix or Add) with its sockets.

use super::{node_label, Builder};
use crate::error::Result;
use crate::materials::graph::closure::LeafKind;
use crate::materials::graph::geometry_nodes::{ImageProjection, MappingKind, NormalSpace};
use crate::materials::graph::nodes::NodeOp;
use crate::materials::graph::program::Op;
use crate::materials::graph::spec::{Dflt, NodeSpec, Ty};
use crate::materials::texture::Interp;
use glam::Vec3;

/// What a node compiles to.
pub(super) enum Kind {
    /// A value node: an operation, and whether it reads the shading point (never folded).
    Value {
        op: Op,
        reads_point: bool,
        moves: bool,
    },
    /// A constant (Value, RGB).
    Const(Vec3),
    Leaf(LeafKind),
    Mix,
    Add,
}

impl<'a> Builder<'a> {
    pub(super) fn kind(&mut self, i: u32) -> Result<(Kind, NodeSpec)> {
        let n = &self.desc.nodes[i as usize];
        let p = self.reader(i);
        use Dflt::*;
        use Ty::*;
        let spec = NodeSpec::new;
        let value = |op, reads_point, moves| Kind::Value {
            op,
            reads_point,
            moves,
        };
        let normal = ("normal", Vector, Normal);
        Ok(match n.kind.as_str() {
            "value" => (
                Kind::Const(Vec3::new(p.f32_or("value", 0.0)?, 0.0, 0.0)),
                spec(&[], &[("value", Float)]),
            ),
            "rgb" => {
                let v = match n.params.get("color").and_then(|v| v.as_array()) {
                    Some(a) if a.len() >= 3 => Vec3::new(
                        a[0].as_f64().unwrap_or(0.0) as f32,
                        a[1].as_f64().unwrap_or(0.0) as f32,
                        a[2].as_f64().unwrap_or(0.0) as f32,
                    ),
                    _ => return Err(p.err("color", "must be a list of 3 numbers")),
                };
                (Kind::Const(v), spec(&[], &[("color", Color)]))
            }
            "tex_coord" => (
                value(Op::TexCoord { variant: 0 }, true, true),
                spec(
                    &[],
                    &[
                        ("generated", Vector),
                        ("normal", Vector),
                        ("uv", Vector),
                        ("object", Vector),
                        ("reflection", Vector),
                    ],
                ),
            ),
            "geometry" => (
                value(Op::Geometry { variant: 0 }, true, true),
                spec(
                    &[],
                    &[
                        ("position", Vector),
                        ("normal", Vector),
                        ("tangent", Vector),
                        ("true_normal", Vector),
                        ("incoming", Vector),
                        ("parametric", Vector),
                        ("backfacing", Float),
                    ],
                ),
            ),
            "uv_map" => (
                value(
                    Op::UvMap {
                        variant: 0,
                        key: match p.str_or("uv_map", "")? {
                            "" => None,
                            name => Some(crate::geometry::attribute_key(name)),
                        },
                    },
                    true,
                    true,
                ),
                spec(&[], &[("uv", Vector)]),
            ),
            "attribute" => (
                value(
                    Op::Attribute {
                        key: crate::geometry::attribute_key(p.str_or("name", "")?),
                        fallback: match n.params.get("fallback") {
                            None => glam::Vec4::ZERO,
                            Some(v) => {
                                let bad =
                                    || p.err("fallback", "must be a list of 4 numbers (RGBA)");
                                let a = v.as_array().filter(|a| a.len() == 4).ok_or_else(bad)?;
                                let mut f = [0.0f32; 4];
                                for (k, x) in a.iter().enumerate() {
                                    f[k] = x.as_f64().filter(|x| x.is_finite()).ok_or_else(bad)?
                                        as f32;
                                }
                                glam::Vec4::from(f)
                            }
                        },
                        variant: 0,
                    },
                    true,
                    true,
                ),
                spec(
                    &[],
                    &[
                        ("color", Color),
                        ("vector", Vector),
                        ("fac", Float),
                        ("alpha", Float),
                    ],
                ),
            ),
            "object_info" => (
                value(Op::ObjectInfo, true, false),
                spec(
                    &[],
                    &[
                        ("location", Vector),
                        ("random", Float),
                        ("object_index", Float),
                    ],
                ),
            ),
            "light_path" => (
                value(Op::LightPath, true, false),
                spec(
                    &[],
                    &[
                        ("is_camera_ray", Float),
                        ("is_shadow_ray", Float),
                        ("is_diffuse_ray", Float),
                        ("is_glossy_ray", Float),
                        ("is_singular_ray", Float),
                        ("is_reflection_ray", Float),
                        ("is_transmission_ray", Float),
                        ("is_volume_scatter_ray", Float),
                        ("ray_length", Float),
                        ("ray_depth", Float),
                        ("diffuse_depth", Float),
                        ("glossy_depth", Float),
                        ("transparent_depth", Float),
                        ("transmission_depth", Float),
                        ("portal_depth", Float),
                    ],
                ),
            ),
            "layer_weight" => (
                value(Op::LayerWeight, true, false),
                spec(
                    &[("blend", Float, F(0.5)), normal],
                    &[("fresnel", Float), ("facing", Float)],
                ),
            ),
            "fresnel" => (
                value(Op::Fresnel, true, false),
                spec(&[("ior", Float, F(1.5)), normal], &[("fac", Float)]),
            ),
            "mapping" => (
                value(
                    Op::Mapping(p.enum_or("vector_type", "POINT", MappingKind::from_blender)?),
                    false,
                    false,
                ),
                spec(
                    &[
                        ("vector", Vector, V([0.0; 3])),
                        ("location", Vector, V([0.0; 3])),
                        ("rotation", Vector, V([0.0; 3])),
                        ("scale", Vector, V([1.0; 3])),
                    ],
                    &[("vector", Vector)],
                ),
            ),
            "separate_xyz" => (
                value(Op::SeparateXyz, false, false),
                spec(
                    &[("vector", Vector, V([0.0; 3]))],
                    &[("x", Float), ("y", Float), ("z", Float)],
                ),
            ),
            "combine_xyz" => (
                value(Op::CombineXyz, false, false),
                spec(
                    &[
                        ("x", Float, F(0.0)),
                        ("y", Float, F(0.0)),
                        ("z", Float, F(0.0)),
                    ],
                    &[("vector", Vector)],
                ),
            ),
            "normal_map" => (
                value(
                    Op::NormalMap(p.enum_or("space", "TANGENT", NormalSpace::from_blender)?),
                    true,
                    false,
                ),
                spec(
                    &[
                        ("strength", Float, F(1.0)),
                        ("color", Color, V([0.5, 0.5, 1.0])),
                    ],
                    &[("normal", Vector)],
                ),
            ),
            "bump" => (
                value(
                    Op::Bump {
                        invert: p.bool_or("invert", false)?,
                    },
                    true,
                    false,
                ),
                spec(
                    &[
                        ("strength", Float, F(1.0)),
                        ("distance", Float, F(0.001)),
                        ("height", Float, F(1.0)),
                        normal,
                        // Cycles' finite difference spans this fraction of the pixel's
                        // footprint; the height's gradient is taken at a far smaller step.
                        ("filter_width", Float, F(0.1)),
                    ],
                    &[("normal", Vector)],
                ),
            ),
            "displacement" => (
                value(
                    Op::Displacement {
                        object: p.enum_or("space", "OBJECT", |s| match s {
                            "OBJECT" => Some(true),
                            "WORLD" => Some(false),
                            _ => None,
                        })?,
                    },
                    true,
                    false,
                ),
                spec(
                    &[
                        ("height", Float, F(0.0)),
                        ("midlevel", Float, F(0.5)),
                        ("scale", Float, F(1.0)),
                        normal,
                    ],
                    &[("displacement", Vector)],
                ),
            ),
            "image_texture" => {
                let t = p.u32_or("texture", u32::MAX)?;
                if t as usize >= self.n_textures {
                    return Err(p.err(
                        "texture",
                        format!("must name one of the scene's {} textures", self.n_textures),
                    ));
                }
                let interp = p.enum_or("interpolation", "Linear", Interp::from_blender)?;
                let image = |projection| Op::Image {
                    texture: t,
                    interp,
                    projection,
                };
                let op = match p.str_or("projection", "FLAT")? {
                    "BOX" => Op::ImageBox {
                        texture: t,
                        blend: p.f32_or("projection_blend", 0.0)?.clamp(0.0, 1.0),
                        interp,
                    },
                    "FLAT" => image(ImageProjection::Flat),
                    "SPHERE" => image(ImageProjection::Sphere),
                    "TUBE" => image(ImageProjection::Tube),
                    other => return Err(p.err("projection", format!("unknown value '{other}'"))),
                };
                let box_ = matches!(op, Op::ImageBox { .. });
                (
                    value(op, box_, false),
                    spec(
                        &[("vector", Vector, Uv)],
                        &[("color", Color), ("alpha", Float)],
                    ),
                )
            }
            "mix_shader" => (
                Kind::Mix,
                spec(
                    &[
                        ("fac", Float, F(0.5)),
                        ("shader1", Closure, Empty),
                        ("shader2", Closure, Empty),
                    ],
                    &[("shader", Closure)],
                ),
            ),
            "add_shader" => (
                Kind::Add,
                spec(
                    &[("shader1", Closure, Empty), ("shader2", Closure, Empty)],
                    &[("shader", Closure)],
                ),
            ),
            other => {
                if let Some((k, s)) = LeafKind::parse(other, &p)? {
                    (Kind::Leaf(k), s)
                } else if let Some((op, s)) = NodeOp::parse(other, &p)? {
                    (value(Op::Node(op), false, false), s)
                } else {
                    return Err(self.err(
                        &format!("/nodes/{i}/type"),
                        format!("node {}: unknown node type '{other}'", node_label(n)),
                    ));
                }
            }
        })
    }
}
