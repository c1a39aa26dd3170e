//! The lobes' own normals (a specular or coat normal apart from the frame's), bump
//! shadowing, and the coat's layering over the lobes under it.

use super::{Bsdf, LobeFlags};
use crate::materials::layer::CoatLayer;
use crate::materials::lobe::Lobe;
use crate::math::{Frame, Spectrum};
use glam::{Mat3, Vec3};

/// Which direction's cosine a caller multiplies f by (see [`Bsdf::set_specular_normal`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum CosineOf {
    Wi,
    /// None: a photon's flux carries the cosine of the surface it landed on, the smooth
    /// surface's under a bump (the frame's without one).
    Flux,
}

/// Cycles' bump shadowing (Conty Estevez et al. 2019, "A Microfacet-Based Shadowing Function
/// to Solve the Bump Terminator Problem"): light `wi` (local) reaching a lobe of a bumped
/// frame whose smooth normal is `ns` (local). Zero when `wi` lies on the other side of the
/// smooth surface than of the bumped one; for diffuse lobes, also the GGX shadowing G1 of a
/// roughness that grows with the bump's tilt.
#[inline]
pub(super) fn bump_shadowing(ns: Vec3, alpha2: f32, wi: Vec3, diffuse: bool) -> f32 {
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
    /// Gives the non-diffuse lobes the normal `n` (world space) in place of the frame's, as
    /// Cycles gives its glossy, glass and Principled specular closures a normal bent towards
    /// the geometric one where the bumped normal would reflect the view below the surface
    /// ([`crate::materials::graph::geometry_nodes::ensure_valid_reflection`]); diffuse lobes
    /// keep the frame's.
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
    pub(super) fn rot(&self, i: usize) -> Option<&Mat3> {
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
    pub(super) fn view_lobe(&self, l: &Lobe, wo: Vec3) -> Lobe {
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
    pub(super) fn lobe_albedo(&self, i: usize, wo: Vec3, mask: u8) -> Spectrum {
        let l = &self.lobes[i];
        if self.spec.is_none() && self.coat_n.is_none() {
            return l.albedo(wo, mask);
        }
        self.view_lobe(l, wo).albedo(self.in_lobe(i, wo), mask)
    }

    /// `v` (local) in the local space of lobe `i`.
    #[inline]
    pub(super) fn in_lobe(&self, i: usize, v: Vec3) -> Vec3 {
        self.rot(i).map_or(v, |r| *r * v)
    }

    /// Lobe `l`'s f at local `wo`, `wi`, scaled for what the caller multiplies it by
    /// ([`CosineOf`]) so that the product carries the lobe's own cosine.
    #[inline]
    pub(super) fn lobe_eval(
        &self,
        i: usize,
        wo: Vec3,
        wi: Vec3,
        mask: u8,
        cosine: CosineOf,
    ) -> Spectrum {
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
    pub(super) fn weight_at(&self, i: usize, wo: Vec3) -> Spectrum {
        let w = Spectrum::splat(self.weights[i]);
        match &self.coat {
            Some(c) if self.coated[i] => w * c.under(self.coat_cos(wo)),
            _ => w,
        }
    }

    /// The (index, weight for the view `wo`, lobe) triples, `wo` local.
    pub(super) fn lobes_at(&self, wo: Vec3) -> impl Iterator<Item = (usize, Spectrum, &Lobe)> {
        (0..self.count).map(move |i| (i, self.weight_at(i, wo), &self.lobes[i]))
    }
}
