//! The Checker Texture node.

use glam::Vec3;

/// Checker Texture: alternating unit cubes of two colours.
///
/// | Parameter | Type   | Default         | Description |
/// |-----------|--------|-----------------|-------------|
/// | Vector    | vector | —               | Texture coordinate |
/// | Color1    | colour | (0.8, 0.8, 0.8) | Colour of the cubes where Fac = 1 |
/// | Color2    | colour | (0.2, 0.2, 0.2) | Colour of the other cubes |
/// | Scale     | float  | 5               | Cubes per unit |
///
/// Outputs: Color and Fac (1 on Color1's cubes, else 0).  Coordinates are
/// nudged by `(p + 1e-6) * 0.999999` so that integer coordinates fall
/// consistently into one cube.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct CheckerTexture;

/// Socket values of the Checker Texture node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CheckerInputs {
    /// Texture coordinate.
    pub vector: Vec3,
    /// First colour.
    pub color1: Vec3,
    /// Second colour.
    pub color2: Vec3,
    /// Cubes per unit.
    pub scale: f32,
}

impl Default for CheckerInputs {
    fn default() -> Self {
        Self {
            vector: Vec3::ZERO,
            color1: Vec3::splat(0.8),
            color2: Vec3::splat(0.2),
            scale: 5.0,
        }
    }
}

/// Outputs of the Checker Texture node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CheckerOutput {
    /// Colour of the cube.
    pub color: Vec3,
    /// 1 on Color1's cubes, 0 elsewhere.
    pub fac: f32,
}

impl CheckerTexture {
    /// Evaluates the node.
    pub fn eval(&self, inputs: &CheckerInputs) -> CheckerOutput {
        let p = ((inputs.vector * inputs.scale) + 0.000001) * 0.999999;
        let parity = |c: f32| (c.floor() as i32).unsigned_abs() % 2;
        let same_xy = parity(p.x) == parity(p.y);
        let fac = if u32::from(same_xy) == parity(p.z) {
            1.0
        } else {
            0.0
        };
        CheckerOutput {
            color: if fac == 1.0 {
                inputs.color1
            } else {
                inputs.color2
            },
            fac,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::reference::{check_case, Reference};
    use super::*;

    #[test]
    fn matches_blender() {
        let r = Reference::load(include_str!("testdata/checker.json"));
        for case in &r.cases {
            check_case(&r, case, |p| {
                let o = CheckerTexture.eval(&CheckerInputs {
                    vector: p.truncate(),
                    color1: case.input_vec3("Color1"),
                    color2: case.input_vec3("Color2"),
                    scale: case.input("Scale"),
                });
                vec![
                    ("Factor", vec![o.fac]),
                    ("Color", o.color.to_array().to_vec()),
                ]
            });
        }
    }
}
