//! Shading graphs: a material as a tree of closures combined by Mix and Add, whose inputs are
//! node expressions, compiled once per scene into a flat program run at every shading point.
//!
//! - [`spec`]: socket types and defaults; [`compile`]: IR -> [`program::Program`] + closure
//!   leaves; [`program`]: the instructions and the register machine;
//! - [`closure`]: closure leaves and their sum as one BSDF; [`geometry_nodes`]: the nodes
//!   that read the shading point ([`point`]);
//! - [`nodes`]: converters and textures as instructions; [`tex`]: procedural textures with
//!   Cycles' semantics (value for value); [`ops`]: converters (Math, Mix, ColorRamp, ...).
//!
//! A material whose graph is one closure with constant inputs compiles to the plain
//! material it is, and costs what that material costs.

pub mod closure;
pub mod compile;
pub mod geometry_nodes;
pub mod nodes;
pub mod ops;
pub mod point;
pub mod program;
pub mod spec;
pub mod tex;

use crate::error::Result;
use crate::materials::bsdf::Bsdf;
use crate::materials::texture::Texture;
use crate::math::{Frame, Spectrum};
use crate::scene::graph_desc::GraphDesc;
use closure::{LeafTables, Shaded};
use compile::Compiled;
use glam::Vec3;
use point::ShadingPoint;
use program::{EvalCtx, Op, NO_REG};
use std::cell::RefCell;

/// What a scene's shading graphs compiled to (the stats' `shading_graphs`).
///
/// | field | meaning |
/// |---|---|
/// | `graphs` | materials given as graphs in the IR |
/// | `folded` | of those, graphs that were one constant closure, rendered as plain materials |
/// | `instructions` | instructions run per shading point, summed over the other graphs |
/// | `leaves` | closure leaves, summed over the other graphs |
/// | `tangent_meshes` | meshes given tangents (MikkTSpace's frames) for a tangent-space Normal Map |
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct GraphStats {
    pub graphs: usize,
    pub folded: usize,
    pub instructions: usize,
    pub leaves: usize,
    /// Meshes given tangents for a tangent-space Normal Map.
    pub tangent_meshes: usize,
}

/// A compiled shading graph.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderGraph {
    pub name: String,
    compiled: Compiled,
    tables: Vec<LeafTables>,
    emissive: bool,
    specular: bool,
    transparent: bool,
    scatters: bool,
    holds_out: bool,
    /// Whether a node reads object space, the texture space or Object Info.
    pub needs_object: bool,
    /// Whether a tangent-space Normal Map reads the mesh's tangents.
    pub needs_tangents: bool,
}

thread_local! {
    static REGS: RefCell<Vec<Vec3>> = const { RefCell::new(Vec::new()) };
}

/// What a caller needs from [`ShaderGraph::shade`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Want {
    /// BSDF, emission and transparency.
    All,
    /// Emission and transparency only (no BSDF is built).
    Light,
}

impl ShaderGraph {
    /// Compiles `desc`, the material at JSON pointer `pointer`, in a scene of `n_textures`.
    pub fn new(desc: &GraphDesc, pointer: &str, n_textures: usize) -> Result<Self> {
        let compiled = compile::compile(desc, pointer, n_textures)?;
        let (init, konst) = (&compiled.program.init, const_mask(&compiled));
        let tables = compiled
            .leaves
            .iter()
            .map(|l| LeafTables::new(l, &konst, init))
            .collect();
        let any = |f: fn(&closure::Leaf, &[bool], &[Vec3]) -> bool| {
            compiled.leaves.iter().any(|l| f(l, &konst, init))
        };
        let needs_object = compiled.program.code.iter().any(|i| {
            matches!(
                i.op,
                Op::TexCoord { .. } | Op::ObjectInfo | Op::Displacement { object: true }
            ) || matches!(
                i.op,
                Op::NormalMap(
                    geometry_nodes::NormalSpace::Object | geometry_nodes::NormalSpace::Tangent
                )
            )
        });
        let needs_tangents = compiled
            .program
            .code
            .iter()
            .any(|i| matches!(i.op, Op::NormalMap(geometry_nodes::NormalSpace::Tangent)));
        Ok(ShaderGraph {
            name: desc.name.clone(),
            emissive: any(closure::leaf_emits),
            specular: any(closure::leaf_has_specular),
            transparent: any(closure::leaf_transparent),
            scatters: any(closure::leaf_scatters),
            holds_out: compiled
                .leaves
                .iter()
                .any(|l| l.kind == closure::LeafKind::Holdout),
            needs_object,
            needs_tangents,
            tables,
            compiled,
        })
    }

