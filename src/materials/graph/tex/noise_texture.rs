//! The Noise Texture node.

use super::fractal::{
    fbm, hetero_terrain, hybrid_multi_fractal, multi_fractal, ridged_multi_fractal, NoisePoint,
};
use super::hash::{hash_float_to_float, hash_vec2_to_float};
use super::Dimensions;
use glam::{Vec2, Vec3, Vec4};

/// How the octaves of noise are combined.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum NoiseType {
    /// Fractal Brownian motion (the node's default).
    #[default]
    Fbm,
    /// Product of octaves.
    MultiFractal,
    /// Hybrid additive/multiplicative multifractal (uses Offset and Gain).
    HybridMultiFractal,
    /// Ridged multifractal (uses Offset and Gain).
    RidgedMultiFractal,
    /// Heterogeneous terrain (uses Offset).
    HeteroTerrain,
}

impl NoiseType {
    /// From Blender's RNA identifier (`noise_type`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        Some(match identifier {
            "FBM" => Self::Fbm,
            "MULTIFRACTAL" => Self::MultiFractal,
            "HYBRID_MULTIFRACTAL" => Self::HybridMultiFractal,
            "RIDGED_MULTIFRACTAL" => Self::RidgedMultiFractal,
            "HETERO_TERRAIN" => Self::HeteroTerrain,
            _ => return None,
        })
    }
}

/// Noise Texture: fractal Perlin noise with optional domain distortion.
///
/// | Parameter      | Type       | Default | Description |
/// |----------------|------------|---------|-------------|
/// | `dimensions`   | property   | 3D      | `1D` uses W, `2D` Vector.xy, `3D` Vector, `4D` Vector and W |
/// | `noise_type`   | property   | FBM     | FBM, MULTIFRACTAL, HYBRID_MULTIFRACTAL, RIDGED_MULTIFRACTAL, HETERO_TERRAIN |
/// | `normalize`    | property   | true    | FBM only: remap to about \[0, 1\] by the total amplitude |
/// | Vector         | vector     | —       | Texture coordinate |
/// | W              | float      | 0       | Fourth coordinate |
/// | Scale          | float      | 5       | Multiplies Vector and W |
/// | Detail         | float      | 2       | Octaves after the first, clamped to \[0, 15\]; fractional values blend |
/// | Roughness      | float      | 0.5     | Amplitude gain per octave, clamped to ≥ 0 |
/// | Lacunarity     | float      | 2       | Frequency gain per octave |
/// | Offset         | float      | 0       | Terrain offset (hybrid, ridged, hetero) |
/// | Gain           | float      | 1       | Terrain gain (hybrid, ridged) |
/// | Distortion     | float      | 0       | Amount of noise added to the coordinate first |
///
/// Outputs: Fac (the noise) and Color (Fac and two more noises at seeded
/// offsets of the coordinate).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct NoiseTexture {
    /// Dimensions of the evaluated noise.
    pub dimensions: Dimensions,
    /// Octave combination.
    pub noise_type: NoiseType,
    /// Normalise FBM to about \[0, 1\].
    pub normalize: bool,
}

/// Socket values of the Noise Texture node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseInputs {
    /// Texture coordinate.
    pub vector: Vec3,
    /// Fourth coordinate.
    pub w: f32,
    /// Coordinate scale.
    pub scale: f32,
    /// Octaves after the first.
    pub detail: f32,
    /// Amplitude gain per octave.
    pub roughness: f32,
    /// Frequency gain per octave.
    pub lacunarity: f32,
    /// Terrain offset.
    pub offset: f32,
    /// Terrain gain.
    pub gain: f32,
    /// Domain distortion.
    pub distortion: f32,
}

impl Default for NoiseInputs {
    fn default() -> Self {
        Self {
            vector: Vec3::ZERO,
            w: 0.0,
            scale: 5.0,
            detail: 2.0,
            roughness: 0.5,
            lacunarity: 2.0,
            offset: 0.0,
            gain: 1.0,
            distortion: 0.0,
        }
    }
}

/// Outputs of the Noise Texture node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseOutput {
    /// Noise value.
    pub fac: f32,
    /// Three decorrelated noise values (the first equals `fac`).
    pub color: Vec3,
}

/// Coordinates usable by the noise texture: noise plus seeded offsets.
trait Coord: NoisePoint {
    /// Components in `[100, 200]` derived from `seed`.
    fn random_offset(seed: f32) -> Self;
    /// Noise evaluated per component at shifted copies of `self`, scaled.
    fn distorted(self, distortion: f32) -> Self;
}

#[inline]
fn offset_component(seed: f32, axis: f32) -> f32 {
    100.0 + hash_vec2_to_float(Vec2::new(seed, axis)) * 100.0
}

impl Coord for f32 {
    fn random_offset(seed: f32) -> Self {
        100.0 + hash_float_to_float(seed) * 100.0
    }
    fn distorted(self, d: f32) -> Self {
        self + (self + Self::random_offset(0.0)).snoise() * d
    }
}

impl Coord for Vec2 {
    fn random_offset(seed: f32) -> Self {
        Vec2::new(offset_component(seed, 0.0), offset_component(seed, 1.0))
    }
    fn distorted(self, d: f32) -> Self {
        self + Vec2::new(
            (self + Self::random_offset(0.0)).snoise() * d,
            (self + Self::random_offset(1.0)).snoise() * d,
        )
    }
}

