//! Rectangle and disk area lights (Blender area lights: square, rectangle, disk, ellipse).
//!
//! | parameter | meaning |
//! |---|---|
//! | `transform` | light-to-world; the light lies in its local XY plane and emits along local -Z |
//! | `width`, `height` / `radius` | size in local units (scaled by the transform) |
//! | `power` P (W) x `color` | radiance L = P / (pi A) with A the world-space area; halved per side when `two_sided` |
//! | `spread` | Blender's Spread, the full angle of the emission cone (pi: the whole hemisphere). Cycles' soft-box grid: L(theta) = L (tan a - tan theta) / (tan a - a) for theta < a = spread/2, which keeps the power P |
//!
//! A disk's two radius vectors may differ: an ellipse. The light is one-sided unless
//! `two_sided`: from behind it is invisible, and it never occludes anything (rays pass
//! through it). Sampled uniformly by area; multiple importance sampling with the BSDF handles
//! the rest.

use super::LightSample;
use crate::math::{Spectrum, PI};
use crate::sampling::warp;
use glam::{Vec2, Vec3};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AreaShape {
    Rect,
    Disk,
}

#[derive(Clone, Debug)]
pub struct AreaLight {
    pub shape: AreaShape,
    pub center: Vec3,
    /// Half-extent (rect) or radius (disk) vectors in world space.
    pub ex: Vec3,
    pub ey: Vec3,
    /// Unit emission normal.
    pub n: Vec3,
    pub area: f32,
    pub radiance: Spectrum,
    pub two_sided: bool,
    pub spread: Spread,
    /// Inverse Gram matrix of (ex, ey), for planar coordinates of a hit point.
    gram_inv: [f32; 4],
}

impl AreaLight {
    pub fn new(
        shape: AreaShape,
        center: Vec3,
        ex: Vec3,
        ey: Vec3,
        n: Vec3,
        power: f32,
        color: Spectrum,
        two_sided: bool,
        spread: f32,
    ) -> Self {
        let cross = ex.cross(ey).length();
        let area = match shape {
            AreaShape::Rect => 4.0 * cross,
            AreaShape::Disk => PI * cross,
        };
        let sides = if two_sided { 2.0 } else { 1.0 };
        let radiance = if area > 0.0 {
            color * (power / (PI * area * sides))
        } else {
            Spectrum::ZERO
        };
        let (a, b, d) = (ex.dot(ex), ex.dot(ey), ey.dot(ey));
        let det = a * d - b * b;
        let gram_inv = if det > 0.0 {
            [d / det, -b / det, -b / det, a / det]
        } else {
            [0.0; 4]
        };
        AreaLight {
            shape,
            center,
            ex,
            ey,
            n: n.normalize(),
            area,
            radiance,
            two_sided,
            spread: Spread::new(spread),
            gram_inv,
        }
    }

    fn point_at(&self, u: Vec2) -> Vec3 {
        let q = match self.shape {
            AreaShape::Rect => 2.0 * u - Vec2::ONE,
            AreaShape::Disk => warp::square_to_uniform_disk_concentric(u),
        };
        self.center + self.ex * q.x + self.ey * q.y
    }

    /// Radiance leaving at cosine `cos_l` to the emission normal (negative: the back face).
    pub fn emitted(&self, cos_l: f32) -> Spectrum {
        if cos_l > 0.0 || (self.two_sided && cos_l < 0.0) {
            self.radiance * self.spread.attenuation(cos_l.abs())
        } else {
            Spectrum::ZERO
        }
    }

    pub fn sample_li(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        let pl = self.point_at(u);
        let to = pl - p;
        let d2 = to.length_squared();
        if !(d2 > 0.0) || self.area <= 0.0 {
            return None;
        }
        let dist = d2.sqrt();
        let wi = to / dist;
        let cos_l = -wi.dot(self.n);
        let li = self.emitted(cos_l);
        Some(LightSample {
            wi,
            li,
            pdf: warp::area_to_solid_angle(1.0 / self.area, d2, cos_l),
            dist,
            p: pl,
            n: self.n,
            delta: false,
        })
    }

    pub fn pdf_li(&self, p: Vec3, p_light: Vec3, n_light: Vec3) -> f32 {
        let to = p_light - p;
        let d2 = to.length_squared();
        if d2 <= 0.0 || self.area <= 0.0 {
            return 0.0;
        }
        let cos_l = -(to / d2.sqrt()).dot(n_light);
        if !self.two_sided && cos_l <= 0.0 {
            return 0.0;
        }
        warp::area_to_solid_angle(1.0 / self.area, d2, cos_l)
    }

    /// Radiance seen along direction `d` hitting the light.
    pub fn le(&self, d: Vec3) -> Spectrum {
        self.emitted(-d.normalize_or_zero().dot(self.n))
    }

    /// Ray parameter of a hit on the light's emitting side (either side when two-sided).
    pub fn intersect(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
        let denom = d.dot(self.n);
        if denom.abs() < 1e-12 || (denom > 0.0 && !self.two_sided) {
            return None;
        }
        let t = (self.center - o).dot(self.n) / denom;
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        let q = o + d * t - self.center;
        let (qx, qy) = (q.dot(self.ex), q.dot(self.ey));
        let g = self.gram_inv;
        let (a, b) = (g[0] * qx + g[1] * qy, g[2] * qx + g[3] * qy);
        let inside = match self.shape {
            AreaShape::Rect => a.abs() <= 1.0 && b.abs() <= 1.0,
            AreaShape::Disk => a * a + b * b <= 1.0,
        };
        inside.then_some(t)
    }

    pub fn power(&self) -> Spectrum {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        self.radiance * (PI * self.area * sides)
    }
}

/// Cycles' area-light spread: a soft-box grid passing the fraction (tan a - tan theta) /
/// (tan a - a) of the light at angle theta to the normal, a the half spread angle. The
/// normalisation keeps the power: the integral of (tan a - tan theta) cos sin over [0, a] is
/// (tan a - a)/2, the Lambertian hemisphere's 1/2 times (tan a - a).
#[derive(Clone, Copy, Debug)]
pub struct Spread {
    /// Half angle a; None for the whole hemisphere (spread pi).
    half: Option<f32>,
    tan_half: f32,
    norm: f32,
}

impl Spread {
    pub fn new(spread: f32) -> Self {
        if !(spread < PI - 1e-6) {
            return Spread {
                half: None,
                tan_half: f32::INFINITY,
                norm: 1.0,
            };
        }
        let a = 0.5 * spread.max(1e-4);
        let tan_half = a.tan();
        // 1 / (tan a - a), by its Taylor series a^3/3 + 2a^5/15 where the difference cancels.
        let diff = if a > 0.05 {
            tan_half - a
        } else {
            a * a * a / 3.0 + 2.0 * a.powi(5) / 15.0
        };
        Spread {
            half: Some(a),
            tan_half,
            norm: 1.0 / diff,
        }
    }

    /// The half angle a of the emission cone (pi/2 for the whole hemisphere).
    pub fn half_angle(&self) -> f32 {
        self.half.unwrap_or(0.5 * PI)
    }

    /// Factor on the radiance leaving at cosine `cos` (> 0) to the normal.
    pub fn attenuation(&self, cos: f32) -> f32 {
        if self.half.is_none() {
            return 1.0;
        }
        if !(cos > 0.0) {
            return 0.0;
        }
        let tan = (1.0 - cos * cos).max(0.0).sqrt() / cos;
        ((self.tan_half - tan) * self.norm).max(0.0)
    }
}
