//! Which lobes an operation takes part in: the lobe selections, and the BSDF's evaluation,
//! pdf and sampling over a selection (one-sample MIS), per Russian-roulette component.

use super::normals::{bump_shadowing, CosineOf};
use super::{mean, Bsdf, BsdfSample, Component, LobeFlags, MAX_LOBES};
use crate::materials::lobe::Lobe;
use crate::math::Spectrum;
use glam::{Vec2, Vec3};

/// Which lobes take part in an operation, and which hemispheres they may scatter into.
#[derive(Clone, Copy, Debug)]
pub(super) struct Selection {
    /// Scattering sides allowed: `REFLECTION`, `TRANSMISSION` or both.
    pub(super) mask: u8,
    /// Lobes are kept when their flags contain any of these bits...
    pub(super) include: u8,
    /// ...and none of these.
    pub(super) exclude: u8,
}

pub(super) const SELECT_ALL: Selection = Selection {
    mask: LobeFlags::REFLECTION | LobeFlags::TRANSMISSION,
    include: LobeFlags::ALL,
    exclude: 0,
};

impl Selection {
    pub(super) fn for_component(c: Component) -> Selection {
        match c {
            Component::Diffuse => Selection {
                mask: LobeFlags::REFLECTION,
                include: LobeFlags::DIFFUSE,
                exclude: 0,
            },
            Component::Specular => Selection {
                mask: LobeFlags::REFLECTION,
                include: LobeFlags::ALL,
                exclude: LobeFlags::DIFFUSE,
            },
            Component::Transmission => Selection {
                mask: LobeFlags::TRANSMISSION,
                include: LobeFlags::ALL,
                exclude: 0,
            },
            Component::NearSpecular => Selection {
                mask: LobeFlags::REFLECTION,
                include: LobeFlags::NEAR_SPECULAR,
                exclude: LobeFlags::DIFFUSE,
            },
            Component::SpecularOther => Selection {
                mask: LobeFlags::REFLECTION,
                include: LobeFlags::ALL,
                exclude: LobeFlags::DIFFUSE | LobeFlags::NEAR_SPECULAR,
            },
        }
    }
    pub(super) fn keeps(&self, lobe: &Lobe) -> bool {
        let f = lobe.flags();
        f & self.include != 0 && f & self.exclude == 0
    }
}

/// Delta and near-specular lobes on both sides: what final gathering follows by sampling.
pub(super) const SELECT_SPECULAR_LIKE: Selection = Selection {
    mask: LobeFlags::REFLECTION | LobeFlags::TRANSMISSION,
    include: LobeFlags::SPECULAR | LobeFlags::NEAR_SPECULAR,
    exclude: 0,
};

/// Glossy (non-delta, non-diffuse) lobes on both sides.
pub(super) const SELECT_GLOSSY: Selection = Selection {
    mask: LobeFlags::REFLECTION | LobeFlags::TRANSMISSION,
    include: LobeFlags::GLOSSY,
    exclude: LobeFlags::DIFFUSE | LobeFlags::SPECULAR,
};

impl Bsdf {
    /// Directional albedo of one reflection [`Component`] at `wo` (world space), from the
    /// lobes' estimates (`Lobe::albedo`).
    pub fn component_albedo(&self, wo: Vec3, component: Component) -> Spectrum {
        let sel = Selection::for_component(component);
        let wo = self.frame.to_local(wo);
        self.lobes_at(wo)
            .filter(|(_, _, l)| sel.keeps(l))
            .map(|(i, w, _)| w * self.lobe_albedo(i, wo, sel.mask).max(Vec3::ZERO))
            .sum()
    }

