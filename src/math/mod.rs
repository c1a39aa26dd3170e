//! Small math types shared by the whole renderer.
mod bounds;
mod frame;
mod transform;

pub use bounds::Bounds3;
pub use frame::Frame;
pub use transform::Transform;

/// RGB radiometric quantity (linear Rec.709 primaries).
pub type Spectrum = glam::Vec3;

/// Luminance of a linear Rec.709 colour.
#[inline]
pub fn luminance(c: Spectrum) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// True when every component is finite.
#[inline]
pub fn is_finite3(v: glam::Vec3) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

pub const PI: f32 = std::f32::consts::PI;
pub const INV_PI: f32 = std::f32::consts::FRAC_1_PI;
pub const INV_2PI: f32 = 0.5 * std::f32::consts::FRAC_1_PI;
pub const INV_4PI: f32 = 0.25 * std::f32::consts::FRAC_1_PI;

/// Each group's fraction of `total`, per channel, from the groups' shares `parts` (0 where
/// the total is 0).
pub fn fractions(parts: &[Spectrum], total: Spectrum) -> Vec<Spectrum> {
    let inv = total.to_array().map(|t| {
        if t > 0.0 && t.is_finite() {
            1.0 / t
        } else {
            0.0
        }
    });
    parts.iter().map(|p| *p * Spectrum::from(inv)).collect()
}
