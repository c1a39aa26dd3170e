//! The BSDF interface: a small weighted mixture of lobes in the local shading frame.
//!
//! Conventions: the local frame has z along the shading normal; `wo` (towards the viewer, or
//! where a photon goes next when tracing backwards) and `wi` (towards the light) both point
//! away from the surface. `eval` returns f(wo, wi) without the cosine. Transmission is
//! expressed as Cycles expresses it: a camera path crossing a refractive boundary is weighted
//! by the Fresnel transmittance and the tint only, without the 1/eta^2 that physical radiance
//! takes in the denser medium (Veach 1997 §5.2). For closed objects in air the two agree (each
//! path enters and leaves); where a path leaves a medium without refracting (a Mix Shader of
//! Glass and Transparent, an alpha cut-out of glass), Cycles' image is this one. Photons,
//! which carry the adjoint, take the eta^2 instead; see [`BsdfSample::importance_weight`].

mod normals;
mod selection;
mod subsurface;

use super::layer::CoatLayer;
use super::lobe::Lobe;
use crate::geometry::{RayPath, Scatter};
use crate::math::{Frame, Spectrum};
use glam::{Mat3, Vec2, Vec3};
use normals::CosineOf;
use selection::{SELECT_ALL, SELECT_GLOSSY, SELECT_SPECULAR_LIKE};

/// Bit flags describing lobes and sampled events (a closed set of `u8` constants).
pub struct LobeFlags;

impl LobeFlags {
    pub const REFLECTION: u8 = 1;
    pub const TRANSMISSION: u8 = 2;
    pub const DIFFUSE: u8 = 4;
    pub const GLOSSY: u8 = 8;
    /// A Dirac delta lobe: its direction is chosen, never found by `eval`.
    pub const SPECULAR: u8 = 16;
    /// A glossy lobe so narrow (GGX alpha at most
    /// [`NEAR_SPECULAR_ALPHA`](super::microfacet::NEAR_SPECULAR_ALPHA)) that the photon
    /// terms treat it as specular: photon paths through it are caustic paths, and final
    /// gathering follows it by sampling instead of reading the global map on it. A photon-map
    /// density estimate cannot resolve such a lobe: its reflection changes within one search
    /// radius on a curved surface.
    pub const NEAR_SPECULAR: u8 = 32;
    pub const ALL: u8 = 63;
}

/// One sampled scattering event.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// Sampled direction (world space from [`Bsdf::sample`], local from a lobe).
    pub wi: Vec3,
    /// Throughput multiplier: f |cos theta_i| / pdf for a non-delta event; for a delta lobe
    /// the reflectance or transmittance factor divided by the discrete probability of having
    /// chosen it, so that `throughput *= weight` is right in both cases.
    pub weight: Spectrum,
    /// Solid-angle pdf of `wi` (the mixture pdf over the non-delta lobes), or, for a delta
    /// lobe, the discrete probability of having chosen it.
    pub pdf: f32,
    /// [`LobeFlags`] of the sampled event (e.g. `REFLECTION | SPECULAR`).
    pub flags: u8,
    /// Relative IOR crossed (eta_transmitted / eta_incident); 1 for reflection.
    pub eta: f32,
}

impl BsdfSample {
    /// True for a Dirac delta event.
    #[inline]
    pub fn is_delta(&self) -> bool {
        self.flags & LobeFlags::SPECULAR != 0
    }

    /// The kind of ray this sample starts, after a surface that `path` reached.
    pub fn next_path(&self, path: RayPath) -> RayPath {
        let how = if self.flags & LobeFlags::DIFFUSE != 0 {
            Scatter::Diffuse
        } else if self.is_delta() {
            Scatter::Singular
        } else {
            Scatter::Glossy
        };
        path.scattered(how, self.flags & LobeFlags::TRANSMISSION != 0)
    }
    /// The weight for flux or importance transport (photon tracing), the adjoint of `weight`:
    /// refraction into a medium of relative IOR eta scales it by 1/eta^2 (a photon entering
    /// glass from air carries 1/eta^2 of its power, and gets it back on leaving by refraction),
    /// so that a photon estimate answers what a camera path weighted by `weight` would.
    #[inline]
    pub fn importance_weight(&self) -> Spectrum {
        self.weight / (self.eta * self.eta)
    }
}

