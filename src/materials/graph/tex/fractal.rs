//! Fractal sums of Perlin noise: fBm, multifractal, hybrid multifractal,
//! ridged multifractal and heterogeneous terrain, as Cycles computes them.
//!
//! All take a `detail` (number of octaves beyond the first; its fractional
//! part blends in one more octave), a `roughness` (amplitude gain per octave)
//! and a `lacunarity` (frequency gain per octave).  `detail` is clamped to
//! `[0, 15]` here as the texture nodes do, which also bounds the work for
//! non-finite input.

use super::noise::{snoise_1d, snoise_2d, snoise_3d, snoise_4d};
use glam::{Vec2, Vec3, Vec4};
use std::ops::{Add, Mul};

/// A point that signed Perlin noise can be evaluated at (`f32`, `Vec2`,
/// `Vec3` or `Vec4`).
pub trait NoisePoint: Copy + Mul<f32, Output = Self> + Add<Output = Self> {
    /// Signed noise of the point's dimension.
    fn snoise(self) -> f32;
}

impl NoisePoint for f32 {
    fn snoise(self) -> f32 {
        snoise_1d(self)
    }
}

impl NoisePoint for Vec2 {
    fn snoise(self) -> f32 {
        snoise_2d(self)
    }
}

impl NoisePoint for Vec3 {
    fn snoise(self) -> f32 {
        snoise_3d(self)
    }
}

impl NoisePoint for Vec4 {
    fn snoise(self) -> f32 {
        snoise_4d(self)
    }
}

/// Number of whole octaves after the first, and the fractional remainder.
#[inline]
fn octaves(detail: f32) -> (i32, f32) {
    let d = detail.clamp(0.0, 15.0);
    (d as i32, d - d.floor())
}

#[inline]
fn mix(a: f32, b: f32, t: f32) -> f32 {
    a + t * (b - a)
}

/// Fractal Brownian motion.  With `normalize` the sum is divided by the
/// total amplitude and remapped to about `[0, 1]`.
pub fn fbm<P: NoisePoint>(
    p: P,
    detail: f32,
    roughness: f32,
    lacunarity: f32,
    normalize: bool,
) -> f32 {
    let (n, rmd) = octaves(detail);
    let mut fscale = 1.0;
    let mut amp = 1.0;
    let mut maxamp = 0.0;
    let mut sum = 0.0;
    for _ in 0..=n {
        sum += (p * fscale).snoise() * amp;
        maxamp += amp;
        amp *= roughness;
        fscale *= lacunarity;
    }
    let norm = |s: f32, m: f32| 0.5 * s / m + 0.5;
    if rmd != 0.0 {
        let sum2 = sum + (p * fscale).snoise() * amp;
        if normalize {
            mix(norm(sum, maxamp), norm(sum2, maxamp + amp), rmd)
        } else {
            mix(sum, sum2, rmd)
        }
    } else if normalize {
        norm(sum, maxamp)
    } else {
        sum
    }
}

/// Multifractal: a product of `1 + amplitude * noise` over the octaves.
pub fn multi_fractal<P: NoisePoint>(mut p: P, detail: f32, roughness: f32, lacunarity: f32) -> f32 {
    let (n, rmd) = octaves(detail);
    let mut value = 1.0;
    let mut pwr = 1.0;
    for _ in 0..=n {
        value *= pwr * p.snoise() + 1.0;
        pwr *= roughness;
        p = p * lacunarity;
    }
    if rmd != 0.0 {
        value *= rmd * pwr * p.snoise() + 1.0;
    }
    value
}

/// Heterogeneous terrain: octaves scaled by the value so far, so that low
/// areas stay smooth.
pub fn hetero_terrain<P: NoisePoint>(
    mut p: P,
    detail: f32,
    roughness: f32,
    lacunarity: f32,
    offset: f32,
) -> f32 {
    let (n, rmd) = octaves(detail);
    let mut pwr = roughness;
    let mut value = offset + p.snoise();
    p = p * lacunarity;
    for _ in 1..=n {
        let increment = (p.snoise() + offset) * pwr * value;
        value += increment;
        pwr *= roughness;
        p = p * lacunarity;
    }
    if rmd != 0.0 {
        let increment = (p.snoise() + offset) * pwr * value;
        value += rmd * increment;
    }
    value
}

/// Hybrid additive/multiplicative multifractal.
pub fn hybrid_multi_fractal<P: NoisePoint>(
    mut p: P,
    detail: f32,
    roughness: f32,
    lacunarity: f32,
    offset: f32,
    gain: f32,
) -> f32 {
    let (n, rmd) = octaves(detail);
    let mut pwr = 1.0;
    let mut value = 0.0;
    let mut weight = 1.0;
    let mut i = 0;
    while weight > 0.001 && i <= n {
        weight = f32::min(weight, 1.0);
        let signal = (p.snoise() + offset) * pwr;
        pwr *= roughness;
        value += weight * signal;
        weight *= gain * signal;
        p = p * lacunarity;
        i += 1;
    }
    if rmd != 0.0 && weight > 0.001 {
        weight = f32::min(weight, 1.0);
        let signal = (p.snoise() + offset) * pwr;
        value += rmd * weight * signal;
    }
    value
}

/// Ridged multifractal.  Only whole octaves contribute (the fractional part
/// of `detail` is ignored, as in Cycles).
pub fn ridged_multi_fractal<P: NoisePoint>(
    mut p: P,
    detail: f32,
    roughness: f32,
    lacunarity: f32,
    offset: f32,
    gain: f32,
) -> f32 {
    let (n, _) = octaves(detail);
    let mut pwr = roughness;
    let mut signal = offset - p.snoise().abs();
    signal *= signal;
    let mut value = signal;
    for _ in 1..=n {
        p = p * lacunarity;
        let weight = (signal * gain).clamp(0.0, 1.0);
        signal = offset - p.snoise().abs();
        signal *= signal;
        signal *= weight;
        value += signal * pwr;
        pwr *= roughness;
    }
    value
}
