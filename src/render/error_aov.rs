//! The `error` AOV: each pixel's estimated standard error, from independent replicates.
//!
//! A pixel's samples (or progressive passes) are dealt in turn to `REPLICATES` independent
//! replicates: sample `k` goes to replicate `k mod R` as its sample `k div R`. Each replicate
//! is a complete stratified estimate of its own (its own randomisation of the sampling
//! pattern: a digital shift of the Sobol (0,2)-sequence, or its own jittered grid), so the
//! replicate means are independent and identically distributed, and the spread of the R
//! means gives the variance of their mean without bias: s² / R (randomised quasi-Monte
//! Carlo with independent replicates, Owen 1997). Batch means of one stratified sequence
//! would overstate it several times at edges, where stratification helps most.
//!
//! What it measures: the noise of whatever each replicate redraws. In progressive photon
//! mapping every pass has a fresh photon map, so photon noise is included (and the
//! progressive mode adds its bias estimate, see `sppm`). In Jensen's mode the maps and the
//! irradiance cache are shared by all samples, so only the camera-sample noise is.

use crate::math::Spectrum;
use crate::sampling::Rng;
use glam::{DVec3, Vec2};

/// Independent replicates per pixel.
pub const REPLICATES: usize = 4;

/// Which replicate sample `k` of a pixel belongs to, and its index within that replicate.
#[inline]
pub fn replicate_of(k: u32) -> (usize, u32) {
    ((k as usize) % REPLICATES, k / REPLICATES as u32)
}

/// The digital shifts of a pixel's replicates of the Sobol (0,2)-sequence.
#[derive(Clone, Copy, Debug)]
pub struct Shifts([(u32, u32); REPLICATES]);

impl Shifts {
    pub fn draw(rng: &mut Rng) -> Shifts {
        let mut s = [(0, 0); REPLICATES];
        for v in s.iter_mut() {
            *v = (rng.next_u32(), rng.next_u32());
        }
        Shifts(s)
    }

    /// The film sample in [0,1)^2 of the pixel's sample `k`: point `k div R` of the (0,2)
    /// sequence under replicate `k mod R`'s shift. Every power-of-two prefix of a replicate
    /// is stratified.
    pub fn point(&self, k: u32) -> Vec2 {
        let (r, j) = replicate_of(k);
        let (sx, sy) = crate::sampling::sobol02(j);
        let (hx, hy) = self.0[r];
        Vec2::new(
            crate::sampling::to_unit(sx ^ hx),
            crate::sampling::to_unit(sy ^ hy),
        )
    }
}

/// Running sums of one pixel's replicates.
#[derive(Clone, Copy, Debug, Default)]
pub struct Replicates {
    sums: [Spectrum; REPLICATES],
    counts: [u32; REPLICATES],
}

impl Replicates {
    /// The running sums and counts (to continue them elsewhere).
    pub fn to_parts(&self) -> ([Spectrum; REPLICATES], [u32; REPLICATES]) {
        (self.sums, self.counts)
    }

    /// The replicates of [`Replicates::to_parts`].
    pub fn from_parts(sums: [Spectrum; REPLICATES], counts: [u32; REPLICATES]) -> Self {
        Replicates { sums, counts }
    }

    /// Adds sample `k` of the pixel (its value of the combined image).
    pub fn add(&mut self, k: u32, v: Spectrum) {
        let (r, _) = replicate_of(k);
        self.sums[r] += v;
        self.counts[r] += 1;
    }

    /// Mean of every sample added; 0 before any.
    pub fn mean(&self) -> Spectrum {
        let n: u32 = self.counts.iter().sum();
        if n == 0 {
            return Spectrum::ZERO;
        }
        self.sums.iter().copied().sum::<Spectrum>() / n as f32
    }

    /// Standard error of the pixel's mean, per channel: sqrt(s² / R) over the replicate
    /// means; 0 while fewer than two replicates have samples.
    pub fn standard_error(&self) -> Spectrum {
        let means: Vec<DVec3> = self
            .sums
            .iter()
            .zip(&self.counts)
            .filter(|(_, &c)| c > 0)
            .map(|(s, &c)| s.as_dvec3() / c as f64)
            .collect();
        let r = means.len();
        if r < 2 {
            return Spectrum::ZERO;
        }
        let mean = means.iter().copied().sum::<DVec3>() / r as f64;
        let s2 = means
            .iter()
            .map(|m| (*m - mean) * (*m - mean))
            .sum::<DVec3>()
            / (r - 1) as f64;
        (s2 / r as f64).to_array().map(|v| v.sqrt() as f32).into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// For independent samples the replicate error matches sigma / sqrt(n): over many pixels
    /// of uniform samples (sigma² = 1/12), the mean squared error estimate is within 5% of
    /// 1/(12 n).
    #[test]
    fn matches_sigma_over_sqrt_n_for_iid_samples() {
        for n in [4u32, 8, 16, 64, 256] {
            let mut rng = Rng::new(7, n as u64);
            let pixels = 6000;
            let mut acc = 0.0f64;
            for _ in 0..pixels {
                let mut b = Replicates::default();
                for k in 0..n {
                    b.add(k, Spectrum::splat(rng.f32()));
                }
                acc += (b.standard_error().x as f64).powi(2);
            }
            let expected = 1.0 / (12.0 * n as f64);
            let got = acc / pixels as f64;
            assert!(
                (got / expected - 1.0).abs() < 0.05,
                "n {n}: {got:.3e} vs {expected:.3e}"
            );
        }
    }

    /// A stratified estimate of a pixel half covered by an edge: the replicate error matches
    /// the true spread of the pixel mean over many randomisations, within 10%, where a
    /// sample-by-sample variance would overstate it several times.
    #[test]
    fn is_calibrated_for_stratified_samples_at_an_edge() {
        let n = 64u32;
        let pixels = 4000;
        let mut rng = Rng::new(3, 1);
        let (mut pred, mut means, mut naive) = (0.0f64, Vec::new(), 0.0f64);
        for _ in 0..pixels {
            let shifts = Shifts::draw(&mut rng);
            let mut b = Replicates::default();
            let (mut s, mut s2) = (0.0f64, 0.0f64);
            for k in 0..n {
                let u = shifts.point(k);
                let v = if u.x + 0.3 * u.y < 0.6 { 1.0 } else { 0.0 };
                b.add(k, Spectrum::splat(v));
                s += v as f64;
                s2 += (v * v) as f64;
            }
            pred += (b.standard_error().x as f64).powi(2);
            means.push(s / n as f64);
            let m = s / n as f64;
            naive += (s2 / n as f64 - m * m) / (n - 1) as f64;
        }
        let mu = means.iter().sum::<f64>() / pixels as f64;
        let truth = means.iter().map(|m| (m - mu).powi(2)).sum::<f64>() / (pixels - 1) as f64;
        let pred = pred / pixels as f64;
        let naive = naive / pixels as f64;
        assert!(
            (pred / truth - 1.0).abs() < 0.1,
            "{pred:.3e} vs {truth:.3e}"
        );
        assert!(
            naive > 3.0 * truth,
            "the naive estimate {naive:.3e} vs {truth:.3e}"
        );
    }

    #[test]
    fn constant_samples_have_zero_error_and_one_sample_is_unknown() {
        let mut b = Replicates::default();
        b.add(0, Spectrum::ONE);
        assert_eq!(b.standard_error(), Spectrum::ZERO);
        for k in 1..99 {
            b.add(k, Spectrum::ONE);
        }
        assert_eq!(b.standard_error(), Spectrum::ZERO);
        assert_eq!(b.mean(), Spectrum::ONE);
    }
}