    pub fn warnings(&self) -> &[String] {
        &self.compiled.warnings
    }

    /// Number of instructions run per shading point.
    pub fn instructions(&self) -> usize {
        self.compiled.program.code.len()
    }

    /// Number of closure leaves.
    pub fn leaves(&self) -> usize {
        self.compiled.leaves.len()
    }

    pub fn is_emissive(&self) -> bool {
        self.emissive
    }
    pub fn has_specular(&self) -> bool {
        self.specular
    }
    /// Whether a closure can scatter light (`closure::leaf_scatters`).
    pub fn scatters(&self) -> bool {
        self.scatters
    }
    /// Whether light can pass straight through somewhere (Transparent BSDF, Alpha).
    pub fn can_pass(&self) -> bool {
        self.transparent
    }
    /// Whether a closure is a Holdout.
    pub fn holds_out(&self) -> bool {
        self.holds_out
    }

    /// Runs the program at `sp` and sums the closures.
    pub fn shade(&self, sp: &ShadingPoint, textures: &[Texture], want: Want) -> Shaded {
        REGS.with(|cell| {
            let mut regs = cell.borrow_mut();
            let n = self.compiled.program.init.len();
            if regs.len() < n {
                regs.resize(n, Vec3::ZERO);
            }
            let program = &self.compiled.program;
            let ctx = EvalCtx::new(sp, textures);
            let displaced;
            let (sp, smooth) = match self.compiled.displaced {
                None => {
                    program.run(&mut regs, &ctx);
                    (sp, sp.n)
                }
                Some((split, r)) => {
                    regs[..n].copy_from_slice(&program.init);
                    program.run_range(&mut regs, &ctx, 0..split);
                    let v = regs[r as usize];
                    displaced = ShadingPoint {
                        n: if v.is_finite() && v.length_squared() > 0.0 {
                            v.normalize()
                        } else {
                            sp.n
                        },
                        ..*sp
                    };
                    let ctx = EvalCtx::new(&displaced, textures);
                    program.run_range(&mut regs, &ctx, split..program.code.len());
                    (&displaced, sp.n)
                }
            };
            let normal = match self.compiled.normal {
                NO_REG => sp.n,
                r => {
                    let v = regs[r as usize];
                    if v.is_finite() && v.length_squared() > 0.0 {
                        v.normalize()
                    } else {
                        sp.n
                    }
                }
            };
            let frame = Frame::from_normal_tangent(normal, sp.dpdu);
            let mut out = Shaded {
                bsdf: Bsdf::new(frame),
                emission: Spectrum::ZERO,
                transparency: Spectrum::ZERO,
                holdout: 0.0,
            };
            for (leaf, tables) in self.compiled.leaves.iter().zip(&self.tables) {
                let w = leaf.weight(&regs);
                if w > 0.0 {
                    closure::add_leaf(
                        &mut out,
                        leaf,
                        tables,
                        w,
                        &regs,
                        frame,
                        sp,
                        want == Want::All,
                    );
                }
            }
            if normal != smooth {
                // Cycles shadows closures whose normal differs from the displaced one; the
                // photons' adjoint reads the surface's own normal.
                out.bsdf.set_bump_shadowing(smooth, normal != sp.n);
                let spec = geometry_nodes::ensure_valid_reflection(sp.ng, sp.wo, normal);
                if spec != normal {
                    out.bsdf.set_specular_normal(spec, sp.dpdu);
                }
            }
            out
        })
    }

    /// The single constant closure this graph is, if it is one (no mix, constant inputs,
    /// the surface's own normal): `(kind, input values)`.
    pub fn as_constant(&self) -> Option<(closure::LeafKind, Vec<Vec3>)> {
        let [leaf] = self.compiled.leaves.as_slice() else {
            return None;
        };
        if !self.compiled.program.code.is_empty() || !leaf.weight.is_empty() {
            return None;
        }
        if leaf.normal().is_some_and(|r| r != NO_REG) {
            return None;
        }
        let init = &self.compiled.program.init;
        Some((
            leaf.kind,
            leaf.ins
                .iter()
                .map(|&r| {
                    if r == NO_REG {
                        Vec3::ZERO
                    } else {
                        init[r as usize]
                    }
                })
                .collect(),
        ))
    }
}

fn const_mask(c: &Compiled) -> Vec<bool> {
    let mut k = vec![true; c.program.init.len()];
    for i in &c.program.code {
        for &o in i.outs.iter() {
            if let Some(s) = k.get_mut(o as usize) {
                *s = false;
            }
        }
    }
    k
}

#[cfg(test)]
mod tests;
