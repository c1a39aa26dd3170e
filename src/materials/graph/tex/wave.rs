//! The Wave Texture node.

use super::fractal::fbm;
use glam::Vec3;
use std::f32::consts::{FRAC_PI_2, TAU};

/// Bands (planar waves) or rings (radial waves).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum WaveType {
    /// Parallel bands (the node's default).
    #[default]
    Bands,
    /// Concentric rings.
    Rings,
}

/// Direction across which bands vary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BandsDirection {
    /// Along x (the node's default).
    #[default]
    X,
    /// Along y.
    Y,
    /// Along z.
    Z,
    /// Along (1, 1, 1).
    Diagonal,
}

/// Axis the rings are centred on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum RingsDirection {
    /// Cylinders around x (the node's default).
    #[default]
    X,
    /// Cylinders around y.
    Y,
    /// Cylinders around z.
    Z,
    /// Spheres around the origin.
    Spherical,
}

/// Wave profile.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum WaveProfile {
    /// Sine (the node's default).
    #[default]
    Sin,
    /// Sawtooth.
    Saw,
    /// Triangle.
    Tri,
}

impl WaveType {
    /// From Blender's RNA identifier (`wave_type`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        Some(match identifier {
            "BANDS" => Self::Bands,
            "RINGS" => Self::Rings,
            _ => return None,
        })
    }
}

impl BandsDirection {
    /// From Blender's RNA identifier (`bands_direction`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        Some(match identifier {
            "X" => Self::X,
            "Y" => Self::Y,
            "Z" => Self::Z,
            "DIAGONAL" => Self::Diagonal,
            _ => return None,
        })
    }
}

impl RingsDirection {
    /// From Blender's RNA identifier (`rings_direction`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        Some(match identifier {
            "X" => Self::X,
            "Y" => Self::Y,
            "Z" => Self::Z,
            "SPHERICAL" => Self::Spherical,
            _ => return None,
        })
    }
}

impl WaveProfile {
    /// From Blender's RNA identifier (`wave_profile`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        Some(match identifier {
            "SIN" => Self::Sin,
            "SAW" => Self::Saw,
            "TRI" => Self::Tri,
            _ => return None,
        })
    }
}

/// Wave Texture: bands or rings, optionally distorted by fBm noise.
///
/// | Parameter          | Type     | Default | Description |
/// |--------------------|----------|---------|-------------|
/// | `wave_type`        | property | BANDS   | BANDS or RINGS |
/// | `bands_direction`  | property | X       | X, Y, Z, DIAGONAL (bands) |
/// | `rings_direction`  | property | X       | X, Y, Z, SPHERICAL (rings) |
/// | `wave_profile`     | property | SIN     | SIN, SAW, TRI |
/// | Vector             | vector   | —       | Texture coordinate |
/// | Scale              | float    | 5       | Multiplies the coordinate |
/// | Distortion         | float    | 0       | Amount of noise added to the wave phase |
/// | Detail             | float    | 2       | Octaves of the distortion noise after the first |
/// | Detail Scale       | float    | 1       | Frequency of the distortion noise |
/// | Detail Roughness   | float    | 0.5     | Octave gain of the distortion noise |
/// | Phase Offset       | float    | 0       | Added to the phase (radians) |
///
/// Outputs: Fac in \[0, 1\] and Color (Fac in all three channels).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct WaveTexture {
    /// Bands or rings.
    pub wave_type: WaveType,
    /// Direction of bands.
    pub bands_direction: BandsDirection,
    /// Direction of rings.
    pub rings_direction: RingsDirection,
    /// Wave profile.
    pub profile: WaveProfile,
}

/// Socket values of the Wave Texture node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaveInputs {
    /// Texture coordinate.
    pub vector: Vec3,
    /// Coordinate scale.
    pub scale: f32,
    /// Phase distortion amount.
    pub distortion: f32,
    /// Distortion noise octaves after the first.
    pub detail: f32,
    /// Distortion noise frequency.
    pub detail_scale: f32,
    /// Distortion noise octave gain.
    pub detail_roughness: f32,
    /// Phase offset.
    pub phase_offset: f32,
}

