//! From an IR graph to a [`Program`] and its closure leaves: nodes nothing reads are
//! skipped, nodes whose inputs are all constant are evaluated here, and the Bump node's
//! height is compiled once per tangent offset.

use super::closure::{Leaf, LeafKind};
use super::geometry_nodes::{ImageProjection, MappingKind, NormalSpace};
use super::nodes::NodeOp;
use super::point::ShadingPoint;
use super::program::{EvalCtx, Instr, Op, Program, Reg, MAX_REGS, NO_REG};
use super::spec::{Dflt, NodeSpec, ParamReader, Ty};
use crate::error::{Error, Result};
use crate::materials::texture::Interp;
use crate::scene::graph_desc::{GraphDesc, InputDesc, LinkDesc, NodeDesc};
use glam::Vec3;
use std::collections::HashMap;

/// What a node compiles to.
enum Kind {
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

/// A compiled graph.
#[derive(Clone, Debug, PartialEq)]
pub struct Compiled {
    pub program: Program,
    pub leaves: Vec<Leaf>,
    /// The shading normal of the closures (`NO_REG`: the surface's).
    pub normal: Reg,
    /// With a displacement: the instructions that compute it come first, up to the first
    /// field, and give the displaced normal in the register of the second; the rest of the
    /// program runs at the point with that normal.
    pub displaced: Option<(usize, Reg)>,
    /// What renders other than the graph says, naming the node.
    pub warnings: Vec<String>,
}

struct Builder<'a> {
    desc: &'a GraphDesc,
    pointer: &'a str,
    n_textures: usize,
    init: Vec<Vec3>,
    konst: Vec<bool>,
    code: Vec<Instr>,
    memo: HashMap<(u32, u8), Vec<Reg>>,
    moves: HashMap<u32, bool>,
    active: Vec<u32>,
    leaves: Vec<Leaf>,
    warnings: Vec<String>,
}

fn node_label(n: &NodeDesc) -> String {
    if n.name.is_empty() {
        format!("'{}'", n.kind)
    } else {
        format!("'{}' ({})", n.name, n.kind)
    }
}

impl<'a> Builder<'a> {
    fn err(&self, at: &str, message: impl Into<String>) -> Error {
        Error::InvalidScene {
            pointer: format!("{}{at}", self.pointer),
            object: self.desc.name.clone(),
            message: message.into(),
        }
    }

