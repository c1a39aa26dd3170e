//! `specular`: everything reaching the eye after at least one perfect mirror or refraction
//! bounce (Jensen 2001, §9.1 "specular and glossy reflection", here the perfectly specular
//! part). The eye path follows delta lobes, chosen by sampling, up to a maximum depth; at the
//! end of the chain each term's estimator runs as it would at a directly visible point, and its
//! result is routed here instead of to its own AOV.

use crate::materials::bsdf::{Bsdf, BsdfSample, LobeFlags};
use crate::math::Spectrum;
use crate::render::aov::Term;
use crate::sampling::Rng;
use glam::Vec3;

/// Where the estimate of `term` goes for an eye path that has made `specular_bounces` delta bounces.
#[inline]
pub fn route(term: Term, specular_bounces: u32) -> Term {
    if specular_bounces == 0 {
        term
    } else {
        Term::Specular
    }
}

/// Russian roulette on long specular chains: continue with probability tied to the throughput.
/// Returns the new throughput, or None to stop.
#[inline]
pub fn continue_chain(beta: Spectrum, bounces: u32, u: f32) -> Option<Spectrum> {
    if bounces < 3 {
        return Some(beta);
    }
    let q = beta.max_element().min(0.95);
    if q <= 0.0 || u >= q {
        None
    } else {
        Some(beta / q)
    }
}

/// Which lobes a specular chain follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Follow {
    /// Perfectly specular lobes, chosen by sampling the whole BSDF: a sample of another lobe
    /// ends the chain (the eye pass and the irradiance cache's first-surface search, where
    /// the estimators answer for those lobes).
    Specular,
    /// Perfectly specular and near-specular lobes, sampled alone (gather rays, whose hit
    /// estimate leaves the near-specular lobes out).
    NearSpecular,
}

/// The next bounce of a specular chain leaving a surface with `bsdf` towards `wo`, or `None`
/// where the chain ends there. Rough glass (`Bsdf::passes_through`), which no estimate
/// covers, is followed whole either way.
pub fn next_bounce(bsdf: &Bsdf, wo: Vec3, follow: Follow, rng: &mut Rng) -> Option<BsdfSample> {
    let passes = bsdf.passes_through();
    let lobes = match follow {
        Follow::Specular => LobeFlags::SPECULAR,
        Follow::NearSpecular => LobeFlags::SPECULAR | LobeFlags::NEAR_SPECULAR,
    };
    if bsdf.flags() & lobes == 0 && !passes {
        return None;
    }
    let (u_lobe, u) = (rng.f32(), rng.vec2());
    match follow {
        _ if passes => bsdf.sample(wo, u_lobe, u),
        Follow::Specular => bsdf.sample(wo, u_lobe, u).filter(|bs| bs.is_delta()),
        Follow::NearSpecular => bsdf.sample_specular_like(wo, u_lobe, u),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::conductor::SpecularReflection;
    use crate::materials::dielectric::SmoothDielectric;
    use crate::materials::diffuse::Lambert;
    use crate::materials::fresnel::Fresnel;
    use crate::materials::lobe::Lobe;
    use crate::materials::microfacet::Ggx;
    use crate::materials::rough_dielectric::RoughDielectric;
    use crate::math::Frame;

    fn bsdf(lobes: &[(f32, Lobe)]) -> Bsdf {
        let mut b = Bsdf::new(Frame::from_normal(Vec3::Z));
        for (w, l) in lobes {
            b.add(*w, *l);
        }
        b
    }

    fn lambert() -> Lobe {
        Lobe::Lambert(Lambert {
            albedo: Spectrum::splat(0.5),
        })
    }

    fn mirror() -> Lobe {
        Lobe::SpecularReflection(SpecularReflection {
            fresnel: Fresnel::Constant(Spectrum::ONE),
        })
    }

    /// How often the chain goes on from `b`, and whether every bounce it takes is delta.
    fn taken(b: &Bsdf, follow: Follow) -> (f32, bool) {
        let mut rng = Rng::new(1, 2);
        let wo = Vec3::new(0.3, 0.1, 0.9).normalize();
        let mut n = 0;
        let mut all_delta = true;
        for _ in 0..2000 {
            if let Some(bs) = next_bounce(b, wo, follow, &mut rng) {
                n += 1;
                all_delta &= bs.is_delta();
            }
        }
        (n as f32 / 2000.0, all_delta)
    }

    #[test]
    fn a_chain_follows_mirrors_and_glass_and_ends_at_diffuse_surfaces() {
        let glass = Lobe::SmoothDielectric(SmoothDielectric {
            eta: 1.5,
            tint: Spectrum::ONE,
            refraction_only: false,
        });
        for follow in [Follow::Specular, Follow::NearSpecular] {
            assert_eq!(taken(&bsdf(&[(1.0, lambert())]), follow).0, 0.0);
            assert_eq!(taken(&bsdf(&[(1.0, mirror())]), follow), (1.0, true));
            assert_eq!(taken(&bsdf(&[(1.0, glass)]), follow), (1.0, true));
        }
    }

    #[test]
    fn half_mirror_half_diffuse_goes_on_by_sampling_or_by_its_mirror_alone() {
        let b = bsdf(&[(0.5, lambert()), (0.5, mirror())]);
        // Sampling the whole BSDF picks a lobe in proportion to weight x albedo, the mirror
        // (0.5 x 1) two times in three beside the diffuse lobe (0.5 x 0.5), and only then
        // goes on.
        let (f, delta) = taken(&b, Follow::Specular);
        assert!((f - 2.0 / 3.0).abs() < 0.04 && delta, "{f}");
        // Gather rays sample the specular part alone: always.
        assert_eq!(taken(&b, Follow::NearSpecular), (1.0, true));
    }

    #[test]
    fn rough_glass_is_followed_whole_and_near_specular_only_by_gather_rays() {
        let rough = Lobe::RoughDielectric(RoughDielectric {
            ggx: Ggx::new(0.3),
            eta: 1.5,
            tint: Spectrum::ONE,
            multiscatter: true,
            refraction_only: false,
        });
        let b = bsdf(&[(1.0, rough)]);
        assert!(b.passes_through());
        for follow in [Follow::Specular, Follow::NearSpecular] {
            let (f, delta) = taken(&b, follow);
            assert!(f > 0.9 && !delta, "{follow:?}: {f}");
        }
    }
}