    /// Directional reflectivities for photon Russian roulette at `wo` (world space):
    /// (diffuse, specular + glossy reflection, transmission). Each is an estimate of the
    /// component's directional albedo, exact for Lambert, smooth conductors and smooth
    /// dielectrics; the three are scaled down together if their means sum above one, so
    /// they can serve directly as the probabilities P_d, P_s, P_t of Jensen 2001 §6.3
    /// (mean over channels), with absorption 1 - P_d - P_s - P_t.
    pub fn rr_reflectivities(&self, wo: Vec3) -> (Spectrum, Spectrum, Spectrum) {
        let wo = self.frame.to_local(wo);
        let (mut d, mut s, mut t) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
        if wo.z == 0.0 || !wo.is_finite() {
            return (d, s, t);
        }
        for (i, w, l) in self.lobes_at(wo) {
            let r = w * self
                .lobe_albedo(i, wo, LobeFlags::REFLECTION)
                .max(Vec3::ZERO);
            if l.flags() & LobeFlags::DIFFUSE != 0 {
                d += r;
            } else {
                s += r;
            }
            t += w * self
                .lobe_albedo(i, wo, LobeFlags::TRANSMISSION)
                .max(Vec3::ZERO);
        }
        let total = mean(d) + mean(s) + mean(t);
        if total > 1.0 {
            let k = 1.0 / total;
            (d * k, s * k, t * k)
        } else {
            (d, s, t)
        }
    }

    /// Samples only one [`Component`] (after Russian roulette chose it), for a photon that
    /// arrived from `wo` and leaves along the sampled `wi`. The weight is the adjoint's,
    /// f_c(wi, wo) |cos wi| / pdf_c of that component alone (or its delta factor over the
    /// discrete probability): the lobes that depend on the view direction only (Cycles'
    /// layering and multiple-scattering compensation) are not reciprocal, and light leaving
    /// along `wi` is what they weigh. Divide it by the probability of having chosen the
    /// component.
    pub fn sample_component(
        &self,
        wo: Vec3,
        component: Component,
        u_lobe: f32,
        u: Vec2,
    ) -> Option<BsdfSample> {
        let sel = Selection::for_component(component);
        let wo_l = self.frame.to_local(wo);
        let mut s = self.sample_sel(wo_l, u_lobe, u, sel)?;
        if !s.is_delta() && s.flags & LobeFlags::REFLECTION != 0 {
            // Reflection: evaluate with the directions swapped (the reciprocal lobes give the
            // same value; refraction keeps the camera's, see `importance_weight`). Under a
            // bump the photon's flux carries the smooth surface's cosine where it arrived and
            // leaves with the smooth surface's cosine (Veach 1997 §5.3, the adjoint BSDF with
            // shading normals): f(wi, wo) cos_lobe(wo) / cos_s(wo) cos_s(wi) / pdf.
            let f = self.eval_mode(s.wi, wo_l, sel, CosineOf::Flux);
            let cos_out = match self.bump {
                Some((ns, _, _)) => ns.dot(s.wi).abs(),
                None => s.wi.z.abs(),
            };
            s.weight = f * (cos_out / s.pdf);
        }
        Some(BsdfSample {
            wi: self.frame.to_world(s.wi),
            ..s
        })
    }

    /// f of one component alone, world-space directions.
    pub fn eval_component(&self, wo: Vec3, wi: Vec3, component: Component) -> Spectrum {
        let sel = Selection::for_component(component);
        self.eval_sel(self.frame.to_local(wo), self.frame.to_local(wi), sel)
    }

    /// Pdf of [`Bsdf::sample_component`], world-space directions.
    pub fn pdf_component(&self, wo: Vec3, wi: Vec3, component: Component) -> f32 {
        let sel = Selection::for_component(component);
        self.pdf_sel(self.frame.to_local(wo), self.frame.to_local(wi), sel)
    }

    pub(super) fn eval_sel(&self, wo: Vec3, wi: Vec3, sel: Selection) -> Spectrum {
        self.eval_mode(wo, wi, sel, CosineOf::Wi)
    }

