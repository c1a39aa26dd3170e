//! Adaptive sampling of the camera pass: after every pixel has taken its `spp` samples, the
//! pixels in noisy regions take more, in whole rounds of `spp` (each round a complete
//! stratified set), up to `max_factor` rounds in all.
//!
//! **How many.** A pixel's noise is the standard error of its combined image's luminance
//! (the `error` AOV's replicates) over the square root of its mean luminance times the
//! image's brightness: the form of Cycles' noise threshold (error over the root of the
//! value), between absolute error (which only sees highlights) and relative error (which only
//! sees the dark), made free of light units and exposure by the image's brightness (its mean
//! luminance with the brightest 1% clamped). Halving the noise takes four times the samples,
//! so a pixel whose neighbourhood is at noise `e` takes `ceil((e / threshold)^2)` rounds,
//! clamped to `1..=max_factor`.
//!
//! **Without bias.** Stopping a pixel when its own samples look converged is biased: a
//! pixel whose first samples missed a rare bright path (a small light seen through glass)
//! stops at a value too dark, one that caught it takes more samples and dilutes it, and
//! the expectation falls short of the pixel's value. So a pixel's rounds are decided once,
//! after the first round, from its eight neighbours' noise (the largest of them) and never
//! from its own samples. Each pixel's samples are then independent of how many it takes,
//! and its mean is unbiased for any decision. A feature one pixel wide is refined only if
//! it is noisy in its neighbours too.
//!
//! The decision reads only the first round of every pixel, which is the same for any thread
//! count, so the film stays bit-identical whatever the threads.

use super::settings::RenderSettings;
use crate::math::{luminance, Spectrum};

/// The adaptive stage's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adaptive {
    /// Target noise: standard error / sqrt(mean luminance x the image's brightness).
    pub threshold: f32,
    /// Most rounds of `spp` samples a pixel takes, the first included.
    pub max_factor: u32,
}

/// What the adaptive stage did, for the stats.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct AdaptiveStats {
    pub threshold: f32,
    pub max_factor: u32,
    /// Pixels that took more than one round.
    pub pixels_refined: u64,
    /// Camera samples taken beyond the first round, over the whole image.
    pub extra_samples: u64,
    /// Mean samples per pixel over the image.
    pub mean_spp: f64,
}

/// Floor of the noise measure's denominator, as a fraction of the image's brightness: below
/// it, noise is judged as if absolute.
const DARK: f32 = 1e-3;

/// The image's brightness that noise is measured against: the mean luminance of the pixels,
/// each clamped at the 99th percentile so that a light seen in frame does not set it.
pub fn brightness(means: &[f32]) -> f32 {
    if means.is_empty() {
        return 0.0;
    }
    let mut sorted: Vec<f32> = means
        .iter()
        .map(|m| if m.is_finite() { m.max(0.0) } else { 0.0 })
        .collect();
    let k = ((sorted.len() - 1) as f64 * 0.99).round() as usize;
    let (_, cap, _) = sorted.select_nth_unstable_by(k, f32::total_cmp);
    let cap = *cap;
    (sorted.iter().map(|&m| m.min(cap) as f64).sum::<f64>() / sorted.len() as f64) as f32
}

/// Each pixel's noise: the standard error of its luminance over sqrt(mean x `brightness`),
/// both in luminance. Scaling every light scales error and mean alike, so the noise and the
/// decisions do not change with light units or exposure.
pub fn noise_map(means: &[Spectrum], errors: &[Spectrum]) -> Vec<f32> {
    let lum: Vec<f32> = means.iter().map(|m| luminance(*m)).collect();
    let b = brightness(&lum);
    lum.iter()
        .zip(errors)
        .map(|(&m, e)| noise(m, luminance(e.max(Spectrum::ZERO)), b))
        .collect()
}

/// One pixel's noise, from its mean and standard error (luminance) and the image's
/// brightness; 0 in a black image.
fn noise(mean: f32, standard_error: f32, brightness: f32) -> f32 {
    if brightness <= 0.0 {
        return 0.0;
    }
    let n = standard_error / (mean.max(DARK * brightness) * brightness).sqrt();
    if n.is_finite() {
        n.max(0.0)
    } else {
        0.0
    }
}

impl AdaptiveStats {
    /// The stats of adaptive stage `a` that gave `rounds` (one per pixel of the image) of
    /// `spp` samples, `extra_samples` beyond the first round.
    pub fn of(a: Adaptive, rounds: &[u32], spp: u32, extra_samples: u64) -> AdaptiveStats {
        AdaptiveStats {
            threshold: a.threshold,
            max_factor: a.max_factor,
            pixels_refined: rounds.iter().filter(|&&r| r > 1).count() as u64,
            extra_samples,
            mean_spp: rounds.iter().map(|&r| (r * spp) as f64).sum::<f64>()
                / rounds.len().max(1) as f64,
        }
    }
}