    fn node(&self, i: u32, at: &str) -> Result<&'a NodeDesc> {
        self.desc.nodes.get(i as usize).ok_or_else(|| {
            self.err(
                at,
                format!(
                    "links to node {i}, but the graph has {} nodes",
                    self.desc.nodes.len()
                ),
            )
        })
    }

    fn reader(&self, i: u32) -> ParamReader<'a> {
        ParamReader {
            node: &self.desc.nodes[i as usize],
            pointer: format!("{}/nodes/{i}", self.pointer),
            material: self.desc.name.clone(),
        }
    }

    fn reg(&mut self, v: Vec3, konst: bool) -> Result<Reg> {
        if self.init.len() >= MAX_REGS {
            return Err(self.err(
                "/nodes",
                format!("the graph needs more than {MAX_REGS} registers; simplify it"),
            ));
        }
        self.init.push(v);
        self.konst.push(konst);
        Ok((self.init.len() - 1) as Reg)
    }

    fn is_const(&self, r: Reg) -> bool {
        r != NO_REG && self.konst[r as usize]
    }

    fn kind(&mut self, i: u32) -> Result<(Kind, NodeSpec)> {
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

    /// Whether node `i`'s value changes when the shading point moves along the surface.
    fn moves(&mut self, i: u32) -> Result<bool> {
        if let Some(&m) = self.moves.get(&i) {
            return Ok(m);
        }
        if self.active.contains(&i) {
            return Err(self.err(
                &format!("/nodes/{i}"),
                "the graph has a cycle through this node",
            ));
        }
        self.active.push(i);
        let (kind, spec) = self.kind(i)?;
        let mut m = matches!(kind, Kind::Value { moves: true, .. });
        let n = &self.desc.nodes[i as usize];
        for (name, _, dflt) in &spec.ins {
            m |= match n.inputs.get(*name) {
                Some(InputDesc::Link(l)) => {
                    self.node(l.node, &format!("/nodes/{i}/inputs/{name}"))?;
                    self.moves(l.node)?
                }
                Some(_) => false,
                None => matches!(dflt, Dflt::Generated | Dflt::Uv),
            };
        }
        self.active.pop();
        self.moves.insert(i, m);
        Ok(m)
    }

    /// Every input the node is given must be one of its sockets.
    fn check_inputs(&self, i: u32, spec: &NodeSpec) -> Result<()> {
        let n = &self.desc.nodes[i as usize];
        for name in n.inputs.keys() {
            if !spec.ins.iter().any(|(s, _, _)| s == name) {
                let known: Vec<&str> = spec.ins.iter().map(|(s, _, _)| *s).collect();
                return Err(self.err(
                    &format!("/nodes/{i}/inputs/{name}"),
                    format!(
                        "node {} has no input '{name}' (its inputs: {})",
                        node_label(n),
                        known.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Registers of node `i`'s outputs, computed at tangent offset `variant`.
    fn values(&mut self, i: u32, variant: u8) -> Result<Vec<Reg>> {
        let variant = if variant > 0 && !self.moves(i)? {
            0
        } else {
            variant
        };
        if let Some(r) = self.memo.get(&(i, variant)) {
            return Ok(r.clone());
        }
        if self.active.contains(&i) {
            return Err(self.err(
                &format!("/nodes/{i}"),
                "the graph has a cycle through this node",
            ));
        }
        self.active.push(i);
        let (kind, spec) = self.kind(i)?;
        let n = &self.desc.nodes[i as usize];
        self.check_inputs(i, &spec)?;
        let out = match kind {
            Kind::Const(v) => vec![self.reg(v, true)?],
            Kind::Value {
                op, reads_point, ..
            } => {
                let mut ins = Vec::with_capacity(spec.ins.len() + 2);
                for (name, ty, dflt) in &spec.ins {
                    if matches!(op, Op::Bump { .. }) && *name == "height" {
                        for v in 0..3u8 {
                            ins.push(self.input(i, name, *ty, *dflt, v)?);
                        }
                    } else {
                        ins.push(self.input(i, name, *ty, *dflt, variant)?);
                    }
                }
                let op = match op {
                    Op::TexCoord { .. } => Op::TexCoord { variant },
                    Op::Geometry { .. } => Op::Geometry { variant },
                    Op::UvMap { key, .. } => Op::UvMap { variant, key },
                    Op::Attribute { key, fallback, .. } => Op::Attribute {
                        key,
                        fallback,
                        variant,
                    },
                    op => op,
                };
                let mut outs = Vec::with_capacity(spec.outs.len());
                let fold = !reads_point && ins.iter().all(|&r| self.is_const(r));
                for _ in &spec.outs {
                    outs.push(self.reg(Vec3::ZERO, fold)?);
                }
                let instr = Instr {
                    op,
                    ins: ins.into(),
                    outs: outs.clone().into(),
                };
                if fold {
                    let sp = ShadingPoint::at(Vec3::ZERO, Vec3::Z, glam::Vec2::ZERO);
                    let ctx = EvalCtx::new(&sp, &[]);
                    instr.run(&mut self.init, &ctx);
                } else {
                    self.code.push(instr);
                }
                outs
            }
            Kind::Leaf(_) | Kind::Mix | Kind::Add => {
                return Err(self.err(
                    &format!("/nodes/{i}"),
                    format!(
                        "node {} is a shader, linked to a value input",
                        node_label(n)
                    ),
                ))
            }
        };
        self.active.pop();
        self.memo.insert((i, variant), out.clone());
        Ok(out)
    }

    /// The register an input of node `i` reads, converted to `ty`.
    fn input(&mut self, i: u32, name: &str, ty: Ty, dflt: Dflt, variant: u8) -> Result<Reg> {
        let at = format!("/nodes/{i}/inputs/{name}");
        match self.desc.nodes[i as usize].inputs.get(name) {
            Some(InputDesc::Float(v)) => {
                if !v.is_finite() {
                    return Err(self.err(&at, format!("must be finite, got {v}")));
                }
                let r = self.reg(Vec3::new(*v, 0.0, 0.0), true)?;
                Ok(self.splat_if(r, ty, *v))
            }
            Some(InputDesc::Vector(v)) => {
                if v.iter().any(|x| !x.is_finite())
                    || !(v.len() == 3 || v.len() == 4 || v.len() == 1)
                {
                    return Err(self.err(&at, "must be 1, 3 or 4 finite numbers"));
                }
                let c = if v.len() == 1 {
                    Vec3::splat(v[0])
                } else {
                    Vec3::new(v[0], v[1], v[2])
                };
                let c = if ty == Ty::Float {
                    Vec3::new(c.x, 0.0, 0.0)
                } else {
                    c
                };
                self.reg(c, true)
            }
            Some(InputDesc::Link(l)) => self.link(l, ty, variant, &at),
            None => match dflt {
                Dflt::F(v) => self.reg(Vec3::new(v, 0.0, 0.0), true),
                Dflt::V(v) => self.reg(Vec3::from(v), true),
                Dflt::Normal => Ok(NO_REG),
                Dflt::Generated => self.implicit(Op::TexCoord { variant }, 5, 0),
                Dflt::Uv => self.implicit(Op::UvMap { variant, key: None }, 1, 0),
                Dflt::Empty => Ok(NO_REG),
            },
        }
    }

    fn splat_if(&mut self, r: Reg, ty: Ty, v: f32) -> Reg {
        if ty != Ty::Float {
            self.init[r as usize] = Vec3::splat(v);
        }
        r
    }

    /// An implicit source (a texture's default coordinates), shared by every node.
    fn implicit(&mut self, op: Op, n_out: usize, which: usize) -> Result<Reg> {
        if let Some(ins) = self.code.iter().find(|c| c.op == op && c.ins.is_empty()) {
            return Ok(ins.outs[which]);
        }
        let mut outs = Vec::new();
        for _ in 0..n_out {
            outs.push(self.reg(Vec3::ZERO, false)?);
        }
        self.code.push(Instr {
            op,
            ins: Box::new([]),
            outs: outs.clone().into(),
        });
        Ok(outs[which])
    }

    /// The register of a linked output, converted to `ty`.
    fn link(&mut self, l: &LinkDesc, ty: Ty, variant: u8, at: &str) -> Result<Reg> {
        let src = self.node(l.node, at)?;
        let (_, spec) = self.kind(l.node)?;
        let k = if l.output.is_empty() {
            0
        } else {
            spec.outs
                .iter()
                .position(|(s, _)| *s == l.output)
                .ok_or_else(|| {
                    let known: Vec<&str> = spec.outs.iter().map(|(s, _)| *s).collect();
                    self.err(
                        at,
                        format!(
                            "node {} has no output '{}' (its outputs: {})",
                            node_label(src),
                            l.output,
                            known.join(", ")
                        ),
                    )
                })?
        };
        let from = spec.outs[k].1;
        if from == Ty::Closure || ty == Ty::Closure {
            return Err(self.err(at, "a shader output and a value input cannot be linked"));
        }
        let r = self.values(l.node, variant)?[k];
        let conv = match (from, ty) {
            (Ty::Color, Ty::Float) => Some(Op::Gray),
            (Ty::Vector, Ty::Float) => Some(Op::Average),
            (Ty::Float, Ty::Color | Ty::Vector) => Some(Op::Node(NodeOp::Splat)),
            _ => None,
        };
        let Some(op) = conv else { return Ok(r) };
        let fold = self.is_const(r);
        let out = self.reg(Vec3::ZERO, fold)?;
        let instr = Instr {
            op,
            ins: Box::new([r]),
            outs: Box::new([out]),
        };
        if fold {
            let sp = ShadingPoint::at(Vec3::ZERO, Vec3::Z, glam::Vec2::ZERO);
            instr.run(&mut self.init, &EvalCtx::new(&sp, &[]));
        } else {
            self.code.push(instr);
        }
        Ok(out)
    }

    /// Collects the closure leaves under `link`, each weighted by the product of the mix
    /// factors above it.
    fn closure(&mut self, link: &LinkDesc, weight: &[(Reg, bool)], at: &str) -> Result<()> {
        let i = link.node;
        let n = self.node(i, at)?;
        if self.active.contains(&i) {
            return Err(self.err(
                &format!("/nodes/{i}"),
                "the graph has a cycle through this node",
            ));
        }
        let (kind, spec) = self.kind(i)?;
        self.check_inputs(i, &spec)?;
        let shader = |name: &str| match n.inputs.get(name) {
            Some(InputDesc::Link(l)) => Some(l.clone()),
            _ => None,
        };
        self.active.push(i);
        match kind {
            Kind::Mix => {
                let fac = self.input(i, "fac", Ty::Float, Dflt::F(0.5), 0)?;
                for (name, complement) in [("shader1", true), ("shader2", false)] {
                    if let Some(l) = shader(name) {
                        let mut w = weight.to_vec();
                        w.push((fac, complement));
                        if !self.is_zero(&w) {
                            self.closure(&l, &w, &format!("/nodes/{i}/inputs/{name}"))?;
                        }
                    }
                }
            }
            Kind::Add => {
                for name in ["shader1", "shader2"] {
                    if let Some(l) = shader(name) {
                        self.closure(&l, weight, &format!("/nodes/{i}/inputs/{name}"))?;
                    }
                }
            }
            Kind::Leaf(kind) => {
                let mut ins = Vec::with_capacity(spec.ins.len());
                for (name, ty, dflt) in &spec.ins {
                    ins.push(self.input(i, name, *ty, *dflt, 0)?);
                }
                for w in kind.warnings(&ins, &self.init, &self.konst, &spec) {
                    self.warnings.push(format!(
                        "material '{}': node {}: {w}",
                        self.desc.name,
                        node_label(n)
                    ));
                }
                self.leaves.push(Leaf {
                    kind,
                    weight: weight.to_vec(),
                    ins,
                    node: i,
                });
            }
            Kind::Value { .. } | Kind::Const(_) => {
                return Err(self.err(
                    at,
                    format!(
                        "node {} is not a shader, linked to a shader input",
                        node_label(n)
                    ),
                ))
            }
        }
        self.active.pop();
        Ok(())
    }

    /// Compiles the displacement `link` as a bump of the shading normal: the offset at the
    /// point and at the two tangent offsets, then the bumped normal. None when the offset
    /// does not change over the surface (no bump). What follows is compiled afresh, so that
    /// the nodes the surface reads see the displaced normal.
    fn displacement(&mut self, link: &LinkDesc) -> Result<Option<(usize, Reg)>> {
        let mut d = [NO_REG; 3];
        for (v, r) in d.iter_mut().enumerate() {
            *r = self.link(link, Ty::Vector, v as u8, "/displacement")?;
        }
        if d[1] == d[0] && d[2] == d[0] {
            return Ok(None);
        }
        let out = self.reg(Vec3::ZERO, false)?;
        self.code.push(Instr {
            op: Op::DisplacementBump,
            ins: d.into(),
            outs: Box::new([out]),
        });
        self.memo.clear();
        Ok(Some((self.code.len(), out)))
    }

    /// Whether a product of factors is the constant zero.
    fn is_zero(&self, w: &[(Reg, bool)]) -> bool {
        w.iter().any(|&(r, c)| {
            self.is_const(r) && {
                let f = self.init[r as usize].x.clamp(0.0, 1.0);
                (if c { 1.0 - f } else { f }) == 0.0
            }
        })
    }
}

/// The node types the compiler knows besides closures and [`NodeOp`]s.
pub(crate) const BUILTIN: &[&str] = &[
    "value",
    "rgb",
    "tex_coord",
    "geometry",
    "uv_map",
    "attribute",
    "object_info",
    "light_path",
    "layer_weight",
    "fresnel",
    "mapping",
    "separate_xyz",
    "combine_xyz",
    "normal_map",
    "bump",
    "displacement",
    "image_texture",
    "mix_shader",
    "add_shader",
];

/// Every node type with its sockets, as JSON: `{type: {"inputs": [[name, type], ...],
/// "outputs": [[name, type], ...]}}` (types `float`, `vector`, `color`, `closure`). Front
/// ends translate to these names.
pub fn node_specs() -> serde_json::Value {
    let mut out = serde_json::Map::new();
    let names = BUILTIN
        .iter()
        .chain(super::closure::LeafKind::TYPES)
        .chain(NodeOp::TYPES);
    let ty = |t: Ty| match t {
        Ty::Float => "float",
        Ty::Vector => "vector",
        Ty::Color => "color",
        Ty::Closure => "closure",
    };
    for name in names {
        // Properties a node cannot do without, for listing its sockets.
        let curve = serde_json::json!([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0]]);
        let n_curves = if *name == "rgb_curves" { 4 } else { 1 };
        let desc = GraphDesc {
            name: String::new(),
            nodes: vec![NodeDesc {
                kind: name.to_string(),
                params: [
                    ("texture".to_string(), serde_json::json!(0)),
                    ("color".to_string(), serde_json::json!([0.0, 0.0, 0.0])),
                    (
                        "stops".to_string(),
                        serde_json::json!([[0.0, 0.0, 0.0, 0.0, 1.0]]),
                    ),
                    (
                        "curves".to_string(),
                        serde_json::json!(vec![curve; n_curves]),
                    ),
                ]
                .into_iter()
                .collect(),
                ..Default::default()
            }],
            surface: None,
            displacement: None,
        };
        let mut b = builder(&desc, "", usize::MAX);
        if let Ok((_, spec)) = b.kind(0) {
            out.insert(
                name.to_string(),
                serde_json::json!({
                    "inputs": spec.ins.iter().map(|(n, t, _)| [*n, ty(*t)]).collect::<Vec<_>>(),
                    "outputs": spec.outs.iter().map(|(n, t)| [*n, ty(*t)]).collect::<Vec<_>>(),
                }),
            );
        }
    }
    serde_json::Value::Object(out)
}

fn builder<'a>(desc: &'a GraphDesc, pointer: &'a str, n_textures: usize) -> Builder<'a> {
    Builder {
        desc,
        pointer,
        n_textures,
        init: Vec::new(),
        konst: Vec::new(),
        code: Vec::new(),
        memo: HashMap::new(),
        moves: HashMap::new(),
        active: Vec::new(),
        leaves: Vec::new(),
        warnings: Vec::new(),
    }
}

/// Compiles the graph of material `pointer` (a JSON pointer such as `/materials/3`) for a
/// scene with `n_textures` textures.
pub fn compile(desc: &GraphDesc, pointer: &str, n_textures: usize) -> Result<Compiled> {
    let mut b = builder(desc, pointer, n_textures);
    let displaced = match &desc.displacement {
        Some(l) => b.displacement(l)?,
        None => None,
    };
    if let Some(s) = &desc.surface {
        b.closure(s, &[], "/surface")?;
    }
    // The closures share one shading frame: the first linked normal.
    let normals: Vec<Reg> = b
        .leaves
        .iter()
        .filter_map(|l| l.normal())
        .filter(|&r| r != NO_REG)
        .collect();
    let normal = normals.first().copied().unwrap_or(NO_REG);
    if normals.iter().any(|&r| r != normal)
        || (normal != NO_REG && b.leaves.iter().any(|l| l.normal() == Some(NO_REG)))
    {
        b.warnings.push(format!(
            "material '{}': its shaders have different normals; all use the first one's",
            desc.name
        ));
    }
    Ok(Compiled {
        program: Program {
            init: b.init,
            code: b.code,
        },
        leaves: b.leaves,
        normal,
        displaced,
        warnings: b.warnings,
    })
}
