//! `subsurface`: light that leaves a surface after entering it below a subsurface material.
//!
//! A camera path that reaches a subsurface material's lobe (`Bsdf::subsurface_entry`) walks
//! below it as Cycles' Random Walk does (`materials::subsurface`): it refracts in through a
//! GGX interface, scatters in a homogeneous medium, and leaves at the first surface of the
//! same object it meets. There the photon maps answer, as on any diffuse surface: the exit is
//! a white Lambertian surface, and its `direct`, `caustic` and `indirect` estimates, times the
//! walk's weight, are this term. The walk is the BSSRDF, sampled; the light reaching its exit
//! comes from the lights and the photon maps (Jensen & Buhler 2002 gather the irradiance at
//! the surface the same way, under a diffusion BSSRDF).
//!
//! Light reaching the material from anywhere else walks below it too, as in Cycles, where a
//! Random Walk material stays one after any bounce: a photon that the lobe takes walks the
//! other way ([`photon_walk`]), entering where it arrived, and is stored where it leaves
//! (`FLAG_SUBSURFACE_EXIT`); a final-gathering ray that lands on the material reads those
//! photons' exitance. So light passes through a thin or weakly scattering object onto what
//! lies behind it.

pub use crate::scene::subsurface_walk::{photon_walk, walk, Exit};