impl Coord for Vec3 {
    fn random_offset(seed: f32) -> Self {
        Vec3::new(
            offset_component(seed, 0.0),
            offset_component(seed, 1.0),
            offset_component(seed, 2.0),
        )
    }
    fn distorted(self, d: f32) -> Self {
        self + Vec3::new(
            (self + Self::random_offset(0.0)).snoise() * d,
            (self + Self::random_offset(1.0)).snoise() * d,
            (self + Self::random_offset(2.0)).snoise() * d,
        )
    }
}

impl Coord for Vec4 {
    fn random_offset(seed: f32) -> Self {
        Vec4::new(
            offset_component(seed, 0.0),
            offset_component(seed, 1.0),
            offset_component(seed, 2.0),
            offset_component(seed, 3.0),
        )
    }
    fn distorted(self, d: f32) -> Self {
        self + Vec4::new(
            (self + Self::random_offset(0.0)).snoise() * d,
            (self + Self::random_offset(1.0)).snoise() * d,
            (self + Self::random_offset(2.0)).snoise() * d,
            (self + Self::random_offset(3.0)).snoise() * d,
        )
    }
}

impl NoiseTexture {
    fn select<P: NoisePoint>(&self, p: P, i: &NoiseInputs, roughness: f32) -> f32 {
        let (d, l) = (i.detail, i.lacunarity);
        match self.noise_type {
            NoiseType::Fbm => fbm(p, d, roughness, l, self.normalize),
            NoiseType::MultiFractal => multi_fractal(p, d, roughness, l),
            NoiseType::HybridMultiFractal => {
                hybrid_multi_fractal(p, d, roughness, l, i.offset, i.gain)
            }
            NoiseType::RidgedMultiFractal => {
                ridged_multi_fractal(p, d, roughness, l, i.offset, i.gain)
            }
            NoiseType::HeteroTerrain => hetero_terrain(p, d, roughness, l, i.offset),
        }
    }

    /// `first_color_seed`: seed of the Color output's second channel; the
    /// distortion uses the seeds below it.
    fn eval_at<P: Coord>(
        &self,
        co: P,
        i: &NoiseInputs,
        first_color_seed: f32,
        with_color: bool,
    ) -> NoiseOutput {
        let roughness = i.roughness.max(0.0);
        let p = if i.distortion != 0.0 {
            co.distorted(i.distortion)
        } else {
            co
        };
        let fac = self.select(p, i, roughness);
        let color = if with_color {
            Vec3::new(
                fac,
                self.select(p + P::random_offset(first_color_seed), i, roughness),
                self.select(p + P::random_offset(first_color_seed + 1.0), i, roughness),
            )
        } else {
            Vec3::splat(fac)
        };
        NoiseOutput { fac, color }
    }

    fn eval_impl(&self, inputs: &NoiseInputs, with_color: bool) -> NoiseOutput {
        let v = inputs.vector * inputs.scale;
        let w = inputs.w * inputs.scale;
        match self.dimensions {
            Dimensions::D1 => self.eval_at(w, inputs, 1.0, with_color),
            Dimensions::D2 => self.eval_at(v.truncate(), inputs, 2.0, with_color),
            Dimensions::D3 => self.eval_at(v, inputs, 3.0, with_color),
            Dimensions::D4 => self.eval_at(v.extend(w), inputs, 4.0, with_color),
        }
    }

    /// Evaluates both outputs.
    pub fn eval(&self, inputs: &NoiseInputs) -> NoiseOutput {
        self.eval_impl(inputs, true)
    }

    /// Evaluates only Fac (a third of the work of [`Self::eval`]).
    pub fn eval_fac(&self, inputs: &NoiseInputs) -> f32 {
        self.eval_impl(inputs, false).fac
    }
}

#[cfg(test)]
mod tests {
    use super::super::reference::{check_case, Reference};
    use super::*;

    #[test]
    fn matches_blender() {
        let r = Reference::load(include_str!("testdata/noise_texture.json"));
        for case in &r.cases {
            let tex = NoiseTexture {
                dimensions: Dimensions::from_blender(case.prop_str("noise_dimensions"))
                    .expect("dimensions"),
                noise_type: NoiseType::from_blender(case.prop_str("noise_type")).expect("type"),
                normalize: case.prop_bool("normalize"),
            };
            check_case(&r, case, |p| {
                let out = tex.eval(&NoiseInputs {
                    vector: p.truncate(),
                    w: p.w,
                    scale: case.input("Scale"),
                    detail: case.input("Detail"),
                    roughness: case.input("Roughness"),
                    lacunarity: case.input("Lacunarity"),
                    offset: case.input("Offset"),
                    gain: case.input("Gain"),
                    distortion: case.input("Distortion"),
                });
                vec![
                    ("Factor", vec![out.fac]),
                    ("Color", out.color.to_array().to_vec()),
                ]
            });
        }
    }

    #[test]
    fn non_finite_inputs_do_not_panic() {
        for v in [f32::NAN, f32::INFINITY, -f32::INFINITY] {
            for t in [
                "FBM",
                "MULTIFRACTAL",
                "HYBRID_MULTIFRACTAL",
                "RIDGED_MULTIFRACTAL",
            ] {
                let tex = NoiseTexture {
                    dimensions: Dimensions::D4,
                    noise_type: NoiseType::from_blender(t).expect("type"),
                    normalize: true,
                };
                let i = NoiseInputs {
                    vector: Vec3::splat(v),
                    w: v,
                    detail: v,
                    roughness: v,
                    lacunarity: v,
                    distortion: v,
                    ..Default::default()
                };
                let _ = tex.eval(&i);
            }
        }
    }
}
