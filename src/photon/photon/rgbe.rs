//! Ward's RGBE shared-exponent encoding of a photon's power (G. Ward, "Real Pixels",
//! Graphics Gems II, 1991).

use super::check_power;
use crate::photon::PhotonError;
use glam::Vec3;

/// Largest channel value representable in RGBE: `255 · 2^(255−136)`
/// ≈ 1.6948e38. Larger (finite) channels saturate to this value.
pub const RGBE_MAX: f32 = 1.694_765_7e38;

/// Exact `2^x` as f32 for `-149 <= x <= 127` (subnormal results included).
#[inline(always)]
fn exp2i_f32(x: i32) -> f32 {
    debug_assert!((-149..=127).contains(&x));
    if x >= -126 {
        f32::from_bits(((x + 127) as u32) << 23)
    } else {
        f32::from_bits(1u32 << (x + 149))
    }
}

/// Exact `2^x` as f64 for `-1022 <= x <= 1023`.
#[inline(always)]
fn exp2i_f64(x: i32) -> f64 {
    f64::from_bits(((x + 1023) as u64) << 52)
}

/// Encodes a non-negative RGB power as Ward's RGBE (shared exponent).
///
/// Format (as Radiance's `float2rgbe`): with `frexp(max) = m·2^e`,
/// `m ∈ [0.5, 1)`, each channel is stored as `c·2^(8−e)` in a byte and the
/// exponent byte is `e + 128`; exponent byte 0 means exactly zero. Decoding
/// ([`rgbe_decode`]) is `byte · 2^(E−136)` (no +0.5 offset, so a zero byte
/// decodes to exactly zero).
///
/// Precision: this encoder **rounds** to nearest (Radiance truncates), so
/// * the largest channel has relative error ≤ 1/256 (its mantissa byte is in
///   [128, 255] before rounding, rounding error ≤ ½);
/// * every channel has absolute error ≤ half a step = `2^(e−9)`, which is
///   ≤ max/256 — except when rounding the largest mantissa carries into the
///   exponent (max ∈ [255.5, 256)·2^(e−8)), where it is ≤ max/255.5; so the
///   bound that always holds is max/255.5 (< max/256 · 1.002);
/// * channels below half a step flush to exactly 0: always when
///   `c < max·2⁻⁹`, possibly when `c < max·2⁻⁸`.
///
/// Range: a largest channel below `f32::MIN_POSITIVE` (zero, subnormals)
/// encodes to exactly zero — every normal f32 has an in-range exponent.
/// Channels above [`RGBE_MAX`] (≥ 2^127 needs exponent byte 256) saturate
/// to exponent byte 255 with mantissas clamped to 255; the exponent byte
/// never wraps.
///
/// Negative, NaN or infinite channels are rejected with
/// [`PhotonError::InvalidPower`].
pub fn rgbe_encode(rgb: Vec3) -> Result<[u8; 4], PhotonError> {
    check_power(rgb)?;
    Ok(rgbe_encode_valid(rgb.to_array()))
}

fn rgbe_encode_valid(c: [f32; 3]) -> [u8; 4] {
    let max = c[0].max(c[1]).max(c[2]);
    if max < f32::MIN_POSITIVE {
        return [0; 4];
    }
    let max = max as f64;
    // frexp: max = m·2^e with m in [0.5, 1) (max is a normal f64 here).
    let mut e = ((max.to_bits() >> 52) & 0x7ff) as i32 - 1022;
    if max * exp2i_f64(8 - e) + 0.5 >= 256.0 {
        // Rounding the largest mantissa up to 256 carries into the exponent.
        e += 1;
    }
    // Exponent byte 256 would wrap: saturate at byte 255 instead (the
    // mantissas then clamp to 255 through the saturating `as u8`).
    let e = e.min(127);
    let scale = exp2i_f64(8 - e);
    let q = |x: f32| (x as f64 * scale + 0.5) as u8;
    [q(c[0]), q(c[1]), q(c[2]), (e + 128) as u8]
}

/// Decodes Ward's RGBE: `byte · 2^(E−136)` per channel, exactly zero when
/// the exponent byte is 0. Exact in f32 (no rounding) for every input.
#[inline]
pub fn rgbe_decode(rgbe: [u8; 4]) -> Vec3 {
    if rgbe[3] == 0 {
        return Vec3::ZERO;
    }
    let f = exp2i_f32(rgbe[3] as i32 - 136);
    Vec3::new(rgbe[0] as f32 * f, rgbe[1] as f32 * f, rgbe[2] as f32 * f)
}
