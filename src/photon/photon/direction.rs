//! The quantised (phi, theta) encoding of a photon's incoming direction, one byte each.

use glam::Vec3;
use std::sync::LazyLock;

/// Worst-case angle (radians) between a unit vector and its decoded
/// quantisation: `π·√5 / 512` ≈ 0.013723 rad ≈ 0.786°.
///
/// Derivation: theta (256 steps over [0, π]) and phi (256 steps over
/// [0, 2π)) are truncated into bins and decoded at the bin *centre*, so
/// |Δθ| ≤ π/512 and |Δφ| ≤ 2π/512 = π/256. The path that moves θ and φ
/// linearly between the two points has length
/// `∫ √(Δθ² + sin²θ(t)·Δφ²) dt ≤ √(Δθ² + S²·Δφ²)`, with `S` the largest
/// `sin θ` over the theta bin (≤ 1), and the great-circle angle is no longer
/// than that path: angle ≤ √((π/512)² + (S·π/256)²) ≤ π√5/512.
/// (Jensen's code decodes at the bin start, which doubles the bound.)
pub const DIRECTION_ERROR_BOUND: f32 = 0.013_720_342; // rounded up from π√5/512

/// Precomputed sines and cosines of the (bin-centre) decoded angles,
/// as Jensen's `costheta/sintheta/cosphi/sinphi` tables (appendix B).
#[derive(Debug, Clone)]
pub struct DirectionTables {
    /// `cos((i + ½)·π/256)`.
    pub cos_theta: [f32; 256],
    /// `sin((i + ½)·π/256)`.
    pub sin_theta: [f32; 256],
    /// `cos((j + ½)·2π/256)`.
    pub cos_phi: [f32; 256],
    /// `sin((j + ½)·2π/256)`.
    pub sin_phi: [f32; 256],
}

static DIRECTION_TABLES: LazyLock<DirectionTables> = LazyLock::new(|| {
    let mut t = DirectionTables {
        cos_theta: [0.0; 256],
        sin_theta: [0.0; 256],
        cos_phi: [0.0; 256],
        sin_phi: [0.0; 256],
    };
    for i in 0..256 {
        let theta = (i as f64 + 0.5) * (std::f64::consts::PI / 256.0);
        let phi = (i as f64 + 0.5) * (2.0 * std::f64::consts::PI / 256.0);
        t.cos_theta[i] = theta.cos() as f32;
        t.sin_theta[i] = theta.sin() as f32;
        t.cos_phi[i] = phi.cos() as f32;
        t.sin_phi[i] = phi.sin() as f32;
    }
    t
});

/// The shared direction tables (built once, on first use).
#[inline]
pub fn direction_tables() -> &'static DirectionTables {
    &DIRECTION_TABLES
}

/// Quantises a unit vector to `(phi, theta)` bytes (Jensen 2001 §7.2 /
/// *Practical Guide*): `theta = ⌊acos(z)·256/π⌋`,
/// `phi = ⌊atan2(y, x)·256/(2π)⌋` (+256 when negative), both clamped to
/// 255. Uses `floor` rather than C's truncation toward zero so that small
/// negative phi wraps to 255 instead of sharing bin 0. See
/// [`DIRECTION_ERROR_BOUND`] for the accuracy.
#[inline]
pub fn encode_direction(dir: Vec3) -> (u8, u8) {
    let z = dir.z.clamp(-1.0, 1.0);
    let theta = (z.acos() * (256.0 / std::f32::consts::PI)).floor();
    let theta = theta.clamp(0.0, 255.0) as u8;
    let mut phi = (dir.y.atan2(dir.x) * (256.0 / std::f32::consts::TAU)).floor();
    if phi < 0.0 {
        phi += 256.0;
    }
    let phi = phi.clamp(0.0, 255.0) as u8;
    (phi, theta)
}

/// Decodes `(phi, theta)` bytes to a unit vector through the tables.
#[inline]
pub fn decode_direction(phi: u8, theta: u8) -> Vec3 {
    let t = direction_tables();
    let st = t.sin_theta[theta as usize];
    Vec3::new(
        st * t.cos_phi[phi as usize],
        st * t.sin_phi[phi as usize],
        t.cos_theta[theta as usize],
    )
}