/// The parts of a BSDF that photon Russian roulette chooses between (Jensen 2001 §6.3:
/// "d and s are diffuse and specular reflectivities with d + s <= 1"), extended by
/// transmission.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Component {
    /// Diffuse reflection.
    Diffuse,
    /// Specular and glossy reflection.
    Specular,
    /// Transmission of every kind.
    Transmission,
    /// The near-specular reflection lobes alone (a part of `Specular`).
    NearSpecular,
    /// `Specular` without its near-specular lobes.
    SpecularOther,
}

/// Maximum number of lobes in one BSDF.
pub const MAX_LOBES: usize = 5;

/// A weighted sum of up to [`MAX_LOBES`] lobes, placed in a shading frame. No allocation.
#[derive(Clone, Copy, Debug)]
pub struct Bsdf {
    frame: Frame,
    lobes: [Lobe; MAX_LOBES],
    weights: [f32; MAX_LOBES],
    count: usize,
    /// A clear coat over the lobes marked in `coated` (the Principled BSDF's Coat).
    coat: Option<CoatLayer>,
    coated: [bool; MAX_LOBES],
    /// The subsurface material's lobe, which camera paths walk below, if any.
    subsurface: Option<u8>,
    /// With a bumped or normal-mapped frame: the surface's own (smooth) normal in the local
    /// frame, the bump's GGX alpha^2, and whether light is shadowed ([`normals::bump_shadowing`]).
    bump: Option<(Vec3, f32, bool)>,
    /// With a specular normal of its own ([`Bsdf::set_specular_normal`]): the rotation from
    /// the frame's local space to the local space of the non-diffuse lobes.
    spec: Option<Mat3>,
    /// With a coat normal of its own ([`Bsdf::set_coat_normal`]): the rotation from the
    /// frame's local space to the coat's, for the lobes marked in `in_coat_frame` (the coat's
    /// reflection) and the coat's layering.
    coat_n: Option<Mat3>,
    in_coat_frame: [bool; MAX_LOBES],
}

impl Bsdf {
    /// A BSDF with no lobes (black) in `frame`.
    pub fn new(frame: Frame) -> Self {
        Bsdf {
            frame,
            lobes: [Lobe::NONE; MAX_LOBES],
            weights: [0.0; MAX_LOBES],
            count: 0,
            coat: None,
            coated: [false; MAX_LOBES],
            subsurface: None,
            bump: None,
            spec: None,
            coat_n: None,
            in_coat_frame: [false; MAX_LOBES],
        }
    }

    /// Adds every lobe of `other` (built in the same frame) with its weight times `w`,
    /// keeping its coat and subsurface marks; one coat per BSDF (a second coat's lobes are
    /// added uncoated).
    pub fn absorb(&mut self, other: &Bsdf, w: f32) {
        for i in 0..other.count {
            if !self.add(other.weights[i] * w, other.lobes[i]) {
                continue;
            }
            let k = self.count - 1;
            if other.coated[i]
                && other.coat.is_some()
                && (self.coat.is_none() || self.coat == other.coat)
            {
                self.coat = other.coat;
                self.coated[k] = true;
            }
            if other.subsurface == Some(i as u8) {
                self.subsurface = Some(k as u8);
            }
            self.in_coat_frame[k] = other.in_coat_frame[i];
        }
    }

    /// Adds `weight * lobe`. Non-positive or non-finite weights and lobes beyond
    /// [`MAX_LOBES`] are ignored; returns whether the lobe was added.
    pub fn add(&mut self, weight: f32, lobe: Lobe) -> bool {
        if !(weight > 0.0 && weight.is_finite()) || self.count >= MAX_LOBES {
            return false;
        }
        self.lobes[self.count] = lobe;
        self.weights[self.count] = weight;
        self.count += 1;
        true
    }

    /// Builder form of [`Bsdf::add`].
    pub fn with(mut self, weight: f32, lobe: Lobe) -> Self {
        self.add(weight, lobe);
        self
    }

    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// The (weight, lobe) pairs.
    pub fn lobes(&self) -> impl Iterator<Item = (f32, &Lobe)> {
        self.weights[..self.count]
            .iter()
            .copied()
            .zip(self.lobes[..self.count].iter())
    }

