//! What a pixel accumulates over its camera samples, a parameter of the camera-pass driver
//! (`driver`): f32 sums ([`Sums`], Jensen's mode and sppm) or 64-bit fixed-point sums
//! ([`FixedSums`], pppm, whose blocks of passes merge in any order to the same bits).
//!
//! Both keep each term's sum over the samples and, for the `error` AOV, the sums of the
//! combined image per replicate (`error_aov`). Both drop a term's non-finite estimate (the
//! finite-sample firewall) and say how many they dropped.

use super::aov::Term;
use super::error_aov::{Replicates, REPLICATES};
use super::film::TermRadiance;
use crate::math::Spectrum;

/// One unit of radiance in the fixed point of [`FixedSums`]: 2^24.
pub const FIXED_ONE: f64 = (1u64 << 24) as f64;

/// Largest absolute value of one sample's estimate of one term of one pixel in fixed point
/// (2^29 ≈ 5.4e8); a larger one is clamped.
pub const MAX_PASS_VALUE: f64 = (1u64 << 29) as f64;

/// Integers per pixel of the fixed-point term sums: RGB per term.
pub const TERM_VALUES: usize = Term::COUNT * 3;
/// Integers per pixel of the fixed-point replicate sums: RGB of the combined image per
/// replicate.
pub const REPLICATE_VALUES: usize = REPLICATES * 3;

/// A pixel's sums over its samples.
pub trait Accumulator: Default + Send + Sync {
    /// Adds sample `k`: the finite terms of `l`, and their total plus `further` (the sample's
    /// share of the combined image kept elsewhere) to replicate `k mod R`, and how much of
    /// the sample is `transparent` (a transparent background or a Holdout). Returns how many
    /// terms were not finite (and were dropped).
    fn add(&mut self, k: u32, l: &TermRadiance, further: Spectrum, transparent: f32) -> usize;

    /// The pixel's alpha after `samples` samples: one minus the mean transparency, in [0, 1]
    /// (as Cycles resolves its combined pass).
    fn alpha(&self, samples: u32) -> f32;

    /// The mean of the terms over `samples` samples, and the standard error of the combined
    /// image from the replicates.
    fn resolve(&self, samples: u32) -> (TermRadiance, Spectrum);
}

/// f32 sums.
#[derive(Clone, Copy, Debug, Default)]
pub struct Sums {
    /// Sum over samples of the terms estimated at the eye (finite ones only).
    pub acc: TermRadiance,
    /// Batch means of each sample's value of the combined image (the `error` AOV).
    pub batches: Replicates,
    /// Sum over samples of their transparency.
    pub transparent: f32,
}

impl Sums {
    /// The mean of the terms over `samples` samples.
    pub fn mean(&self, samples: u32) -> TermRadiance {
        let inv = 1.0 / samples.max(1) as f32;
        let mut v = self.acc;
        for c in v.0.iter_mut() {
            *c *= inv;
        }
        v
    }
}

/// One minus the mean transparency of `samples` samples, in [0, 1].
fn alpha_of(transparent_sum: f64, samples: u32) -> f32 {
    (1.0 - transparent_sum / samples.max(1) as f64).clamp(0.0, 1.0) as f32
}

impl Accumulator for Sums {
    fn add(&mut self, k: u32, l: &TermRadiance, further: Spectrum, transparent: f32) -> usize {
        if transparent.is_finite() {
            self.transparent += transparent;
        }
        let mut total = Spectrum::ZERO;
        let mut dropped = 0;
        for t in Term::ALL {
            let v = l.0[t.index()];
            if v.is_finite() {
                self.acc.0[t.index()] += v;
                total += v;
            } else {
                dropped += 1;
            }
        }
        self.batches.add(k, total + further);
        dropped
    }

    fn alpha(&self, samples: u32) -> f32 {
        alpha_of(self.transparent as f64, samples)
    }

    fn resolve(&self, samples: u32) -> (TermRadiance, Spectrum) {
        (self.mean(samples), self.batches.standard_error())
    }
}

/// Fixed-point sums: each sample's value of each term rounded to 2^-24 ([`FIXED_ONE`]) and
/// added to 64-bit integers. Integer addition is associative and commutative (wrapping, so
/// even an intermediate overflow cancels out): the sums of samples 0..N are the same bits
/// however they were split into blocks, rendered and merged.
#[derive(Clone, Copy, Debug)]
pub struct FixedSums {
    /// Per term, RGB.
    pub terms: [i64; TERM_VALUES],
    /// Per replicate, RGB of the combined image.
    pub replicates: [i64; REPLICATE_VALUES],
    /// Samples added per replicate.
    pub counts: [u32; REPLICATES],
    /// The samples' transparency.
    pub transparent: i64,
}

impl Default for FixedSums {
    fn default() -> Self {
        FixedSums {
            terms: [0; TERM_VALUES],
            replicates: [0; REPLICATE_VALUES],
            counts: [0; REPLICATES],
            transparent: 0,
        }
    }
}

