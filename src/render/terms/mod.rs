//! One file per term of the rendering equation (Jensen 2001, §9.1; media, chapter 10).
pub mod caustic;
pub mod direct;
pub mod emission;
pub mod indirect;
pub mod specular;
pub mod subsurface;
#[cfg(test)]
pub(crate) mod testing;
pub mod volume;

use crate::photon::map::{FLAG_CAUSTIC_PATH, FLAG_FIRST_HIT, FLAG_SUBSURFACE_EXIT};
use crate::render::aov::Term;

/// The term a surface photon's light belongs to where a density estimate reads it, at an eye
/// path's shading point after `specular_bounces` delta bounces: none for a first-hit photon
/// (direct light is `direct`'s, by light sampling), `caustic` for a light -> specular+ -> here
/// path, `indirect` for the rest; behind a specular bounce, `specular` (see
/// [`specular::route`]).
#[inline]
pub fn of_photon(flags: u16, specular_bounces: u32) -> Option<Term> {
    if flags & (FLAG_FIRST_HIT | FLAG_SUBSURFACE_EXIT) != 0 {
        return None;
    }
    let term = if flags & FLAG_CAUSTIC_PATH != 0 {
        Term::Caustic
    } else {
        Term::Indirect
    };
    Some(specular::route(term, specular_bounces))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn photons_go_to_the_term_of_their_path() {
        assert_eq!(of_photon(FLAG_FIRST_HIT, 0), None);
        assert_eq!(of_photon(FLAG_FIRST_HIT, 2), None);
        assert_eq!(of_photon(FLAG_CAUSTIC_PATH, 0), Some(Term::Caustic));
        assert_eq!(of_photon(0, 0), Some(Term::Indirect));
        assert_eq!(of_photon(FLAG_CAUSTIC_PATH, 1), Some(Term::Specular));
        assert_eq!(of_photon(0, 3), Some(Term::Specular));
    }
}
