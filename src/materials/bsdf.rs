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

use super::layer::CoatLayer;
use super::lobe::Lobe;
use crate::geometry::{RayPath, Scatter};
use crate::math::{Frame, Spectrum};
use glam::{Mat3, Vec2, Vec3};

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

/// Which lobes take part in an operation, and which hemispheres they may scatter into.
#[derive(Clone, Copy, Debug)]
struct Selection {
    /// Scattering sides allowed: `REFLECTION`, `TRANSMISSION` or both.
    mask: u8,
    /// Lobes are kept when their flags contain any of these bits...
    include: u8,
    /// ...and none of these.
    exclude: u8,
}

const SELECT_ALL: Selection = Selection {
    mask: LobeFlags::REFLECTION | LobeFlags::TRANSMISSION,
    include: LobeFlags::ALL,
    exclude: 0,
};

impl Selection {
    fn for_component(c: Component) -> Selection {
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
    fn keeps(&self, lobe: &Lobe) -> bool {
        let f = lobe.flags();
        f & self.include != 0 && f & self.exclude == 0
    }
}

/// Delta and near-specular lobes on both sides: what final gathering follows by sampling.
const SELECT_SPECULAR_LIKE: Selection = Selection {
    mask: LobeFlags::REFLECTION | LobeFlags::TRANSMISSION,
    include: LobeFlags::SPECULAR | LobeFlags::NEAR_SPECULAR,
    exclude: 0,
};

/// Glossy (non-delta, non-diffuse) lobes on both sides.
const SELECT_GLOSSY: Selection = Selection {
    mask: LobeFlags::REFLECTION | LobeFlags::TRANSMISSION,
    include: LobeFlags::GLOSSY,
    exclude: LobeFlags::DIFFUSE | LobeFlags::SPECULAR,
};

/// Which direction's cosine a caller multiplies f by (see [`Bsdf::set_specular_normal`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum CosineOf {
    Wi,
    /// None: a photon's flux carries the cosine of the surface it landed on, the smooth
    /// surface's under a bump (the frame's without one).
    Flux,
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
    /// frame, the bump's GGX alpha^2, and whether light is shadowed ([`bump_shadowing`]).
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

/// Cycles' bump shadowing (Conty Estevez et al. 2019, "A Microfacet-Based Shadowing Function
/// to Solve the Bump Terminator Problem"): light `wi` (local) reaching a lobe of a bumped
/// frame whose smooth normal is `ns` (local). Zero when `wi` lies on the other side of the
/// smooth surface than of the bumped one; for diffuse lobes, also the GGX shadowing G1 of a
/// roughness that grows with the bump's tilt.
#[inline]
fn bump_shadowing(ns: Vec3, alpha2: f32, wi: Vec3, diffuse: bool) -> f32 {
    let cos_nsi = ns.dot(wi);
    if cos_nsi * ns.z * wi.z < 0.0 {
        return 0.0;
    }
    if !diffuse {
        return 1.0;
    }
    let cos_i = cos_nsi.abs();
    if ns.z.abs() >= 1.0 || cos_i >= 1.0 {
        return 1.0;
    }
    if cos_i < 1e-6 {
        return 0.0;
    }
    let tan2_i = (1.0 - cos_i * cos_i) / (cos_i * cos_i);
    2.0 / (1.0 + (1.0 + alpha2 * tan2_i).sqrt())
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

    /// Gives the non-diffuse lobes the normal `n` (world space) in place of the frame's, as
    /// Cycles gives its glossy, glass and Principled specular closures a normal bent towards
    /// the geometric one where the bumped normal would reflect the view below the surface
    /// ([`super::graph::geometry_nodes::ensure_valid_reflection`]); diffuse lobes keep the frame's.
    pub fn set_specular_normal(&mut self, n: Vec3, dpdu: Vec3) {
        if !n.is_finite() || n == self.frame.n {
            self.spec = None;
            return;
        }
        self.spec = Some(self.rotation_to(n, dpdu));
    }

    /// The rotation from the frame's local space to that of a frame with normal `n`.
    fn rotation_to(&self, n: Vec3, dpdu: Vec3) -> Mat3 {
        let f = Frame::from_normal_tangent(n, dpdu);
        let col = |v: Vec3| f.to_local(self.frame.to_world(v));
        Mat3::from_cols(col(Vec3::X), col(Vec3::Y), col(Vec3::Z))
    }

    /// Gives the coat (its reflection lobe, marked by [`Bsdf::add_coat_lobe`], and the
    /// layering of the lobes under it) the normal `n` (world space), as the Principled
    /// BSDF's Coat Normal does; the frame's normal when they are equal.
    pub fn set_coat_normal(&mut self, n: Vec3, dpdu: Vec3) {
        self.coat_n = (n.is_finite() && n != self.frame.n).then(|| self.rotation_to(n, dpdu));
    }

    /// Adds the coat's reflection lobe (see [`Bsdf::set_coat_normal`]).
    pub fn add_coat_lobe(&mut self, weight: f32, lobe: Lobe) -> bool {
        let added = self.add(weight, lobe);
        if added {
            self.in_coat_frame[self.count - 1] = true;
        }
        added
    }

    /// The rotation into lobe `i`'s local space, if it has one.
    #[inline]
    fn rot(&self, i: usize) -> Option<&Mat3> {
        if self.in_coat_frame[i] && self.coat_n.is_some() {
            return self.coat_n.as_ref();
        }
        match &self.spec {
            Some(r) if self.lobes[i].flags() & LobeFlags::DIFFUSE == 0 => Some(r),
            _ => None,
        }
    }

    /// The cosine of the view `wo` (local) with the coat's normal.
    #[inline]
    fn coat_cos(&self, wo: Vec3) -> f32 {
        match self.coat_n.as_ref().or(self.spec.as_ref()) {
            Some(r) => (*r * wo).z.abs(),
            None => wo.z.abs(),
        }
    }

    /// Lobe `l` as it is seen from `wo` (local): a diffuse base layered under a specular
    /// layer with a normal of its own takes the layer's albedo at that normal's cosine, as
    /// Cycles layers it.
    #[inline]
    fn view_lobe(&self, l: &Lobe, wo: Vec3) -> Lobe {
        match (&self.spec, l) {
            (Some(r), Lobe::CoatedDiffuse(c)) => {
                let mut c = *c;
                c.pin_view(wo.z.abs(), (*r * wo).z.abs());
                Lobe::CoatedDiffuse(c)
            }
            _ => *l,
        }
    }

    /// Lobe `i`'s albedo estimate towards `wo` (local).
    #[inline]
    fn lobe_albedo(&self, i: usize, wo: Vec3, mask: u8) -> Spectrum {
        let l = &self.lobes[i];
        if self.spec.is_none() && self.coat_n.is_none() {
            return l.albedo(wo, mask);
        }
        self.view_lobe(l, wo).albedo(self.in_lobe(i, wo), mask)
    }

    /// `v` (local) in the local space of lobe `i`.
    #[inline]
    fn in_lobe(&self, i: usize, v: Vec3) -> Vec3 {
        self.rot(i).map_or(v, |r| *r * v)
    }

    /// Lobe `l`'s f at local `wo`, `wi`, scaled for what the caller multiplies it by
    /// ([`CosineOf`]) so that the product carries the lobe's own cosine.
    #[inline]
    fn lobe_eval(&self, i: usize, wo: Vec3, wi: Vec3, mask: u8, cosine: CosineOf) -> Spectrum {
        let l = &self.lobes[i];
        if self.spec.is_none()
            && self.coat_n.is_none()
            && (self.bump.is_none() || cosine != CosineOf::Flux)
        {
            return l.eval(wo, wi, mask);
        }
        let (wo_l, wi_l) = match self.rot(i) {
            Some(r) => (*r * wo, *r * wi),
            None => (wo, wi),
        };
        let f = self.view_lobe(l, wo).eval(wo_l, wi_l, mask);
        match cosine {
            CosineOf::Wi if wi_l != wi => f * (wi_l.z.abs() / wi.z.abs()),
            CosineOf::Flux => match self.bump {
                Some((ns, _, _)) => {
                    let c = ns.dot(wi).abs();
                    if c > 0.0 {
                        f * (wi_l.z.abs() / c)
                    } else {
                        Spectrum::ZERO
                    }
                }
                None => f * (wi_l.z.abs() / wi.z.abs()),
            },
            _ => f,
        }
    }

    /// Marks the frame as bumped away from the surface's smooth normal `smooth` (world space):
    /// photons' flux is read against it, and with `shadow` light is shadowed as Cycles shadows
    /// bump-mapped closures ([`bump_shadowing`]; Cycles does not shadow a displacement's bump).
    pub fn set_bump_shadowing(&mut self, smooth: Vec3, shadow: bool) {
        let ns = self.frame.to_local(smooth);
        let cos_d = ns.z.abs();
        if !(cos_d < 1.0) || !ns.is_finite() {
            self.bump = None;
            return;
        }
        let tan2_d = 1.0 / (cos_d * cos_d) - 1.0;
        self.bump = Some((ns, (0.125 * tan2_d).clamp(0.0, 1.0), shadow));
    }

    /// Puts `coat` over every lobe added so far (the coat's own reflection is added after, as
    /// an ordinary lobe): each is weighted by what the coat lets through towards the viewer.
    pub fn coat_over(&mut self, coat: CoatLayer) {
        self.coat = Some(coat);
        for c in self.coated[..self.count].iter_mut() {
            *c = true;
        }
    }

    /// The weight of lobe `i` for the view direction `wo` (local): its own, times the coat's
    /// attenuation when it lies under the coat.
    #[inline]
    fn weight_at(&self, i: usize, wo: Vec3) -> Spectrum {
        let w = Spectrum::splat(self.weights[i]);
        match &self.coat {
            Some(c) if self.coated[i] => w * c.under(self.coat_cos(wo)),
            _ => w,
        }
    }

    /// The (index, weight for the view `wo`, lobe) triples, `wo` local.
    fn lobes_at(&self, wo: Vec3) -> impl Iterator<Item = (usize, Spectrum, &Lobe)> {
        (0..self.count).map(move |i| (i, self.weight_at(i, wo), &self.lobes[i]))
    }

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

    fn eval_sel(&self, wo: Vec3, wi: Vec3, sel: Selection) -> Spectrum {
        self.eval_mode(wo, wi, sel, CosineOf::Wi)
    }

    /// f of the selected lobes; `cosine`: see [`Bsdf::lobe_eval`].
    fn eval_mode(&self, wo: Vec3, wi: Vec3, sel: Selection, cosine: CosineOf) -> Spectrum {
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

    fn pdf_sel(&self, wo: Vec3, wi: Vec3, sel: Selection) -> f32 {
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

    fn sample_sel(&self, wo: Vec3, u_lobe: f32, u: Vec2, sel: Selection) -> Option<BsdfSample> {
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

#[inline]
pub(crate) fn mean(c: Spectrum) -> f32 {
    (c.x + c.y + c.z) * (1.0 / 3.0)
}
