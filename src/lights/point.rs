//! Point, spot and sphere lights: one emitter at a position, with an optional radius and an
//! optional spot cone, drawn as Cycles draws them.
//!
//! | parameter | meaning |
//! |---|---|
//! | `position` | centre |
//! | `power` P (W) x `color` | intensity I = P/(4 pi); with a radius r > 0 the emitter has radiance L = P/(4 pi^2 r^2) |
//! | `radius` | emitter radius (soft shadows), 0 for a true point |
//! | `soft_falloff` | Blender's "Soft Falloff" (on by default): the emitter is a disk of radius r facing the shading point, so irradiance falls as 1/(d^2 + r^2) near the light; off: a sphere of radius r, exactly 1/d^2 outside it |
//! | spot `cone_angle`, `blend` | full cone angle; Cycles' smoothstep falloff over `blend` of the cone |
//!
//! The spot attenuation is taken along the direction the light travels, from the point on the
//! emitter to the receiver (Cycles' `spot_light_attenuation(-D)`), so the cone stays sharp for
//! any radius. Seen from a ray, the emitter is the sphere (or the disk facing the ray's origin)
//! with radiance L times that attenuation; it never occludes anything.
//!
//! Photons (`emit.rs`) pick a direction w first (uniform over the sphere or the spot's cone),
//! then an origin uniformly on the disk of radius r through the centre perpendicular to w
//! (moved back onto the sphere for a sphere emitter): for points outside the emitter these
//! rays are exactly the sphere's light field. For the soft-falloff disk a photon whose origin
//! is at h from the centre counts only where it first lands at least h^2/sqrt(r^2 - h^2) from
//! its origin: there, and only there, the disk facing the landing point contains the photon's
//! line (`soft_disk_min_travel`).

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

    /// Attenuation for light travelling along `w` (unit, away from the light), as Cycles' spot.
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
        // Full cone plus the smoothstep band: in cos units the band integrates to smooth / 2.
        let inner = (self.cos_half + self.smooth).min(1.0);
        let band = 0.5 * (inner - self.cos_half);
        2.0 * PI * ((1.0 - inner) + band)
    }
}

#[derive(Clone, Debug)]
pub struct PointLight {
    pub position: Vec3,
    pub radius: f32,
    /// Intensity P/(4 pi) x colour (W/sr).
    pub intensity: Spectrum,
    pub spot: Option<SpotShape>,
    /// The emitter is a disk facing the shading point (Blender's soft falloff), not a sphere.
    pub soft_falloff: bool,
}

impl PointLight {
    pub fn new(
        position: Vec3,
        power: f32,
        color: Spectrum,
        radius: f32,
        spot: Option<SpotShape>,
        soft_falloff: bool,
    ) -> Self {
        PointLight {
            position,
            radius,
            intensity: color * (power / (4.0 * PI)),
            spot,
            soft_falloff,
        }
    }

    /// Emitter radiance; intensity = radiance x pi r^2.
    pub fn radiance(&self) -> Spectrum {
        self.intensity / (PI * self.radius * self.radius)
    }

    /// Spot attenuation of light travelling along `w` (unit).
    pub fn spot_att(&self, w: Vec3) -> f32 {
        self.spot.map_or(1.0, |s| s.attenuation(w))
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
        if self.soft_falloff {
            // A uniform point on the disk facing p.
            let frame = Frame::from_normal(-wc);
            let q = warp::square_to_uniform_disk_concentric(u) * r;
            let pl = self.position + frame.s * q.x + frame.t * q.y;
            let to_l = pl - p;
            let t2 = to_l.length_squared();
            if !(t2 > 0.0) {
                return None;
            }
            let t = t2.sqrt();
            let wi = to_l / t;
            let n = -wc;
            let pdf = warp::area_to_solid_angle(1.0 / (PI * r * r), t2, wi.dot(n));
            return Some(LightSample {
                wi,
                li: self.radiance() * self.spot_att(-wi),
                pdf,
                dist: t,
                p: pl,
                n,
                delta: false,
            });
        }
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
        Some(LightSample {
            wi,
            li: self.radiance() * self.spot_att(-wi),
            pdf: warp::uniform_cone_pdf(cos_max),
            dist: t,
            p: pl,
            n,
            delta: false,
        })
    }

    /// Solid-angle density of `sample_li` at `p` for the point `p_light` on the emitter.
    pub fn pdf_li(&self, p: Vec3, p_light: Vec3) -> f32 {
        if self.radius == 0.0 {
            return 0.0;
        }
        let d2 = (self.position - p).length_squared();
        let r2 = self.radius * self.radius;
        if self.soft_falloff {
            if !(d2 > 0.0) {
                return 0.0;
            }
            let n = (p - self.position) / d2.sqrt();
            let to = p_light - p;
            let t2 = to.length_squared();
            if !(t2 > 0.0) {
                return 0.0;
            }
            return warp::area_to_solid_angle(1.0 / (PI * r2), t2, (to / t2.sqrt()).dot(n));
        }
        if d2 <= r2 {
            return 0.0;
        }
        let cos_max = (1.0 - r2 / d2).max(0.0).sqrt();
        warp::uniform_cone_pdf(cos_max)
    }

    /// Radiance leaving the emitter towards the origin of a ray of direction `d` (unit or
    /// not) that reached it: the light travels along -d, and the spot cone is taken along it.
    pub fn le(&self, d: Vec3) -> Spectrum {
        self.radiance() * self.spot_att(-d.normalize_or_zero())
    }

    /// Ray distance to the emitter as the ray's origin sees it (the sphere from outside, or
    /// the disk facing the origin), and the emitter's normal there; None without a radius.
    pub fn intersect(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<(f32, Vec3)> {
        if self.radius == 0.0 {
            return None;
        }
        let oc = o - self.position;
        let d2 = oc.length_squared();
        if self.soft_falloff {
            if !(d2 > 0.0) {
                return None;
            }
            let n = oc / d2.sqrt();
            let denom = d.dot(n);
            if !(denom < 0.0) {
                return None;
            }
            let t = -oc.dot(n) / denom;
            let q = oc + d * t;
            return (t > 0.0 && t < t_max && q.length_squared() <= self.radius * self.radius)
                .then_some((t, n));
        }
        if d2 <= self.radius * self.radius {
            return None; // from inside, the sphere is not seen (it emits outwards)
        }
        let t = sphere_hit(self.position, self.radius, o, d, t_max)?;
        Some((t, (o + d * t - self.position) / self.radius))
    }

    /// Emitted power over all directions (for soft falloff the nominal power: the disk model
    /// delivers a little less near the light).
    pub fn power(&self) -> Spectrum {
        let solid = self.spot.map_or(4.0 * PI, |s| s.solid_angle());
        self.intensity * solid
    }
}

/// For a soft-falloff photon leaving the disk through the centre at distance `h` from it
/// (disk radius `r`): the distance it must travel before a surface it reaches sees its line
/// inside the disk facing that surface (h^2 (d^2 + r^2) <= r^2 d^2 with d^2 = h^2 + t^2).
pub fn soft_disk_min_travel(h: f32, r: f32) -> f32 {
    let rest = r * r - h * h;
    if rest <= 0.0 {
        f32::INFINITY
    } else {
        h * h / rest.sqrt()
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
