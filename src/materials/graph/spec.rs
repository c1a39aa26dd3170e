//! Node sockets as the compiler sees them: types, defaults, and property readers.

use crate::error::{Error, Result};
use crate::scene::graph_desc::NodeDesc;

/// A socket's type. Links convert between types as Cycles does: a colour read as a float
/// is its luminance, a vector its mean, a float read as a colour or vector is splatted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    Float,
    Vector,
    Color,
    Closure,
}

/// What an unlinked socket without a value reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Dflt {
    F(f32),
    V([f32; 3]),
    /// The shading normal.
    Normal,
    /// Generated texture coordinates (procedural textures' default).
    Generated,
    /// The mesh's UV (image textures' default).
    Uv,
    /// A closure: none.
    Empty,
}

/// Sockets of a node type: inputs (name, type, default) and outputs (name, type).
#[derive(Clone, Debug, PartialEq)]
pub struct NodeSpec {
    pub ins: Vec<(&'static str, Ty, Dflt)>,
    pub outs: Vec<(&'static str, Ty)>,
}

impl NodeSpec {
    pub fn new(ins: &[(&'static str, Ty, Dflt)], outs: &[(&'static str, Ty)]) -> Self {
        NodeSpec {
            ins: ins.to_vec(),
            outs: outs.to_vec(),
        }
    }
}

/// Reads a node's `params`, with errors naming the node and the field.
pub struct ParamReader<'a> {
    pub node: &'a NodeDesc,
    /// JSON pointer of the node.
    pub pointer: String,
    /// The material's name.
    pub material: String,
}

impl<'a> ParamReader<'a> {
    pub fn err(&self, field: &str, message: impl Into<String>) -> Error {
        let who = if self.node.name.is_empty() {
            format!("node '{}'", self.node.kind)
        } else {
            format!("node '{}' ({})", self.node.name, self.node.kind)
        };
        Error::InvalidScene {
            pointer: format!("{}/params/{field}", self.pointer),
            object: self.material.clone(),
            message: format!("{who}: {}", message.into()),
        }
    }

    pub fn has(&self, field: &str) -> bool {
        self.node.params.contains_key(field)
    }

    /// A string property (an enum's Blender identifier) or `default` when absent.
    pub fn str_or(&self, field: &str, default: &'a str) -> Result<&'a str> {
        match self.node.params.get(field) {
            None => Ok(default),
            Some(v) => v
                .as_str()
                .ok_or_else(|| self.err(field, format!("must be a string, got {v}"))),
        }
    }

    /// An enum property parsed by `parse`, naming the value when it is unknown.
    pub fn enum_or<T>(
        &self,
        field: &str,
        default: &'a str,
        parse: impl Fn(&str) -> Option<T>,
    ) -> Result<T> {
        let s = self.str_or(field, default)?;
        parse(s).ok_or_else(|| self.err(field, format!("unknown value '{s}'")))
    }

    pub fn bool_or(&self, field: &str, default: bool) -> Result<bool> {
        match self.node.params.get(field) {
            None => Ok(default),
            Some(v) => v
                .as_bool()
                .ok_or_else(|| self.err(field, format!("must be true or false, got {v}"))),
        }
    }

    pub fn f32_or(&self, field: &str, default: f32) -> Result<f32> {
        match self.node.params.get(field) {
            None => Ok(default),
            Some(v) => match v.as_f64() {
                Some(x) if x.is_finite() => Ok(x as f32),
                _ => Err(self.err(field, format!("must be a finite number, got {v}"))),
            },
        }
    }

    pub fn u32_or(&self, field: &str, default: u32) -> Result<u32> {
        match self.node.params.get(field) {
            None => Ok(default),
            Some(v) => v
                .as_u64()
                .and_then(|x| u32::try_from(x).ok())
                .ok_or_else(|| self.err(field, format!("must be a non-negative integer, got {v}"))),
        }
    }

    /// A list of number lists (ramp stops, curve points), each `width` long.
    pub fn rows(&self, field: &str, width: usize) -> Result<Vec<Vec<f32>>> {
        let Some(v) = self.node.params.get(field) else {
            return Ok(Vec::new());
        };
        let bad = || self.err(field, format!("must be a list of {width}-number lists"));
        let list = v.as_array().ok_or_else(bad)?;
        let mut out = Vec::with_capacity(list.len());
        for row in list {
            let row = row.as_array().ok_or_else(bad)?;
            if row.len() != width {
                return Err(bad());
            }
            let mut r = Vec::with_capacity(width);
            for x in row {
                match x.as_f64() {
                    Some(x) if x.is_finite() => r.push(x as f32),
                    _ => return Err(bad()),
                }
            }
            out.push(r);
        }
        Ok(out)
    }
}