impl Accumulator for FixedSums {
    fn add(&mut self, k: u32, l: &TermRadiance, further: Spectrum, transparent: f32) -> usize {
        if transparent.is_finite() {
            self.transparent = self.transparent.wrapping_add(quantize(transparent));
        }
        let mut combined = [0i64; 3];
        let mut dropped = 0;
        for t in Term::ALL {
            let v = l.0[t.index()];
            if !v.is_finite() {
                dropped += 1;
                continue;
            }
            for (c, sum) in combined.iter_mut().enumerate() {
                let q = quantize(v[c]);
                let j = t.index() * 3 + c;
                self.terms[j] = self.terms[j].wrapping_add(q);
                *sum = sum.wrapping_add(q);
            }
        }
        let r = k as usize % REPLICATES;
        for (c, sum) in combined.iter().enumerate() {
            let q = if further[c].is_finite() {
                quantize(further[c])
            } else {
                0
            };
            let j = r * 3 + c;
            self.replicates[j] = self.replicates[j].wrapping_add(sum.wrapping_add(q));
        }
        self.counts[r] += 1;
        dropped
    }

    fn alpha(&self, samples: u32) -> f32 {
        fixed_alpha(self.transparent, samples)
    }

    fn resolve(&self, samples: u32) -> (TermRadiance, Spectrum) {
        (
            fixed_means(&self.terms, samples),
            replicate_error(&self.replicates, &self.counts).into(),
        )
    }
}

/// The fixed-point value of one sample's estimate.
#[inline]
pub fn quantize(v: f32) -> i64 {
    let x = (v as f64 * FIXED_ONE).round();
    x.clamp(-MAX_PASS_VALUE * FIXED_ONE, MAX_PASS_VALUE * FIXED_ONE) as i64
}

/// Each term's mean over `samples` samples from its fixed-point sums (`sums`: RGB per term).
pub fn fixed_means(sums: &[i64], samples: u32) -> TermRadiance {
    let k = samples.max(1) as f64;
    let mut v = TermRadiance::default();
    for t in Term::ALL {
        let j = t.index() * 3;
        v.0[t.index()] = Spectrum::new(
            (sums[j] as f64 / FIXED_ONE / k) as f32,
            (sums[j + 1] as f64 / FIXED_ONE / k) as f32,
            (sums[j + 2] as f64 / FIXED_ONE / k) as f32,
        );
    }
    v
}

/// A pixel's alpha from the fixed-point sum of its samples' transparency.
pub fn fixed_alpha(transparent: i64, samples: u32) -> f32 {
    alpha_of(transparent as f64 / FIXED_ONE, samples)
}

/// Standard error of a pixel's mean from its replicates' fixed-point sums (`sums`: RGB per
/// replicate) and sample counts: sqrt(s² / R) over the replicate means.
pub fn replicate_error(sums: &[i64], counts: &[u32; REPLICATES]) -> [f32; 3] {
    let mut out = [0.0f32; 3];
    for (c, o) in out.iter_mut().enumerate() {
        let means: Vec<f64> = (0..REPLICATES)
            .filter(|&r| counts[r] > 0)
            .map(|r| sums[r * 3 + c] as f64 / FIXED_ONE / counts[r] as f64)
            .collect();
        let n = means.len();
        if n < 2 {
            continue;
        }
        let m = means.iter().sum::<f64>() / n as f64;
        let s2 = means.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1) as f64;
        *o = (s2 / n as f64).sqrt() as f32;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantisation_is_exact_on_the_fixed_point_grid_and_clamped() {
        assert_eq!(quantize(1.0), FIXED_ONE as i64);
        assert_eq!(quantize(-0.5), -(FIXED_ONE as i64) / 2);
        assert_eq!(quantize(1e12), (MAX_PASS_VALUE * FIXED_ONE) as i64);
    }

    /// Both accumulators drop the same non-finite terms and agree on the means.
    #[test]
    fn both_accumulators_drop_non_finite_terms_and_agree() {
        let (mut a, mut b) = (Sums::default(), FixedSums::default());
        for k in 0..8u32 {
            let mut l = TermRadiance::default();
            l.0[0] = Spectrum::splat(0.25 * k as f32);
            l.0[1] = if k == 3 {
                Spectrum::splat(f32::NAN)
            } else {
                Spectrum::new(1.0, 2.0, 0.5)
            };
            let t = 0.125 * (k % 3) as f32;
            let (da, db) = (
                a.add(k, &l, Spectrum::ZERO, t),
                b.add(k, &l, Spectrum::ZERO, t),
            );
            assert_eq!(da, db);
            assert_eq!(da, usize::from(k == 3));
        }
        let ((ma, ea), (mb, eb)) = (a.resolve(8), b.resolve(8));
        for t in 0..Term::COUNT {
            assert!((ma.0[t] - mb.0[t]).abs().max_element() < 1e-6, "term {t}");
        }
        assert!((ea - eb).abs().max_element() < 1e-5);
        assert!(ea.max_element() > 0.0);
        // Transparency 0, 1/8, 1/4, 0, ... over 8 samples: 1 - 0.875/8.
        assert_eq!(a.alpha(8), 1.0 - 0.875 / 8.0);
        assert_eq!(b.alpha(8), 1.0 - 0.875 / 8.0);
        assert_eq!(Sums::default().alpha(0), 1.0);
    }
}
