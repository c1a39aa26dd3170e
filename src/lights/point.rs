//! Point, spot and sphere lights: one emitter at a position, with an optional radius
//! (a sphere of uniform radiance) and an optional spot cone.
//!
//! | parameter | meaning |
//! |---|---|
//! | `position` | centre |
//! | `power` P (W) x `color` | radius 0: intensity I = P/(4 pi); radius r > 0: radiance P/(4 pi^2 r^2) |
//! | `radius` | sphere radius (soft shadows), 0 for a true point |
//! | spot `cone_angle`, `blend` | full cone angle; Cycles' smoothstep falloff over `blend` of the cone |

use super::LightSample;
use crate::math::{Frame, Spectrum, PI};
use crate::sampling::warp;
use glam::{Vec2, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct SpotShape {
    pub axis: Vec3,
    pub cos_half: f32,
    /// Width of the smoothstep in cosine units.
    pub smooth: f32,
}

impl SpotShape {
    pub fn new(axis: Vec3, cone_angle: f32, blend: f32) -> Self {
        let cos_half = (0.5 * cone_angle).cos();
        SpotShape {
            axis: axis.normalize(),
            cos_half,
            smooth: (1.0 - cos_half) * blend,
        }
    }

    /// Attenuation for light leaving along `w` (unit, away from the light), as Cycles' spot.
    pub fn attenuation(&self, w: Vec3) -> f32 {
        let t = w.dot(self.axis);
        if t <= self.cos_half {
            return 0.0;
        }
        if self.smooth > 0.0 && t - self.cos_half < self.smooth {
            let x = (t - self.cos_half) / self.smooth;
            return x * x * (3.0 - 2.0 * x);
        }
        1.0
    }

    /// Exact integral of the attenuation over the sphere of directions (for the power).
    pub fn solid_angle(&self) -> f32 {
        // Full cone plus the smoothstep band; integrate the band numerically in cos.
        let inner = self.cos_half + self.smooth;
        let mut band = 0.0;
        let n = 256;
        if self.smooth > 0.0 {
            for i in 0..n {
                let x = (i as f32 + 0.5) / n as f32;
                band += x * x * (3.0 - 2.0 * x);
            }
            band *= self.smooth / n as f32;
        }
        2.0 * PI * ((1.0 - inner.min(1.0)) + band)
    }
}

#[derive(Clone, Debug)]
pub struct PointLight {
    pub position: Vec3,
    pub radius: f32,
    /// Intensity P/(4 pi) x colour (W/sr).
    pub intensity: Spectrum,
    pub spot: Option<SpotShape>,
}

impl PointLight {
    pub fn new(
        position: Vec3,
        power: f32,
        color: Spectrum,
        radius: f32,
        spot: Option<SpotShape>,
    ) -> Self {
        PointLight {
            position,
            radius,
            intensity: color * (power / (4.0 * PI)),
            spot,
        }
    }

    /// Sphere radiance; intensity = radiance x pi r^2.
    pub fn radiance(&self) -> Spectrum {
        self.intensity / (PI * self.radius * self.radius)
    }

    fn spot_att(&self, from_light: Vec3) -> f32 {
        self.spot.map_or(1.0, |s| s.attenuation(from_light))
    }

    pub fn sample_li(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        let to = self.position - p;
        let d2 = to.length_squared();
        if !(d2 > 0.0) {
            return None;
        }
        let dist = d2.sqrt();
        let wc = to / dist;
        if self.radius == 0.0 {
            let att = self.spot_att(-wc);
            return Some(LightSample {
                wi: wc,
                li: self.intensity * (att / d2),
                pdf: 1.0,
                dist,
                p: self.position,
                n: Vec3::ZERO,
                delta: true,
            });
        }
        let r = self.radius;
        if dist <= r * 1.0001 {
            return None; // inside the sphere light: no defined direction
        }
        // Uniform cone over the visible cap (pbrt-v4 Sphere::Sample by solid angle).
        let sin2_max = (r * r / d2).min(1.0);
        let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
        let local = warp::square_to_uniform_cone(u, cos_max);
        let wi = Frame::from_normal(wc).to_world(local);
        // Distance along wi to the sphere surface (near root).
        let b = wi.dot(to);
        let disc = (b * b - (d2 - r * r)).max(0.0);
        let t = (b - disc.sqrt()).max(0.0);
        let pl = p + wi * t;
        let n = (pl - self.position) / r;
        let att = self.spot_att((pl - self.position).normalize());
        Some(LightSample {
            wi,
            li: self.radiance() * att,
            pdf: warp::uniform_cone_pdf(cos_max),
            dist: t,
            p: pl,
            n,
            delta: false,
        })
    }

    pub fn pdf_li(&self, p: Vec3, _wi: Vec3) -> f32 {
        if self.radius == 0.0 {
            return 0.0;
        }
        let d2 = (self.position - p).length_squared();
        let r2 = self.radius * self.radius;
        if d2 <= r2 {
            return 0.0;
        }
        let cos_max = (1.0 - r2 / d2).max(0.0).sqrt();
        warp::uniform_cone_pdf(cos_max)
    }

    /// Radiance leaving the sphere surface at `p_light` towards `-wi`.
    pub fn le(&self, p_light: Vec3) -> Spectrum {
        self.radiance() * self.spot_att((p_light - self.position).normalize_or_zero())
    }

    /// Ray-sphere distance for rays that can see the light, or None.
    pub fn intersect(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
        if self.radius == 0.0 {
            return None;
        }
        sphere_hit(self.position, self.radius, o, d, t_max)
    }

    pub fn power(&self) -> Spectrum {
        let solid = self.spot.map_or(4.0 * PI, |s| s.solid_angle());
        self.intensity * solid
    }
}

/// Nearest positive ray parameter of a sphere hit, for a unit or non-unit direction.
pub(crate) fn sphere_hit(c: Vec3, r: f32, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
    let oc = o - c;
    let a = d.length_squared();
    let half_b = oc.dot(d);
    let cc = oc.length_squared() - r * r;
    let disc = half_b * half_b - a * cc;
    if disc < 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    let t0 = (-half_b - sq) / a;
    let t1 = (-half_b + sq) / a;
    let t = if t0 > 1e-6 * (1.0 + r) { t0 } else { t1 };
    (t > 1e-6 * (1.0 + r) && t < t_max).then_some(t)
}
