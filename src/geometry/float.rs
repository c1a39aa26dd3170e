//! Floating-point helpers for conservative rounding-error bounds
//! (pbrt-v4, Pharr, Jakob & Humphreys, §6.8 "Managing Rounding Error").

/// Unit roundoff of `f32` (half the machine epsilon), written ε_m in pbrt.
pub const MACHINE_EPSILON: f32 = f32::EPSILON * 0.5;

/// Bound γ_n = nε/(1 − nε) on the relative error after `n` floating-point operations
/// (pbrt-v4 eq. 6.24).
///
/// | parameter | meaning |
/// |-----------|---------|
/// | `n` | number of rounded operations in the chain |
#[inline]
pub fn gamma(n: u32) -> f32 {
    let ne = n as f32 * MACHINE_EPSILON;
    ne / (1.0 - ne)
}

/// Smallest `f32` strictly greater than `v` (`+∞` and NaN are returned unchanged;
/// `-0.0` steps to the smallest positive subnormal).
#[inline]
pub fn next_float_up(v: f32) -> f32 {
    if v.is_infinite() && v > 0.0 || v.is_nan() {
        return v;
    }
    let v = if v == -0.0 { 0.0 } else { v };
    let bits = v.to_bits();
    let bits = if v >= 0.0 { bits + 1 } else { bits - 1 };
    f32::from_bits(bits)
}

/// Largest `f32` strictly less than `v` (`-∞` and NaN are returned unchanged;
/// `+0.0` steps to the smallest negative subnormal).
#[inline]
pub fn next_float_down(v: f32) -> f32 {
    if v.is_infinite() && v < 0.0 || v.is_nan() {
        return v;
    }
    let v = if v == 0.0 { -0.0 } else { v };
    let bits = v.to_bits();
    let bits = if v > 0.0 { bits - 1 } else { bits + 1 };
    f32::from_bits(bits)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn next_float_steps_one_ulp() {
        for &v in &[
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            1e-38,
            -1e-38,
            1e5,
            -3.5e7,
            f32::MAX,
        ] {
            let up = next_float_up(v);
            let down = next_float_down(v);
            assert!(up > v, "{v}");
            assert!(down < v, "{v}");
            if v.is_finite() && up.is_finite() {
                assert_eq!(next_float_down(up), if v == 0.0 { 0.0 } else { v });
            }
        }
        assert_eq!(next_float_up(f32::INFINITY), f32::INFINITY);
        assert_eq!(next_float_down(f32::NEG_INFINITY), f32::NEG_INFINITY);
        assert_eq!(next_float_up(f32::MAX), f32::INFINITY);
        assert!(next_float_up(f32::NAN).is_nan());
    }

    #[test]
    fn gamma_grows_with_n() {
        assert!(gamma(1) > 0.0);
        assert!(gamma(3) > gamma(2));
        assert!((gamma(1) - MACHINE_EPSILON).abs() < 1e-12);
    }
}
