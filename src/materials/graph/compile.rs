//! From an IR graph to a [`Program`] and its closure leaves: nodes nothing reads are
//! skipped, nodes whose inputs are all constant are evaluated here, and the Bump node's
//! height is compiled once per tangent offset.

mod closures;
mod node_types;

use super::closure::Leaf;
use super::nodes::NodeOp;
use super::point::ShadingPoint;
use super::program::{EvalCtx, Instr, Op, Program, Reg, MAX_REGS, NO_REG};
use super::spec::{Dflt, NodeSpec, ParamReader, Ty};
use crate::error::{Error, Result};
use crate::scene::graph_desc::{GraphDesc, InputDesc, LinkDesc, NodeDesc};
use glam::Vec3;
use node_types::Kind;
use std::collections::HashMap;

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
