//! The closure tree: the leaves under the surface output, each weighted by the mix factors
//! above it, and the displacement compiled as a bump of the shading normal.

use super::node_types::Kind;
use super::{node_label, Builder};
use crate::error::Result;
use crate::materials::graph::closure::Leaf;
use crate::materials::graph::program::{Instr, Op, Reg, NO_REG};
use crate::materials::graph::spec::{Dflt, Ty};
use crate::scene::graph_desc::{InputDesc, LinkDesc};
use glam::Vec3;

impl<'a> Builder<'a> {
    /// Collects the closure leaves under `link`, each weighted by the product of the mix
    /// factors above it.
    pub(super) fn closure(
        &mut self,
        link: &LinkDesc,
        weight: &[(Reg, bool)],
        at: &str,
    ) -> Result<()> {
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
    pub(super) fn displacement(&mut self, link: &LinkDesc) -> Result<Option<(usize, Reg)>> {
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
