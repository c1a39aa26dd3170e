//! Subsurface scattering of the Principled material, as Cycles' random walk defines it
//! (Chiang, Kutz & Burley 2016, "Practical and Controllable Subsurface Scattering for
//! Production Path Tracing"; anisotropy after Wrenninge, Villemin & Hery 2017).
//!
//! | parameter | meaning |
//! |---|---|
//! | `weight` | share of the Principled diffuse base that scatters below the surface |
//! | `color` | the albedo a walk returns in a half-space (the base colour by default) |
//! | `radius` | RGB mean free path in scene units (Blender Radius x Scale) |
//! | `ior` | index of refraction of the entry (Random Walk: the material's IOR; Skin: Subsurface IOR) |
//! | `anisotropy` | Henyey-Greenstein g inside, in [0, 0.9] |
//! | `skin` | Blender's Random Walk (Skin): half of the entries diffuse, the others through a GGX interface of roughness 1 |
//!
//! The transport, in the direction a camera path takes (`render::terms::subsurface::walk`):
//! the path refracts into the mesh through a GGX interface (alpha = roughness^2, or 1 for
//! Skin), walks a homogeneous medium of extinction 1 / (l (1 - g)), with the mean free path
//! l = radius / (4 pi) (Skin: scaled by the colour's dipole albedo, [`radius_scale`]), and
//! single-scattering albedo fitted to `color`, and leaves at the first surface of the same object it meets. The
//! exit is a white Lambertian surface: what it receives from the lights, the caustic and the
//! global photon map, divided by pi, is what the walk carries back. Photons walk the other
//! way (`render::terms::subsurface::photon_walk`) and are stored where they leave, for the
//! final-gathering rays that land on the material.

use crate::math::Spectrum;
use crate::scene::desc::SubsurfaceDesc;

/// Largest anisotropy (Cycles clamps the same way).
pub const MAX_ANISOTROPY: f32 = 0.9;
/// Radius channels at or below this (in scene units) render as the diffuse base (Cycles'
/// `BSSRDF_MIN_RADIUS`).
pub const MIN_RADIUS: f32 = 1e-8;
/// Radii above this are clamped.
pub const MAX_RADIUS: f32 = 1e12;
/// The entry's IOR is kept within Cycles' range for subsurface IORs.
pub const IOR_RANGE: (f32, f32) = (1.01, 3.8);
/// Single-scattering albedos below this are raised to it, the walk's weight lowered to match
/// (Cycles: a smooth transition to albedo 0).
const MIN_ALPHA: f32 = 0.2;
/// Scattering events after which a walk gives up (Cycles' `BSSRDF_MAX_BOUNCES`).
pub const MAX_BOUNCES: u32 = 256;
/// Events after which an anisotropic medium is walked as its isotropic similar one
/// (Cycles' `SUBSURFACE_RANDOM_WALK_SIMILARITY_LEVEL`).
pub const SIMILARITY_LEVEL: u32 = 9;

/// A Principled material's subsurface part, as rendered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Subsurface {
    pub weight: f32,
    /// The colour the subsurface lobe reflects (0 in channels rendered as the diffuse base).
    pub color: Spectrum,
    /// Channels too thin to walk, rendered as the diffuse base: 1 where they walk, else 0.
    pub walks: Spectrum,
    pub ior: f32,
    pub g: f32,
    pub skin: bool,
    /// Extinction and single-scattering albedo per channel.
    pub sigma_t: Spectrum,
    pub alpha: Spectrum,
    /// A walk's starting weight per unit of the lobe's colour: 1 / colour (0 where the colour
    /// is 0), lowered where `alpha` was raised to its minimum.
    pub start: Spectrum,
}

