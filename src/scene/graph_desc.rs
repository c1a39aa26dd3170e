//! Shading graphs in the IR: a material as nodes whose inputs are constants or links to other
//! nodes' outputs (see `materials::graph` for the node set and its semantics).

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A material given as a shading graph.
///
/// | field | meaning |
/// |---|---|
/// | `name` | the material's name |
/// | `nodes` | the nodes; links refer to them by index |
/// | `surface` | the closure output that shades the surface (a Material Output's Surface) |
/// | `displacement` | a world-space offset vector (a Material Output's Displacement), applied as a bump of the shading normal that every closure and node then reads (Cycles' Bump Only displacement) |
///
/// Nodes nothing reads are not compiled.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GraphDesc {
    #[serde(default)]
    pub name: String,
    #[serde(default)]
    pub nodes: Vec<NodeDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<LinkDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub displacement: Option<LinkDesc>,
}

/// One node.
///
/// | field | meaning |
/// |---|---|
/// | `type` | the node type (`principled`, `noise_texture`, `math`, ...) |
/// | `name` | the node's name in the editor it came from, for messages |
/// | `inputs` | socket name -> constant (a number or a list of numbers) or a link |
/// | `params` | the node's other properties (modes, ramp stops, image index, ...) |
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct NodeDesc {
    #[serde(rename = "type")]
    pub kind: String,
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub name: String,
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub inputs: BTreeMap<String, InputDesc>,
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub params: BTreeMap<String, serde_json::Value>,
}

/// An output of another node: `{"node": 3, "output": "color"}`.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LinkDesc {
    pub node: u32,
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub output: String,
}

/// A socket's value: a constant or a link.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum InputDesc {
    Float(f32),
    Vector(Vec<f32>),
    Link(LinkDesc),
}
