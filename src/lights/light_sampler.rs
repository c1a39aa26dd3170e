//! Chooses a light in proportion to its power (luminance of Φ).

use crate::math::{luminance, Spectrum};
use crate::sampling::Distribution1D;

#[derive(Clone, Debug)]
pub struct LightSampler {
    dist: Distribution1D,
    count: usize,
}

impl LightSampler {
    pub fn new(powers: &[Spectrum]) -> Self {
        let f: Vec<f32> = powers.iter().map(|p| luminance(*p).max(0.0)).collect();
        LightSampler {
            dist: Distribution1D::new(&f),
            count: powers.len(),
        }
    }

    /// (light index, probability), or None when there are no lights.
    pub fn sample(&self, u: f32) -> Option<(usize, f32, f32)> {
        if self.count == 0 {
            return None;
        }
        let (i, p, u2) = self.dist.sample_discrete(u);
        (p > 0.0).then_some((i, p, u2))
    }

    pub fn pmf(&self, i: usize) -> f32 {
        if i < self.count {
            self.dist.discrete_pdf(i)
        } else {
            0.0
        }
    }
}
