//! The Brick Texture node.

use glam::Vec3;

/// Brick Texture: rows of bricks with mortar, offset and squashed per row.
///
/// | Parameter          | Type     | Default         | Description |
/// |--------------------|----------|-----------------|-------------|
/// | `offset`           | property | 0.5             | Shift of every `offset_frequency`-th row, in brick widths |
/// | `offset_frequency` | property | 2               | Period (rows) of the shift |
/// | `squash`           | property | 1               | Width factor of every `squash_frequency`-th row |
/// | `squash_frequency` | property | 2               | Period (rows) of the squash |
/// | Vector             | vector   | —               | Texture coordinate (x and y are used) |
/// | Color1, Color2     | colour   | 0.8 / 0.2 grey  | Brick colours, blended by a per-brick random tint |
/// | Mortar             | colour   | black           | Mortar colour |
/// | Scale              | float    | 5               | Multiplies the coordinate |
/// | Mortar Size        | float    | 0.02            | Mortar width |
/// | Mortar Smooth      | float    | 0.1             | Softness of the brick/mortar transition |
/// | Bias               | float    | 0               | Added to the tint (towards Color2) |
/// | Brick Width        | float    | 0.5             | Brick width |
/// | Row Height         | float    | 0.25            | Brick height |
///
/// Outputs: Color and Fac (the mortar weight: 1 in the mortar, 0 on bricks).
/// Offset and squash apply only when both frequencies are non-zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrickTexture {
    /// Row shift, in brick widths.
    pub offset: f32,
    /// Shift every this many rows.
    pub offset_frequency: i32,
    /// Row width factor.
    pub squash: f32,
    /// Squash every this many rows.
    pub squash_frequency: i32,
}

impl Default for BrickTexture {
    fn default() -> Self {
        Self {
            offset: 0.5,
            offset_frequency: 2,
            squash: 1.0,
            squash_frequency: 2,
        }
    }
}

/// Socket values of the Brick Texture node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrickInputs {
    /// Texture coordinate.
    pub vector: Vec3,
    /// First brick colour.
    pub color1: Vec3,
    /// Second brick colour.
    pub color2: Vec3,
    /// Mortar colour.
    pub mortar: Vec3,
    /// Coordinate scale.
    pub scale: f32,
    /// Mortar width.
    pub mortar_size: f32,
    /// Mortar transition softness.
    pub mortar_smooth: f32,
    /// Tint bias.
    pub bias: f32,
    /// Brick width.
    pub brick_width: f32,
    /// Row height.
    pub row_height: f32,
}

impl Default for BrickInputs {
    fn default() -> Self {
        Self {
            vector: Vec3::ZERO,
            color1: Vec3::splat(0.8),
            color2: Vec3::splat(0.2),
            mortar: Vec3::ZERO,
            scale: 5.0,
            mortar_size: 0.02,
            mortar_smooth: 0.1,
            bias: 0.0,
            brick_width: 0.5,
            row_height: 0.25,
        }
    }
}

/// Outputs of the Brick Texture node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrickOutput {
    /// Brick or mortar colour.
    pub color: Vec3,
    /// Mortar weight.
    pub fac: f32,
}

/// Integer noise in \[0, 1) of a brick's id.
fn brick_noise(n: u32) -> f32 {
    let mut n = n.wrapping_add(1013) & 0x7fff_ffff;
    n ^= n >> 13;
    let nn = n
        .wrapping_mul(
            n.wrapping_mul(n)
                .wrapping_mul(60493)
                .wrapping_add(19_990_303),
        )
        .wrapping_add(1_376_312_589)
        & 0x7fff_ffff;
    0.5 * (nn as f32 / 1_073_741_824.0)
}

/// 3f² - 2f³ clamped to \[0, 1\].
fn smoothstep(f: f32) -> f32 {
    if f <= 0.0 {
        0.0
    } else if f >= 1.0 {
        1.0
    } else {
        let ff = f * f;
        3.0 * ff - 2.0 * ff * f
    }
}

impl BrickTexture {
    /// Brick tint and mortar weight at `p` (already scaled).
    fn tint_and_mortar(&self, p: Vec3, i: &BrickInputs) -> (f32, f32) {
        let row_height = i.row_height;
        let mut brick_width = i.brick_width;
        let rownum = (p.y / row_height).floor() as i32;
        let mut offset = 0.0;
        if self.offset_frequency != 0 && self.squash_frequency != 0 {
            if rownum.wrapping_rem(self.squash_frequency) == 0 {
                brick_width *= self.squash;
            }
            if rownum.wrapping_rem(self.offset_frequency) == 0 {
                offset = brick_width * self.offset;
            }
        }
        let bricknum = ((p.x + offset) / brick_width).floor() as i32;
        let x = (p.x + offset) - brick_width * bricknum as f32;
        let y = p.y - row_height * rownum as f32;
        let id = rownum.wrapping_shl(16).wrapping_add(bricknum & 0xffff);
        let tint = (brick_noise(id as u32) + i.bias).clamp(0.0, 1.0);
        let min_dist = x.min(y).min((brick_width - x).min(row_height - y));
        let mortar = if min_dist >= i.mortar_size {
            0.0
        } else if i.mortar_smooth == 0.0 {
            1.0
        } else {
            smoothstep((1.0 - min_dist / i.mortar_size) / i.mortar_smooth)
        };
        (tint, mortar)
    }

    /// Evaluates the node.
    pub fn eval(&self, inputs: &BrickInputs) -> BrickOutput {
        let (tint, f) = self.tint_and_mortar(inputs.vector * inputs.scale, inputs);
        let brick = if f != 1.0 {
            (1.0 - tint) * inputs.color1 + tint * inputs.color2
        } else {
            inputs.color1
        };
        BrickOutput {
            color: brick * (1.0 - f) + inputs.mortar * f,
            fac: f,
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
            let tex = BrickTexture {
                offset: case.prop_f32("offset"),
                offset_frequency: case.prop_f32("offset_frequency") as i32,
                squash: case.prop_f32("squash"),
                squash_frequency: case.prop_f32("squash_frequency") as i32,
            };
            check_case(&r, case, |p| {
                let o = tex.eval(&BrickInputs {
                    vector: p.truncate(),
                    color1: case.input_vec3("Color1"),
                    color2: case.input_vec3("Color2"),
                    mortar: case.input_vec3("Mortar"),
                    scale: case.input("Scale"),
                    mortar_size: case.input("Mortar Size"),
                    mortar_smooth: case.input("Mortar Smooth"),
                    bias: case.input("Bias"),
                    brick_width: case.input("Brick Width"),
                    row_height: case.input("Row Height"),
                });
                vec![
                    ("Factor", vec![o.fac]),
                    ("Color", o.color.to_array().to_vec()),
                ]
            });
        }
    }

    /// Geometry Nodes references (Mortar Smooth 0 or 1 only, where its
    /// unclamped smoothstep agrees with Cycles').
    #[test]
    fn matches_blender_geometry_nodes() {
        check(include_str!("testdata/brick.json"));
    }

    /// Cycles renders, including a Mortar Smooth where the clamping matters.
    #[test]
    fn matches_blender_cycles() {
        check(include_str!("testdata/brick_cycles.json"));
    }
}
