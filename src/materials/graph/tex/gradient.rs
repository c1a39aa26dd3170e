//! The Gradient Texture node.

use glam::Vec3;
use std::f32::consts::TAU;

/// Shape of the gradient.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum GradientType {
    /// x (the node's default).
    #[default]
    Linear,
    /// max(x, 0)^2.
    Quadratic,
    /// Smoothstep of x.
    Easing,
    /// (x + y) / 2.
    Diagonal,
    /// 1 - |p|.
    Spherical,
    /// (1 - |p|)^2.
    QuadraticSphere,
    /// Angle around z, 0 to 1 starting at -x.
    Radial,
}

impl GradientType {
    /// From Blender's RNA identifier (`gradient_type`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        Some(match identifier {
            "LINEAR" => Self::Linear,
            "QUADRATIC" => Self::Quadratic,
            "EASING" => Self::Easing,
            "DIAGONAL" => Self::Diagonal,
            "SPHERICAL" => Self::Spherical,
            "QUADRATIC_SPHERE" => Self::QuadraticSphere,
            "RADIAL" => Self::Radial,
            _ => return None,
        })
    }
}

/// Gradient Texture: a value from the coordinate, clamped to \[0, 1\].
///
/// | Parameter       | Type     | Default | Description |
/// |-----------------|----------|---------|-------------|
/// | `gradient_type` | property | LINEAR  | LINEAR, QUADRATIC, EASING, DIAGONAL, SPHERICAL, QUADRATIC_SPHERE, RADIAL |
/// | Vector          | vector   | —       | Texture coordinate (no scale) |
///
/// Outputs: Fac and Color (Fac in all three channels).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct GradientTexture {
    /// Shape of the gradient.
    pub gradient_type: GradientType,
}

/// Outputs of the Gradient Texture node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GradientOutput {
    /// Gradient value in \[0, 1\].
    pub fac: f32,
    /// `fac` in every channel.
    pub color: Vec3,
}

impl GradientTexture {
    /// Evaluates the node at `vector`.
    pub fn eval(&self, vector: Vec3) -> GradientOutput {
        let Vec3 { x, y, z } = vector;
        // The spherical forms are biased slightly so that unit vectors give
        // exactly zero.
        let sphere = || (0.999999 - (x * x + y * y + z * z).sqrt()).max(0.0);
        let f = match self.gradient_type {
            GradientType::Linear => x,
            GradientType::Quadratic => {
                let r = x.max(0.0);
                r * r
            }
            GradientType::Easing => {
                let r = x.clamp(0.0, 1.0);
                let t = r * r;
                3.0 * t - 2.0 * t * r
            }
            GradientType::Diagonal => (x + y) * 0.5,
            GradientType::Radial => y.atan2(x) / TAU + 0.5,
            GradientType::QuadraticSphere => {
                let r = sphere();
                r * r
            }
            GradientType::Spherical => sphere(),
        };
        let fac = f.clamp(0.0, 1.0);
        GradientOutput {
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
        let r = Reference::load(include_str!("testdata/gradient.json"));
        for case in &r.cases {
            let tex = GradientTexture {
                gradient_type: GradientType::from_blender(case.prop_str("gradient_type"))
                    .expect("type"),
            };
            check_case(&r, case, |p| {
                let o = tex.eval(p.truncate());
                vec![
                    ("Factor", vec![o.fac]),
                    ("Color", o.color.to_array().to_vec()),
                ]
            });
        }
    }
}