/// Cycles' fit of the single-scattering albedo that gives the multiple-scattering `albedo`
/// for anisotropy `g` (`subsurface_random_walk_remap`).
pub fn single_scattering_albedo(albedo: f32, g: f32) -> f32 {
    let albedo = albedo.clamp(0.0, 1.0);
    let g2 = g * g;
    let g3 = g2 * g;
    let g4 = g3 * g;
    let g5 = g4 * g;
    let g6 = g5 * g;
    let g7 = g6 * g;
    let a = 1.8260523782 - 1.28451056436 * g - 1.79904629312 * g2 + 9.19393289202 * g3
        - 22.8215585862 * g4
        + 32.0234874259 * g5
        - 23.6264803333 * g6
        + 7.21067002658 * g7;
    let b = 4.98511194385
        + 0.127355959438
            * (31.1491581433 * g - 201.847017512 * g2 + 841.576016723 * g3 - 2018.09288505 * g4
                + 2731.71560286 * g5
                - 1935.41424244 * g6
                + 559.009054474 * g7)
                .exp();
    let c = 1.09686102424 - 0.394704063468 * g + 1.05258115941 * g2 - 8.83963712726 * g3
        + 28.8643230661 * g4
        - 46.8802913581 * g5
        + 38.5402837518 * g6
        - 12.7181042538 * g7;
    let d = 0.496310210422 + 0.360146581622 * g - 2.15139309747 * g2 + 17.8896899217 * g3
        - 55.2984010333 * g4
        + 82.065982243 * g5
        - 58.5106008578 * g6
        + 15.8478295021 * g7;
    let e = 4.23190299701
        + 0.00310603949088
            * (76.7316253952 * g - 594.356773233 * g2 + 2448.8834203 * g3 - 5576.68528998 * g4
                + 7116.60171912 * g5
                - 4763.54467887 * g6
                + 1303.5318055 * g7)
                .exp();
    let f = 2.40602999408 - 2.51814844609 * g + 9.18494908356 * g2 - 79.2191708682 * g3
        + 259.082868209 * g4
        - 403.613804597 * g5
        + 302.85712436 * g6
        - 87.4370473567 * g7;
    let blend = albedo.powf(0.25);
    let alpha =
        (1.0 - blend) * a * (b * albedo).atan().powf(c) + blend * d * (e * albedo).atan().powf(f);
    if alpha.is_finite() {
        alpha.clamp(0.0, 0.999_999)
    } else {
        0.0
    }
}

/// The mean free path per unit of the material's radius, as Cycles sets it up
/// (`bssrdf_setup_radius`): 1 / (4 pi) for Random Walk, so that it looks like the older
/// Cubic, Gaussian and Burley profiles; for Skin, sqrt(3 (1 - a')) with a' the single-scattering
/// albedo whose dipole reflectance (Jensen's F_dr for the IOR) is the colour.
pub fn radius_scale(skin: bool, color: f32, ior: f32) -> f32 {
    if !skin {
        return 0.25 * std::f32::consts::FRAC_1_PI;
    }
    let inv_eta = 1.0 / ior;
    let f_dr = inv_eta * (-1.440 * inv_eta + 0.710) + 0.668 + 0.0636 * ior;
    let a4_3 = (4.0 / 3.0) * (1.0 + f_dr) / (1.0 - f_dr);
    let rd = |ap: f32| {
        let s = (3.0 * (1.0 - ap)).sqrt();
        0.5 * ap * (1.0 + (-a4_3 * s).exp()) * (-s).exp()
    };
    let alpha_prime = if color < 1e-4 {
        0.0
    } else if color >= 0.995 {
        0.999_999
    } else {
        // Bisection, 12 steps, as Cycles does.
        let (mut x0, mut x1, mut xmid) = (0.0f32, 1.0f32, 0.5f32);
        for _ in 0..12 {
            xmid = 0.5 * (x0 + x1);
            if rd(xmid) < color {
                x0 = xmid;
            } else {
                x1 = xmid;
            }
        }
        xmid
    };
    (3.0 * (1.0 - alpha_prime)).sqrt()
}

/// Whether a radius channel is walked (finite, above [`MIN_RADIUS`]).
pub fn radius_walks(r: f32) -> bool {
    r.is_finite() && r > MIN_RADIUS
}

