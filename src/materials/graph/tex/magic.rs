//! The Magic Texture node.

use glam::Vec3;
use std::f32::consts::TAU;

/// Magic Texture: nested sines and cosines of the coordinate ("psychedelic"
/// colour swirls).
///
/// | Parameter          | Type     | Default | Description |
/// |--------------------|----------|---------|-------------|
/// | `turbulence_depth` | property | 2       | Number of nested iterations, 0 to 10 |
/// | Vector             | vector   | —       | Texture coordinate |
/// | Scale              | float    | 5       | Frequency |
/// | Distortion         | float    | 1       | Amplitude fed into each iteration |
///
/// Outputs: Color and Fac (the mean of the colour's channels).  Coordinates
/// are reduced modulo 2π first, which keeps large coordinates finite.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MagicTexture {
    /// Number of nested iterations (values above 10 act as 10).
    pub depth: i32,
}

impl Default for MagicTexture {
    fn default() -> Self {
        Self { depth: 2 }
    }
}

/// Socket values of the Magic Texture node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MagicInputs {
    /// Texture coordinate.
    pub vector: Vec3,
    /// Frequency.
    pub scale: f32,
    /// Amplitude of each iteration.
    pub distortion: f32,
}

impl Default for MagicInputs {
    fn default() -> Self {
        Self {
            vector: Vec3::ZERO,
            scale: 5.0,
            distortion: 1.0,
        }
    }
}

/// Outputs of the Magic Texture node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MagicOutput {
    /// The colour.
    pub color: Vec3,
    /// Mean of the colour's channels.
    pub fac: f32,
}

impl MagicTexture {
    /// Evaluates the node.
    pub fn eval(&self, inputs: &MagicInputs) -> MagicOutput {
        let n = self.depth;
        let d = inputs.distortion;
        let s = inputs.scale;
        let p = Vec3::new(
            inputs.vector.x % TAU,
            inputs.vector.y % TAU,
            inputs.vector.z % TAU,
        );
        let mut x = ((p.x + p.y + p.z) * 5.0 * s).sin();
        let mut y = ((-p.x + p.y - p.z) * 5.0 * s).cos();
        let mut z = -((-p.x - p.y + p.z) * 5.0 * s).cos();
        // Iteration k updates one channel from all three, then scales it.
        if n > 0 {
            x *= d;
            y *= d;
            z *= d;
            y = -(x - y + z).cos() * d;
        }
        if n > 1 {
            x = (x - y - z).cos() * d;
        }
        if n > 2 {
            z = (-x - y - z).sin() * d;
        }
        if n > 3 {
            x = -(-x + y - z).cos() * d;
        }
        if n > 4 {
            y = -(-x + y + z).sin() * d;
        }
        if n > 5 {
            y = -(-x + y + z).cos() * d;
        }
        if n > 6 {
            x = (x + y + z).cos() * d;
        }
        if n > 7 {
            z = (x + y - z).sin() * d;
        }
        if n > 8 {
            x = -(-x - y + z).cos() * d;
        }
        if n > 9 {
            y = -(x - y + z).sin() * d;
        }
        if d != 0.0 {
            let d2 = d * 2.0;
            x /= d2;
            y /= d2;
            z /= d2;
        }
        let color = Vec3::new(0.5 - x, 0.5 - y, 0.5 - z);
        MagicOutput {
            color,
            fac: (color.x + color.y + color.z) * (1.0 / 3.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::reference::{check_case, Reference};
    use super::*;

    fn check(json: &str) {
        let r = Reference::load(json);
        for case in &r.cases {
            let tex = MagicTexture {
                depth: case.prop_f32("turbulence_depth") as i32,
            };
            check_case(&r, case, |p| {
                let o = tex.eval(&MagicInputs {
                    vector: p.truncate(),
                    scale: case.input("Scale"),
                    distortion: case.input("Distortion"),
                });
                vec![
                    ("Factor", vec![o.fac]),
                    ("Color", o.color.to_array().to_vec()),
                ]
            });
        }
    }

    /// Geometry Nodes references (coordinates within ±2π, where Geometry
    /// Nodes, which skips the modulo, agrees with Cycles).
    #[test]
    fn matches_blender_geometry_nodes() {
        check(include_str!("testdata/magic.json"));
    }

    /// Cycles renders with coordinates up to ±12.
    #[test]
    fn matches_blender_cycles() {
        check(include_str!("testdata/magic_cycles.json"));
    }
}
