//! Light groups (`SceneDesc::lightgroups`): one image per group, the light of its emitters
//! alone; the groups sum to the beauty.
//!
//! Every estimator that can tell where its light came from adds each group's share to a
//! [`Split`] beside the total it returns: next-event estimation by the light it sampled,
//! emitters seen directly by the emitter, and the photon maps by the group each photon
//! carries (the light that emitted it, in the photon's flag word: `photon::map::group_of`).
//! What is precomputed from photons keeps its groups' shares: the irradiance points of the
//! global map and the irradiance cache's records hold each group's fraction of their
//! irradiance, and a lookup splits the interpolated irradiance by the interpolated
//! fractions, so that the shares still sum to it. A group's image thus estimates the render
//! with that group's emitters alone, within noise (`tests/lightgroups.rs`).
//!
//! Without groups nothing here runs: the estimators get no split.

pub use crate::math::fractions;
use crate::math::Spectrum;
use crate::scene::Scene;

/// Radiance split by light group: estimators add each group's share, which lands in `acc`
/// times `scale` (the throughput of the path to the estimate).
pub struct Split<'a> {
    acc: &'a mut [Spectrum],
    scale: Spectrum,
}

impl<'a> Split<'a> {
    /// Shares added to `acc` (one entry per group) as they are.
    pub fn new(acc: &'a mut [Spectrum]) -> Split<'a> {
        Split {
            acc,
            scale: Spectrum::ONE,
        }
    }

    /// Adds group `group`'s share `v`.
    #[inline]
    pub fn add(&mut self, group: usize, v: Spectrum) {
        if let Some(a) = self.acc.get_mut(group) {
            *a += self.scale * v;
        }
    }

    /// Adds light `light`'s share `v` to its group.
    #[inline]
    pub fn add_light(&mut self, scene: &Scene, light: u32, v: Spectrum) {
        let g = scene.light_group.get(light as usize).copied().unwrap_or(0);
        self.add(g as usize, v);
    }

    /// Adds `total` split by `fractions` (each group's fraction per channel).
    #[inline]
    pub fn add_fractions(&mut self, total: Spectrum, fractions: &[Spectrum]) {
        for (g, f) in fractions.iter().enumerate() {
            self.add(g, total * *f);
        }
    }

    /// The same split, its shares scaled by `s` as well.
    pub fn scaled(&mut self, s: Spectrum) -> Split<'_> {
        Split {
            acc: &mut *self.acc,
            scale: self.scale * s,
        }
    }

    /// Groups.
    pub fn len(&self) -> usize {
        self.acc.len()
    }

    pub fn is_empty(&self) -> bool {
        self.acc.is_empty()
    }
}

/// A split scaled by `s`, if there is one.
#[inline]
pub fn scaled<'s>(split: &'s mut Option<&mut Split<'_>>, s: Spectrum) -> Option<Split<'s>> {
    split.as_mut().map(|sp| sp.scaled(s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_are_scaled_and_fractions_split_the_total() {
        let mut acc = vec![Spectrum::ZERO; 2];
        let mut s = Split::new(&mut acc);
        s.add(0, Spectrum::ONE);
        {
            let mut half = s.scaled(Spectrum::splat(0.5));
            half.add(1, Spectrum::new(2.0, 4.0, 6.0));
            let mut quarter = half.scaled(Spectrum::splat(0.5));
            quarter.add(1, Spectrum::splat(4.0));
        }
        s.add(7, Spectrum::ONE); // no such group: ignored
        assert_eq!(acc[0], Spectrum::ONE);
        assert_eq!(acc[1], Spectrum::new(2.0, 3.0, 4.0));
        let total = acc[0] + acc[1];
        let f = fractions(&acc, total);
        let mut back = vec![Spectrum::ZERO; 2];
        Split::new(&mut back).add_fractions(total, &f);
        assert!((back[0] - acc[0]).abs().max_element() < 1e-6);
        assert!((back[1] - acc[1]).abs().max_element() < 1e-6);
        assert_eq!(fractions(&acc, Spectrum::ZERO), vec![Spectrum::ZERO; 2]);
    }
}