impl Adaptive {
    /// The adaptive stage of the settings `s`, if they ask for one: adaptive sampling on, a
    /// threshold above 0 and room for a second round under `max_spp`.
    pub fn of(s: &RenderSettings) -> Option<Adaptive> {
        let max_factor = s.max_spp / s.spp.max(1);
        (s.adaptive_sampling && s.noise_threshold > 0.0 && max_factor > 1).then_some(Adaptive {
            threshold: s.noise_threshold,
            max_factor,
        })
    }

    /// Rounds per pixel (`1..=max_factor`) of a `w`-by-`h` image whose pixels have the
    /// given `noise` after their first round: from the largest of the eight neighbours'.
    pub fn rounds(&self, noise: &[f32], w: usize, h: usize) -> Vec<u32> {
        debug_assert_eq!(noise.len(), w * h);
        let max_factor = self.max_factor.max(1);
        (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as i64, (i / w) as i64);
                let mut m = 0.0f32;
                for dy in -1..=1i64 {
                    for dx in -1..=1i64 {
                        let (nx, ny) = (x + dx, y + dy);
                        if (dx, dy) == (0, 0)
                            || nx < 0
                            || ny < 0
                            || nx >= w as i64
                            || ny >= h as i64
                        {
                            continue;
                        }
                        m = m.max(noise[ny as usize * w + nx as usize]);
                    }
                }
                if self.threshold <= 0.0 {
                    return 1;
                }
                let r = (m / self.threshold).powi(2).ceil();
                if r.is_finite() {
                    (r as u32).clamp(1, max_factor)
                } else {
                    max_factor
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_is_error_over_root_mean_times_brightness() {
        // A uniform image of mean 4: brightness 4, noise = se / 4.
        let means = vec![Spectrum::splat(4.0); 100];
        let mut errors = vec![Spectrum::splat(0.2); 100];
        errors[7] = Spectrum::splat(f32::NAN);
        let n = noise_map(&means, &errors);
        assert!((n[0] - 0.05).abs() < 1e-6, "{}", n[0]);
        assert_eq!(n[7], 0.0, "a non-finite error is no noise");
        // Every light 1000 times brighter: the same noise.
        let m2: Vec<Spectrum> = means.iter().map(|m| *m * 1000.0).collect();
        let e2: Vec<Spectrum> = errors.iter().map(|e| *e * 1000.0).collect();
        let n2 = noise_map(&m2, &e2);
        assert!((n2[0] - n[0]).abs() < 1e-6, "{} {}", n2[0], n[0]);
        // A black pixel is judged against the floor, not divided by zero; a black image has
        // no noise.
        let mut dark = means.clone();
        dark[3] = Spectrum::ZERO;
        let d = noise_map(&dark, &errors)[3];
        let b = brightness(&dark.iter().map(|m| luminance(*m)).collect::<Vec<_>>());
        assert!((d - 0.2 / (DARK * b * b).sqrt()).abs() < 1e-3 * d, "{d}");
        assert!(noise_map(&[Spectrum::ZERO; 4], &[Spectrum::ONE; 4])
            .iter()
            .all(|&v| v == 0.0));
    }

    /// A light in frame, far brighter than the rest, does not set the brightness.
    #[test]
    fn brightness_ignores_the_brightest_percent() {
        let mut m = vec![0.5f32; 1000];
        for v in m.iter_mut().take(10) {
            *v = 800.0;
        }
        let b = brightness(&m);
        assert!((b - 0.5).abs() < 1e-6, "{b}");
        assert_eq!(brightness(&[]), 0.0);
    }

    /// A pixel's rounds never read its own noise, only its neighbours'; four times the
    /// samples per halving of the noise; clamped.
    #[test]
    fn rounds_read_neighbours_only() {
        let a = Adaptive {
            threshold: 0.1,
            max_factor: 8,
        };
        let (w, h) = (5, 4);
        let mut n = vec![0.0f32; w * h];
        n[2 * w + 2] = 0.2; // one noisy pixel at (2, 2)
        let r = a.rounds(&n, w, h);
        assert_eq!(r[2 * w + 2], 1, "its own noise does not refine it");
        for (x, y) in [
            (1, 1),
            (2, 1),
            (3, 1),
            (1, 2),
            (3, 2),
            (1, 3),
            (2, 3),
            (3, 3),
        ] {
            assert_eq!(r[y * w + x], 4, "(0.2 / 0.1)^2 rounds at ({x},{y})");
        }
        assert_eq!(r.iter().filter(|&&v| v > 1).count(), 8);
        n[0] = 10.0;
        let r = a.rounds(&n, w, h);
        assert_eq!(r[1], 8, "clamped to max_factor");
        assert_eq!(r[w + 1], 8);
        let off = Adaptive {
            threshold: 0.0,
            max_factor: 8,
        };
        assert!(off.rounds(&n, w, h).iter().all(|&v| v == 1));
    }
}
