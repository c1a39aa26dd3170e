//! `specular`: everything reaching the eye after at least one perfect mirror or refraction
//! bounce (Jensen 2001, §9.1 "specular and glossy reflection", here the perfectly specular
//! part). The eye path follows delta lobes, chosen by sampling, up to a maximum depth; at the
//! end of the chain each term's estimator runs as it would at a directly visible point, and its
//! result is routed here instead of to its own AOV.

use crate::math::Spectrum;
use crate::render::aov::Term;

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
