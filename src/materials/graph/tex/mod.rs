//! Procedural textures, as Cycles evaluates them.
//!
//! Each node is a parameter struct holding the node's properties (built from
//! Blender's RNA identifiers with `from_blender`), an inputs struct holding
//! its socket values (the Vector input already transformed: texture
//! coordinates and the Mapping node are handled by the caller) and an `eval`
//! returning the node's outputs.  Results match Blender's Cycles to float
//! rounding; the tests compare against values produced by Blender itself
//! (`make_references.py`).

pub mod brick;
pub mod checker;
pub mod fractal;
pub mod gradient;
pub mod hash;
pub mod magic;
pub mod noise;
pub mod noise_texture;
pub mod voronoi;
pub mod wave;
pub mod white_noise;

#[cfg(test)]
mod reference;

pub use brick::{BrickInputs, BrickOutput, BrickTexture};
pub use checker::{CheckerInputs, CheckerOutput, CheckerTexture};
pub use gradient::{GradientOutput, GradientTexture, GradientType};
pub use magic::{MagicInputs, MagicOutput, MagicTexture};
pub use noise_texture::{NoiseInputs, NoiseOutput, NoiseTexture, NoiseType};
pub use voronoi::{VoronoiFeature, VoronoiInputs, VoronoiMetric, VoronoiOutput, VoronoiTexture};
pub use wave::{
    BandsDirection, RingsDirection, WaveInputs, WaveOutput, WaveProfile, WaveTexture, WaveType,
};
pub use white_noise::{WhiteNoiseOutput, WhiteNoiseTexture};

/// Dimensionality of the Noise, Voronoi and White Noise textures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Dimensions {
    /// W only.
    D1,
    /// Vector x and y.
    D2,
    /// Vector (the nodes' default).
    #[default]
    D3,
    /// Vector and W.
    D4,
}

impl Dimensions {
    /// From Blender's RNA identifiers `"1D"` to `"4D"`.
    pub fn from_blender(identifier: &str) -> Option<Self> {
        Some(match identifier {
            "1D" => Self::D1,
            "2D" => Self::D2,
            "3D" => Self::D3,
            "4D" => Self::D4,
            _ => return None,
        })
    }
}
