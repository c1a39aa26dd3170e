//! Shading graphs: a material as a tree of closures combined by Mix and Add, whose inputs are
//! node expressions, compiled once per scene into a flat program run at every shading point.
//!
//! - [`tex`]: procedural and image textures with Cycles' semantics (value for value);
//! - [`ops`]: converters (Math, Vector Math, Mix, ColorRamp, Map Range, colour operations).

pub mod ops;
pub mod tex;
