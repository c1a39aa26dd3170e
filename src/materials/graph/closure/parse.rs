//! The closure nodes read from the IR: each node's kind from its `params`, and its sockets.

use super::{LeafKind, PRINCIPLED};
use crate::error::Result;
use crate::materials::graph::spec::{Dflt, NodeSpec, ParamReader, Ty};

impl LeafKind {
    /// The closure node of IR type `kind`, if it is one.
    pub fn parse(kind: &str, p: &ParamReader) -> Result<Option<(LeafKind, NodeSpec)>> {
        use Dflt::*;
        use Ty::*;
        let ms = || p.bool_or("multiscatter", true);
        let normal = ("normal", Vector, Normal);
        let out = [("bsdf", Closure)];
        Ok(Some(match kind {
            "principled" => (
                LeafKind::Principled {
                    multiscatter: ms()?,
                },
                NodeSpec::new(&PRINCIPLED, &out),
            ),
            "diffuse" => (
                LeafKind::Diffuse,
                NodeSpec::new(
                    &[
                        ("color", Color, V([0.8; 3])),
                        ("roughness", Float, F(0.0)),
                        normal,
                    ],
                    &out,
                ),
            ),
            "glossy" => (
                LeafKind::Glossy {
                    multiscatter: ms()?,
                },
                NodeSpec::new(
                    &[
                        ("color", Color, V([0.8; 3])),
                        ("roughness", Float, F(0.5)),
                        normal,
                    ],
                    &out,
                ),
            ),
            "glass" => (
                LeafKind::Glass {
                    multiscatter: ms()?,
                },
                NodeSpec::new(
                    &[
                        ("color", Color, V([1.0; 3])),
                        ("roughness", Float, F(0.0)),
                        ("ior", Float, F(1.5)),
                        normal,
                    ],
                    &out,
                ),
            ),
            "refraction" => (
                LeafKind::Refraction,
                NodeSpec::new(
                    &[
                        ("color", Color, V([1.0; 3])),
                        ("roughness", Float, F(0.0)),
                        ("ior", Float, F(1.45)),
                        normal,
                    ],
                    &out,
                ),
            ),
            "transparent" => (
                LeafKind::Transparent,
                NodeSpec::new(&[("color", Color, V([1.0; 3]))], &out),
            ),
            "translucent" => (
                LeafKind::Translucent,
                NodeSpec::new(&[("color", Color, V([0.8; 3])), normal], &out),
            ),
            "emission" => (
                LeafKind::Emission,
                NodeSpec::new(
                    &[("color", Color, V([1.0; 3])), ("strength", Float, F(1.0))],
                    &[("emission", Closure)],
                ),
            ),
            "holdout" => (
                LeafKind::Holdout,
                NodeSpec::new(&[], &[("holdout", Closure)]),
            ),
            "sheen" => (
                LeafKind::Sheen,
                NodeSpec::new(
                    &[
                        ("color", Color, V([0.8; 3])),
                        ("roughness", Float, F(0.5)),
                        normal,
                    ],
                    &out,
                ),
            ),
            _ => return Ok(None),
        }))
    }
}