impl Default for WaveInputs {
    fn default() -> Self {
        Self {
            vector: Vec3::ZERO,
            scale: 5.0,
            distortion: 0.0,
            detail: 2.0,
            detail_scale: 1.0,
            detail_roughness: 0.5,
            phase_offset: 0.0,
        }
    }
}

/// Outputs of the Wave Texture node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaveOutput {
    /// Wave value in \[0, 1\].
    pub fac: f32,
    /// `fac` in every channel.
    pub color: Vec3,
}

impl WaveTexture {
    /// Evaluates the node.
    pub fn eval(&self, inputs: &WaveInputs) -> WaveOutput {
        // Nudge so that integer coordinates are not on a discontinuity.
        let p = (inputs.vector * inputs.scale + 0.000001) * 0.999999;
        let mut n = match self.wave_type {
            WaveType::Bands => match self.bands_direction {
                BandsDirection::X => p.x * 20.0,
                BandsDirection::Y => p.y * 20.0,
                BandsDirection::Z => p.z * 20.0,
                BandsDirection::Diagonal => (p.x + p.y + p.z) * 10.0,
            },
            WaveType::Rings => {
                let rp = match self.rings_direction {
                    RingsDirection::X => p * Vec3::new(0.0, 1.0, 1.0),
                    RingsDirection::Y => p * Vec3::new(1.0, 0.0, 1.0),
                    RingsDirection::Z => p * Vec3::new(1.0, 1.0, 0.0),
                    RingsDirection::Spherical => p,
                };
                rp.length() * 20.0
            }
        };
        n += inputs.phase_offset;
        if inputs.distortion != 0.0 {
            let noise = fbm(
                p * inputs.detail_scale,
                inputs.detail,
                inputs.detail_roughness,
                2.0,
                true,
            );
            n += inputs.distortion * (noise * 2.0 - 1.0);
        }
        let fac = match self.profile {
            WaveProfile::Sin => 0.5 + 0.5 * (n - FRAC_PI_2).sin(),
            WaveProfile::Saw => {
                let t = n / TAU;
                t - t.floor()
            }
            WaveProfile::Tri => {
                let t = n / TAU;
                (t - (t + 0.5).floor()).abs() * 2.0
            }
        };
        WaveOutput {
            fac,
            color: Vec3::splat(fac),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::reference::{check_case, Reference};
    use super::*;

    #[test]
    fn matches_blender() {
        let r = Reference::load(include_str!("testdata/wave.json"));
        for case in &r.cases {
            let prop = |k: &str, default: &'static str| {
                case.props
                    .get(k)
                    .and_then(|v| v.as_str())
                    .unwrap_or(default)
                    .to_string()
            };
            let tex = WaveTexture {
                wave_type: WaveType::from_blender(&prop("wave_type", "BANDS")).expect("type"),
                bands_direction: BandsDirection::from_blender(&prop("bands_direction", "X"))
                    .expect("bands"),
                rings_direction: RingsDirection::from_blender(&prop("rings_direction", "X"))
                    .expect("rings"),
                profile: WaveProfile::from_blender(&prop("wave_profile", "SIN")).expect("profile"),
            };
            check_case(&r, case, |p| {
                let o = tex.eval(&WaveInputs {
                    vector: p.truncate(),
                    scale: case.input("Scale"),
                    distortion: case.input("Distortion"),
                    detail: case.input("Detail"),
                    detail_scale: case.input("Detail Scale"),
                    detail_roughness: case.input("Detail Roughness"),
                    phase_offset: case.input("Phase Offset"),
                });
                vec![
                    ("Factor", vec![o.fac]),
                    ("Color", o.color.to_array().to_vec()),
                ]
            });
        }
    }
}
