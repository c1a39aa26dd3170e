//! The subsurface material's lobe, below which camera paths walk.

use super::{mean, Bsdf, LobeFlags};
use crate::materials::lobe::Lobe;
use crate::math::Spectrum;
use glam::Vec3;

impl Bsdf {
    /// Adds `weight * lobe` as the lobe a subsurface material's camera paths walk below
    /// (see [`Bsdf::subsurface_entry`]); every other path reflects it as it is.
    pub fn add_subsurface(&mut self, weight: f32, lobe: Lobe) -> bool {
        let added = self.add(weight, lobe);
        if added {
            self.subsurface = Some((self.count - 1) as u8);
        }
        added
    }

    /// Whether a lobe is a subsurface material's.
    pub fn has_subsurface(&self) -> bool {
        self.subsurface.is_some()
    }

    /// The same BSDF without its subsurface lobe (what a camera path estimates at the
    /// surface itself).
    pub fn without_subsurface(&self) -> Bsdf {
        let Some(k) = self.subsurface else {
            return *self;
        };
        let mut b = Bsdf::new(self.frame);
        b.coat = self.coat;
        b.bump = self.bump;
        b.spec = self.spec;
        b.coat_n = self.coat_n;
        for (i, (w, l)) in self.lobes().enumerate() {
            if i != k as usize && b.add(w, *l) {
                b.coated[b.count - 1] = self.coated[i];
                b.in_coat_frame[b.count - 1] = self.in_coat_frame[i];
            }
        }
        b
    }

    /// What the subsurface lobe sends towards `wo` (world space) per unit of what arrives
    /// below it: its weight (under the coat) times its directional albedo, and the lobe's
    /// GGX roughness; `None` without a subsurface lobe.
    pub fn subsurface_entry(&self, wo: Vec3) -> Option<(Spectrum, f32)> {
        let i = self.subsurface? as usize;
        let wo = self.frame.to_local(wo);
        let Lobe::CoatedDiffuse(l) = &self.lobes[i] else {
            return None;
        };
        Some((
            self.weight_at(i, wo) * self.lobes[i].albedo(wo, LobeFlags::ALL),
            l.roughness,
        ))
    }

    /// The subsurface lobe's share of the diffuse reflection at `wo` (world space), in the
    /// channels' mean: the probability that a photon the diffuse component takes walks below
    /// the surface. 0 without a subsurface lobe.
    pub fn subsurface_share(&self, wo: Vec3) -> f32 {
        let Some(k) = self.subsurface else {
            return 0.0;
        };
        let wo = self.frame.to_local(wo);
        let (mut ss, mut all) = (0.0, 0.0);
        for (i, w, l) in self.lobes_at(wo) {
            if l.flags() & LobeFlags::DIFFUSE != 0 {
                let r = mean(w * l.albedo(wo, LobeFlags::REFLECTION).max(Vec3::ZERO));
                all += r;
                if i == k as usize {
                    ss += r;
                }
            }
        }
        if all > 0.0 && ss.is_finite() {
            (ss / all).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }
}
