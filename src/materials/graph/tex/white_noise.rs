//! The White Noise Texture node.

use super::hash::{
    hash_float_to_float, hash_float_to_vec3, hash_vec2_to_float, hash_vec2_to_vec3,
    hash_vec3_to_float, hash_vec3_to_vec3, hash_vec4_to_float, hash_vec4_to_vec3,
};
use super::Dimensions;
use glam::{Vec3, Vec4};

/// White Noise Texture: a hash of the coordinate (no spatial coherence).
///
/// | Parameter    | Type     | Default | Description |
/// |--------------|----------|---------|-------------|
/// | `dimensions` | property | 3D      | `1D` uses W, `2D` Vector.xy, `3D` Vector, `4D` Vector and W |
/// | Vector       | vector   | —       | Coordinate (not scaled) |
/// | W            | float    | 0       | Fourth coordinate |
///
/// Outputs: Value in \[0, 1\] and Color with three independent values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct WhiteNoiseTexture {
    /// Dimensions of the hashed coordinate.
    pub dimensions: Dimensions,
}

/// Outputs of the White Noise Texture node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WhiteNoiseOutput {
    /// Hash in \[0, 1\].
    pub value: f32,
    /// Three hashes in \[0, 1\].
    pub color: Vec3,
}

impl WhiteNoiseTexture {
    /// Evaluates the node at `vector` and `w`.
    pub fn eval(&self, vector: Vec3, w: f32) -> WhiteNoiseOutput {
        let (value, color) = match self.dimensions {
            Dimensions::D1 => (hash_float_to_float(w), hash_float_to_vec3(w)),
            Dimensions::D2 => {
                let v = vector.truncate();
                (hash_vec2_to_float(v), hash_vec2_to_vec3(v))
            }
            Dimensions::D3 => (hash_vec3_to_float(vector), hash_vec3_to_vec3(vector)),
            Dimensions::D4 => {
                let v: Vec4 = vector.extend(w);
                (hash_vec4_to_float(v), hash_vec4_to_vec3(v))
            }
        };
        WhiteNoiseOutput { value, color }
    }
}

#[cfg(test)]
mod tests {
    use super::super::reference::{check_case, Reference};
    use super::*;

    #[test]
    fn matches_blender() {
        let r = Reference::load(include_str!("testdata/white_noise.json"));
        for case in &r.cases {
            let tex = WhiteNoiseTexture {
                dimensions: Dimensions::from_blender(case.prop_str("noise_dimensions"))
                    .expect("dimensions"),
            };
            check_case(&r, case, |p| {
                let o = tex.eval(p.truncate(), p.w);
                vec![
                    ("Value", vec![o.value]),
                    ("Color", o.color.to_array().to_vec()),
                ]
            });
        }
    }
}
