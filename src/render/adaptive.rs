//! Adaptive sampling of the camera pass: after every pixel has taken its `spp` samples, the
//! pixels in noisy regions take more, in whole rounds of `spp` (each round a complete
//! stratified set), up to `max_factor` rounds in all.
//!
//! **How many.** A pixel's noise is the standard error of its combined image's luminance
//! (the `error` AOV's replicates) over the square root of its mean luminance: the measure
//! Cycles' noise threshold uses, between absolute error (which only sees highlights) and
//! relative error (which only sees the dark). Halving the noise takes four times the samples,
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
    /// Target noise: standard error / sqrt(mean luminance).
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

/// Luminance floor of the noise measure's denominator: below it, noise is judged as if
/// absolute.
const DARK: f32 = 1e-3;

/// A pixel's noise: standard error over the square root of its mean, both in luminance.
pub fn noise(mean: Spectrum, standard_error: Spectrum) -> f32 {
    let se = luminance(standard_error.max(Spectrum::ZERO));
    let m = luminance(mean).max(DARK);
    let n = se / m.sqrt();
    if n.is_finite() {
        n
    } else {
        0.0
    }
}

impl Adaptive {
    /// The adaptive stage of the settings `s`, if they ask for one: a threshold above 0 and
    /// room for a second round under `max_spp`.
    pub fn of(s: &RenderSettings) -> Option<Adaptive> {
        let max_factor = s.max_spp / s.spp.max(1);
        (s.noise_threshold > 0.0 && max_factor > 1).then_some(Adaptive {
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
                        if (dx, dy) == (0, 0) || nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64
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
    fn noise_is_error_over_root_mean() {
        let n = noise(Spectrum::splat(4.0), Spectrum::splat(0.2));
        assert!((n - 0.1).abs() < 1e-6, "{n}");
        // Dark pixels are judged against the floor, not divided by zero.
        let d = noise(Spectrum::ZERO, Spectrum::splat(1e-3));
        assert!((d - 1e-3 / DARK.sqrt()).abs() < 1e-6, "{d}");
        assert_eq!(noise(Spectrum::ONE, Spectrum::splat(f32::NAN)), 0.0);
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
        for (x, y) in [(1, 1), (2, 1), (3, 1), (1, 2), (3, 2), (1, 3), (2, 3), (3, 3)] {
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