impl Subsurface {
    /// The subsurface part of a Principled material of base colour `base` and IOR `ior`, or
    /// `None` when it has none: weight 0 or not finite, or no channel with a usable radius
    /// (it renders as the diffuse base; validation warns).
    pub fn from_desc(d: &SubsurfaceDesc, base: Spectrum, ior: f32) -> Option<Subsurface> {
        if !(d.weight.is_finite() && d.weight > 0.0) {
            return None;
        }
        if !d.radius.iter().any(|&r| radius_walks(r)) {
            return None;
        }
        let g = if d.anisotropy.is_finite() {
            d.anisotropy.clamp(0.0, MAX_ANISOTROPY)
        } else {
            0.0
        };
        let color = d.color.map(Spectrum::from).unwrap_or(base);
        let ior = d.ior.unwrap_or(ior);
        let ior = if ior.is_finite() {
            ior.clamp(IOR_RANGE.0, IOR_RANGE.1)
        } else {
            1.4
        };
        let mut s = Subsurface {
            weight: d.weight.min(1.0),
            color: Spectrum::ZERO,
            walks: Spectrum::ZERO,
            ior,
            g,
            skin: d.method == crate::scene::desc::SubsurfaceMethod::Skin,
            sigma_t: Spectrum::ONE,
            alpha: Spectrum::ZERO,
            start: Spectrum::ZERO,
        };
        for k in 0..3 {
            let c = if color[k].is_finite() {
                color[k].clamp(0.0, 1.0)
            } else {
                0.0
            };
            let r = d.radius[k];
            if !radius_walks(r) {
                continue;
            }
            s.walks[k] = 1.0;
            s.color[k] = c;
            let r = r.min(MAX_RADIUS) * radius_scale(s.skin, c, ior);
            s.sigma_t[k] = 1.0 / (r * (1.0 - g));
            let alpha = single_scattering_albedo(c, g);
            s.start[k] = if c > 0.0 { 1.0 / c } else { 0.0 };
            if alpha < MIN_ALPHA {
                s.start[k] *= alpha / MIN_ALPHA;
                s.alpha[k] = MIN_ALPHA;
            } else {
                s.alpha[k] = alpha;
            }
        }
        Some(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn desc(radius: [f32; 3]) -> SubsurfaceDesc {
        SubsurfaceDesc {
            weight: 1.0,
            radius,
            color: None,
            ior: None,
            anisotropy: 0.0,
            method: Default::default(),
        }
    }

    #[test]
    fn the_albedo_fit_is_monotone_and_white_stays_white() {
        let mut last = -1.0;
        for i in 0..=20 {
            let a = single_scattering_albedo(i as f32 / 20.0, 0.0);
            // Strictly increasing until the clamp just below 1.
            assert!(a > last || a == 0.999_999, "{i}: {a} after {last}");
            last = a;
        }
        assert!(single_scattering_albedo(1.0, 0.0) > 0.9999);
        assert_eq!(single_scattering_albedo(0.0, 0.0), 0.0);
        // The fit at 0.8 (isotropic), evaluated independently: 0.99175.
        let a = single_scattering_albedo(0.8, 0.0);
        assert!((a - 0.99175).abs() < 1e-4, "{a}");
    }

    #[test]
    fn coefficients_follow_the_radius() {
        let s = Subsurface::from_desc(&desc([1.0, 0.5, 0.25]), Spectrum::splat(0.8), 1.5).unwrap();
        // Random Walk: the mean free path is the radius / (4 pi).
        let st = s.sigma_t / (4.0 * std::f32::consts::PI);
        assert!(
            (st.x - 1.0).abs() < 1e-5 && (st.y - 2.0).abs() < 1e-5 && (st.z - 4.0).abs() < 1e-4
        );
        assert_eq!(s.ior, 1.5);
        assert!((s.start.x - 1.25).abs() < 1e-6);
        // Radius 0 everywhere, NaN, negative: no subsurface (the diffuse base).
        for r in [[0.0; 3], [f32::NAN; 3], [-1.0; 3]] {
            assert!(Subsurface::from_desc(&desc(r), Spectrum::ONE, 1.5).is_none());
        }
        // One channel of radius 0: that channel is the diffuse base's.
        let s = Subsurface::from_desc(&desc([1.0, 0.0, 1.0]), Spectrum::splat(0.5), 1.5).unwrap();
        assert_eq!(s.walks, Spectrum::new(1.0, 0.0, 1.0));
        assert_eq!(s.color, Spectrum::new(0.5, 0.0, 0.5));
        let mut d = desc([1.0; 3]);
        d.weight = 0.0;
        assert!(Subsurface::from_desc(&d, Spectrum::ONE, 1.5).is_none());
    }

    #[test]
    fn dark_colours_raise_the_albedo_and_lower_the_start() {
        let s = Subsurface::from_desc(&desc([1.0; 3]), Spectrum::new(0.01, 0.0, 0.9), 1.5).unwrap();
        assert_eq!(s.alpha.x, MIN_ALPHA);
        let a = single_scattering_albedo(0.01, 0.0);
        assert!((s.start.x - a / MIN_ALPHA / 0.01).abs() < 1e-3 * s.start.x);
        assert_eq!(s.start.y, 0.0);
        assert!(s.alpha.z > 0.99);
    }
}