    /// Union of the lobes' [`LobeFlags`]; 0 for a black BSDF.
    pub fn flags(&self) -> u8 {
        self.lobes().fold(0, |f, (_, l)| f | l.flags())
    }

    /// Whether some lobe can be evaluated (is not a delta).
    pub fn has_non_delta(&self) -> bool {
        self.lobes()
            .any(|(_, l)| l.flags() & LobeFlags::SPECULAR == 0)
    }

    /// Whether the BSDF reflects and transmits nothing.
    pub fn is_black(&self) -> bool {
        self.count == 0
    }

    /// f(wo, wi) for world-space directions (no cosine; delta lobes give zero).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Spectrum {
        self.eval_local(self.frame.to_local(wo), self.frame.to_local(wi))
    }

    /// f(wo, wi) for light that arrives as a photon's flux, which carries the cosine of the
    /// surface it landed on: [`Bsdf::eval`] times each lobe's cosine over that surface's (the
    /// smooth normal's under a bump or normal map, where the lobes' normals differ from it;
    /// plain f otherwise).
    pub fn eval_flux(&self, wo: Vec3, wi: Vec3) -> Spectrum {
        self.eval_mode(
            self.frame.to_local(wo),
            self.frame.to_local(wi),
            SELECT_ALL,
            CosineOf::Flux,
        )
    }

    /// Solid-angle pdf of [`Bsdf::sample`] producing `wi`, for world-space directions.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.pdf_local(self.frame.to_local(wo), self.frame.to_local(wi))
    }

    /// Samples a direction by one-sample MIS over the lobes (Veach 1997 §9.2.4): a lobe is
    /// picked with `u_lobe` in proportion to weight x albedo estimate, it samples with `u`,
    /// and non-delta samples are weighted by the mixture pdf. `wi` is in world space.
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let s = self.sample_local(self.frame.to_local(wo), u_lobe, u)?;
        Some(BsdfSample {
            wi: self.frame.to_world(s.wi),
            ..s
        })
    }

    /// True when every lobe is Lambertian, so f is the same for all directions in the
    /// hemisphere.
    pub fn is_lambertian(&self) -> bool {
        self.lobes().next().is_some() && self.lobes().all(|(_, l)| matches!(l, Lobe::Lambert(_)))
    }

    /// The diffuse part's radiance towards `wo` (world space) per unit irradiance, summed
    /// over the diffuse lobes (whose response does not depend on where the light comes from);
    /// None without a diffuse lobe. Irradiance caching applies to this part.
    pub fn diffuse_response(&self, wo: Vec3) -> Option<Spectrum> {
        let wo = self.frame.to_local(wo);
        let mut out: Option<Spectrum> = None;
        for (_, w, l) in self.lobes_at(wo) {
            if l.flags() & LobeFlags::DIFFUSE == 0 {
                continue;
            }
            let r = if self.spec.is_none() {
                l.irradiance_response(wo)
            } else {
                self.view_lobe(l, wo).irradiance_response(wo)
            };
            if let Some(r) = r {
                *out.get_or_insert(Vec3::ZERO) += w * r;
            }
        }
        out
    }

    /// The diffuse transmission lobes' radiance towards `wo` (world space) per unit of
    /// irradiance from the other side; None without such a lobe.
    pub fn transmission_response(&self, wo: Vec3) -> Option<Spectrum> {
        let wo = self.frame.to_local(wo);
        let mut out: Option<Spectrum> = None;
        for (_, w, l) in self.lobes_at(wo) {
            if let Lobe::Translucent(t) = l {
                *out.get_or_insert(Vec3::ZERO) += w * t.albedo * crate::math::INV_PI;
            }
        }
        out
    }

    /// Whether a diffuse lobe transmits: light from behind the surface reaches the viewer.
    pub fn transmits_diffusely(&self) -> bool {
        self.lobes().any(|(_, l)| matches!(l, Lobe::Translucent(_)))
    }

    /// Whether paths go on through this surface rather than end on it: rough glass (a glossy
    /// transmission lobe, no diffuse lobe). Like a mirror or smooth glass it stores no
    /// photons, photons through it are caustic photons, and eye and gather paths continue
    /// through it by sampling it.
    pub fn passes_through(&self) -> bool {
        let f = self.flags();
        f & LobeFlags::DIFFUSE == 0
            && self.lobes().any(|(_, l)| {
                let lf = l.flags();
                lf & LobeFlags::TRANSMISSION != 0 && lf & LobeFlags::GLOSSY != 0
            })
    }

    /// Whether a glossy (non-delta, non-diffuse) lobe is present.
    pub fn has_glossy(&self) -> bool {
        self.lobes().any(|(_, l)| SELECT_GLOSSY.keeps(l))
    }

    /// Samples the glossy lobes alone; the weight is f_glossy |cos| / pdf_glossy.
    pub fn sample_glossy(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let s = self.sample_sel(self.frame.to_local(wo), u_lobe, u, SELECT_GLOSSY)?;
        Some(BsdfSample {
            wi: self.frame.to_world(s.wi),
            ..s
        })
    }

    /// Directional albedo of the glossy lobes towards `wo` (world space), each lobe's
    /// estimate (`Lobe::albedo`): the glossy part's reflected radiance under uniform light.
    pub fn glossy_albedo(&self, wo: Vec3) -> Spectrum {
        let wo = self.frame.to_local(wo);
        self.lobes_at(wo)
            .filter(|(_, _, l)| SELECT_GLOSSY.keeps(l))
            .map(|(i, w, _)| w * self.lobe_albedo(i, wo, SELECT_GLOSSY.mask).max(Vec3::ZERO))
            .sum()
    }

    /// The same BSDF prepared for many evaluations towards the one view direction `wo`
    /// (world space; a photon-map radiance estimate): the lobes' view-dependent factors are
    /// computed once. Evaluations with another `wo` stay correct.
    pub fn for_view(&self, wo: Vec3) -> Bsdf {
        let wo_l = self.frame.to_local(wo);
        let mut b = *self;
        for i in 0..b.count {
            let v = self.in_lobe(i, wo_l);
            if self.spec.is_some() {
                b.lobes[i] = self.view_lobe(&self.lobes[i], wo_l);
            }
            b.lobes[i].fix_view(v);
        }
        b
    }

    /// The same BSDF with its glossy lobes only.
    pub fn glossy_part(&self) -> Bsdf {
        self.part(|l| SELECT_GLOSSY.keeps(l))
    }

    /// The same BSDF without its near-specular lobes (what a photon-map estimate on it
    /// answers for).
    pub fn without_near_specular(&self) -> Bsdf {
        self.part(|l| l.flags() & LobeFlags::NEAR_SPECULAR == 0)
    }

    /// The lobes that `keep`, under the same coat.
    fn part(&self, keep: impl Fn(&Lobe) -> bool) -> Bsdf {
        let mut b = Bsdf::new(self.frame);
        b.coat = self.coat;
        b.bump = self.bump;
        b.spec = self.spec;
        b.coat_n = self.coat_n;
        for (i, (w, l)) in self.lobes().enumerate() {
            if keep(l) && b.add(w, *l) {
                b.coated[b.count - 1] = self.coated[i];
                b.in_coat_frame[b.count - 1] = self.in_coat_frame[i];
                if self.subsurface == Some(i as u8) {
                    b.subsurface = Some((b.count - 1) as u8);
                }
            }
        }
        b
    }

    /// Samples the delta and near-specular lobes alone (world space); the weight is theirs,
    /// f_sel |cos| / pdf_sel, or a delta lobe's factor over its discrete probability.
    pub fn sample_specular_like(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let s = self.sample_sel(self.frame.to_local(wo), u_lobe, u, SELECT_SPECULAR_LIKE)?;
        Some(BsdfSample {
            wi: self.frame.to_world(s.wi),
            ..s
        })
    }

    /// [`Bsdf::eval`] with local directions.
    pub fn eval_local(&self, wo: Vec3, wi: Vec3) -> Spectrum {
        self.eval_sel(wo, wi, SELECT_ALL)
    }

    /// [`Bsdf::pdf`] with local directions.
    pub fn pdf_local(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.pdf_sel(wo, wi, SELECT_ALL)
    }

    /// [`Bsdf::sample`] with local directions.
    pub fn sample_local(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        self.sample_sel(wo, u_lobe, u, SELECT_ALL)
    }
}

#[inline]
pub(crate) fn mean(c: Spectrum) -> f32 {
    (c.x + c.y + c.z) * (1.0 / 3.0)
}