    /// f of the selected lobes; `cosine`: see [`Bsdf::lobe_eval`].
    pub(super) fn eval_mode(
        &self,
        wo: Vec3,
        wi: Vec3,
        sel: Selection,
        cosine: CosineOf,
    ) -> Spectrum {
        if wo.z == 0.0 || wi.z == 0.0 {
            return Vec3::ZERO;
        }
        let mut f = Vec3::ZERO;
        for (i, w, l) in self.lobes_at(wo) {
            if sel.keeps(l) {
                // A coat with a normal of its own is shadowed against that normal (not at all
                // when it is the smooth one, a coat left unbumped).
                let g = match self.bump {
                    None => 1.0,
                    Some((ns, a2, true)) => match self.coat_n.filter(|_| self.in_coat_frame[i]) {
                        Some(r) => bump_shadowing(r * ns, a2, r * wi, false),
                        None => bump_shadowing(ns, a2, wi, l.flags() & LobeFlags::DIFFUSE != 0),
                    },
                    Some((_, _, false)) => 1.0,
                };
                if g > 0.0 {
                    f += w * g * self.lobe_eval(i, wo, wi, sel.mask, cosine);
                }
            }
        }
        if f.is_finite() {
            f.max(Vec3::ZERO)
        } else {
            Vec3::ZERO
        }
    }

    /// Lobe selection probabilities at `wo` and their sum (before normalisation).
    fn selection(&self, wo: Vec3, sel: Selection) -> ([f32; MAX_LOBES], f32) {
        let mut p = [0.0f32; MAX_LOBES];
        let mut sum = 0.0;
        for (i, w, l) in self.lobes_at(wo) {
            if sel.keeps(l) {
                let a = mean(w * self.lobe_albedo(i, wo, sel.mask));
                let v = a;
                if v > 0.0 && v.is_finite() {
                    p[i] = v;
                    sum += v;
                }
            }
        }
        if sum > 0.0 {
            for v in p.iter_mut() {
                *v /= sum;
            }
        }
        (p, sum)
    }

    pub(super) fn pdf_sel(&self, wo: Vec3, wi: Vec3, sel: Selection) -> f32 {
        if wo.z == 0.0 || wi.z == 0.0 {
            return 0.0;
        }
        let (p, sum) = self.selection(wo, sel);
        if sum <= 0.0 {
            return 0.0;
        }
        let mut pdf = 0.0;
        for (i, (_, l)) in self.lobes().enumerate() {
            if p[i] > 0.0 && l.flags() & LobeFlags::SPECULAR == 0 {
                pdf += p[i] * l.pdf(self.in_lobe(i, wo), self.in_lobe(i, wi), sel.mask);
            }
        }
        if pdf.is_finite() {
            pdf.max(0.0)
        } else {
            0.0
        }
    }

    pub(super) fn sample_sel(
        &self,
        wo: Vec3,
        u_lobe: f32,
        u: Vec2,
        sel: Selection,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 || !wo.is_finite() {
            return None;
        }
        let (p, sum) = self.selection(wo, sel);
        if sum <= 0.0 {
            return None;
        }
        // Pick lobe k with probability p[k]; remap u_lobe to [0,1) inside its interval.
        let u_lobe = u_lobe.clamp(0.0, 1.0);
        let mut k = usize::MAX;
        let mut cdf = 0.0f32;
        for (i, &pi) in p.iter().enumerate().take(self.count) {
            if pi > 0.0 {
                k = i;
                if u_lobe < cdf + pi {
                    break;
                }
                cdf += pi;
            }
        }
        if k == usize::MAX {
            return None;
        }
        let pk = p[k];
        let uc = ((u_lobe - cdf) / pk).clamp(0.0, 0.999_999_94);
        let lobe = &self.lobes[k];
        let mut s = lobe.sample(self.in_lobe(k, wo), uc, u, sel.mask)?;
        if let Some(r) = self.rot(k) {
            s.wi = r.transpose() * s.wi;
        }
        if s.is_delta() {
            let weight = self.weight_at(k, wo) * s.weight / pk;
            let pdf = pk * s.pdf;
            return (weight.is_finite() && pdf > 0.0).then_some(BsdfSample { weight, pdf, ..s });
        }
        let pdf = self.pdf_sel(wo, s.wi, sel);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let f = self.eval_sel(wo, s.wi, sel);
        let weight = f * (s.wi.z.abs() / pdf);
        weight
            .is_finite()
            .then_some(BsdfSample { weight, pdf, ..s })
    }
}
