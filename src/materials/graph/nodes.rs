//! Converter and texture nodes: their sockets, and how they run.

use super::program::EvalCtx;
use super::spec::{NodeSpec, ParamReader};
use crate::error::Result;
use glam::Vec3;

/// A converter or texture node with its properties.
#[derive(Clone, Debug, PartialEq)]
pub enum NodeOp {
    /// A float read as a colour or vector (all three components).
    Splat,
    /// Invert: inputs fac, color; output color.
    Invert,
}

impl NodeOp {
    /// The IR types of these nodes.
    pub const TYPES: &'static [&'static str] = &["invert"];

    /// The node of IR type `kind`, if it is one of these; `None` for other types.
    pub fn parse(kind: &str, _params: &ParamReader) -> Result<Option<(NodeOp, NodeSpec)>> {
        use super::spec::{Dflt::*, Ty::*};
        Ok(Some(match kind {
            "invert" => (
                NodeOp::Invert,
                NodeSpec::new(
                    &[("fac", Float, F(1.0)), ("color", Color, V([0.0; 3]))],
                    &[("color", Color)],
                ),
            ),
            _ => return Ok(None),
        }))
    }

    /// Runs the node on its inputs (in socket order) into `out`.
    pub fn run(&self, inp: &[Vec3], out: &mut [Vec3; 8], _ctx: &EvalCtx) {
        match self {
            NodeOp::Splat => out[0] = Vec3::splat(inp[0].x),
            NodeOp::Invert => {
                let fac = inp[0].x;
                out[0] = inp[1].lerp(Vec3::ONE - inp[1], fac);
            }
        }
    }
}
