//! Photon emission (Jensen 2001, §5.1): a ray leaving a light, with the flux it carries.
//!
//! Each light kind has its own sampling: point lights a direction uniformly over the sphere
//! (spots over their cone), then, with a radius, an origin on the emitter's disk across that
//! direction (`point.rs`); area and emissive surfaces a uniform point and a cosine-weighted
//! direction (a uniform cone for an area light's narrower spread); distant and environment
//! lights through a disk covering the scene. `sample_le_towards` aims
//! the same emission at bounding spheres of specular objects, for the caustic map (§5.1.4,
//! "projection maps"), with the density of every overlapping target accounted for, so the
//! estimate stays unbiased for every path whose first hit is inside a target.

use super::point::soft_disk_min_travel;
use super::{Light, LightCtx, PointLight};
use crate::math::{Frame, Spectrum, PI};
use crate::sampling::warp;
use glam::{Vec2, Vec3};

/// A photon leaving a light: origin, unit direction, and flux weight Le |cos| / (pdf_pos pdf_dir).
#[derive(Clone, Copy, Debug)]
pub struct LeSample {
    pub o: Vec3,
    pub d: Vec3,
    pub weight: Spectrum,
    /// The photon counts only if its first interaction is at least this far from `o` (the
    /// soft-falloff disk, `point::soft_disk_min_travel`); 0 for every other light.
    pub min_travel: f32,
}

/// A sphere bounding a specular object.
#[derive(Clone, Copy, Debug)]
pub struct Target {
    pub center: Vec3,
    pub radius: f32,
}

/// A point on a finite light: position, emission normal (zero for a point), area density,
/// and whether both faces emit.
struct LightPoint {
    p: Vec3,
    n: Vec3,
    pdf_pos: f32,
    two_sided: bool,
    uv: Vec2,
}

impl Light {
    fn sample_point(&self, u: Vec2) -> Option<LightPoint> {
        match self {
            Light::Area(a) if a.area > 0.0 => {
                let q = match a.shape {
                    super::AreaShape::Rect => 2.0 * u - Vec2::ONE,
                    super::AreaShape::Disk => warp::square_to_uniform_disk_concentric(u),
                };
                let p = a.center + a.ex * q.x + a.ey * q.y;
                Some(LightPoint {
                    p,
                    n: a.n,
                    pdf_pos: 1.0 / a.area,
                    two_sided: a.two_sided,
                    uv: Vec2::ZERO,
                })
            }
            Light::Triangle(t) if t.area > 0.0 => {
                let (b1, b2) = warp::square_to_uniform_triangle(u);
                let b0 = 1.0 - b1 - b2;
                let p = t.v[0] * b0 + t.v[1] * b1 + t.v[2] * b2;
                let uv = t.uv[0] * b0 + t.uv[1] * b1 + t.uv[2] * b2;
                Some(LightPoint {
                    p,
                    n: t.n,
                    pdf_pos: 1.0 / t.area,
                    two_sided: true,
                    uv,
                })
            }
            _ => None,
        }
    }

    /// Radiance leaving the surface point `lp` along `d`, times |cos| to the normal.
    fn emitted_cos(&self, lp: &LightPoint, d: Vec3, ctx: &LightCtx) -> Spectrum {
        let cos = d.dot(lp.n);
        if cos <= 0.0 && !(lp.two_sided && cos < 0.0) {
            return Spectrum::ZERO;
        }
        match self {
            Light::Area(a) => a.emitted(cos) * cos.abs(),
            Light::Triangle(t) => t.emission(lp.p, lp.uv, ctx) * cos.abs(),
            _ => Spectrum::ZERO,
        }
    }

    /// A photon of a point, spot or sphere light leaving along `d`, drawn with density
    /// `pdf_dir`: from the centre, or with a radius from a uniform point `u_pos` of the disk
    /// across `d` (on the sphere, or through the centre for the soft-falloff disk).
    fn point_photon(l: &PointLight, d: Vec3, pdf_dir: f32, u_pos: Vec2) -> Option<LeSample> {
        if !(pdf_dir > 0.0) {
            return None;
        }
        let weight = l.intensity * (l.spot_att(d) / pdf_dir);
        let r = l.radius;
        if r == 0.0 {
            return Some(LeSample {
                o: l.position,
                d,
                weight,
                min_travel: 0.0,
            });
        }
        let q = warp::square_to_uniform_disk_concentric(u_pos) * r;
        let frame = Frame::from_normal(d);
        let across = frame.s * q.x + frame.t * q.y;
        let h2 = q.length_squared();
        Some(if l.soft_falloff {
            LeSample {
                o: l.position + across,
                d,
                weight,
                min_travel: soft_disk_min_travel(h2.sqrt(), r),
            }
        } else {
            LeSample {
                o: l.position + across - d * (r * r - h2).max(0.0).sqrt(),
                d,
                weight,
                min_travel: 0.0,
            }
        })
    }

    /// A photon from this light, over its whole emission.
    pub fn sample_le(&self, u_pos: Vec2, u_dir: Vec2, ctx: &LightCtx) -> Option<LeSample> {
        match self {
            Light::Distant(_) | Light::Environment(_) => {
                let target = Target {
                    center: ctx.scene_center,
                    radius: ctx.scene_radius,
                };
                self.sample_infinite(u_pos, u_dir, &[target], 0.5, ctx)
            }
            Light::Point(l) => {
                let (d, pdf_dir) = match l.spot {
                    Some(s) => (
                        Frame::from_normal(s.axis)
                            .to_world(warp::square_to_uniform_cone(u_dir, s.cos_half)),
                        warp::uniform_cone_pdf(s.cos_half),
                    ),
                    None => (
                        warp::square_to_uniform_sphere(u_dir),
                        warp::UNIFORM_SPHERE_PDF,
                    ),
                };
                Self::point_photon(l, d, pdf_dir, u_pos)
            }
            _ => {
                let lp = self.sample_point(u_pos)?;
                // Cosine-weighted about the normal (a uniform cone over a narrower spread);
                // a two-sided emitter picks a face.
                let (mut u, mut n, mut side_pdf) = (u_dir, lp.n, 1.0);
                if lp.two_sided {
                    side_pdf = 0.5;
                    if u.x < 0.5 {
                        u.x *= 2.0;
                    } else {
                        u.x = (u.x - 0.5) * 2.0;
                        n = -n;
                    }
                }
                let half = match self {
                    Light::Area(a) => a.spread.half_angle(),
                    _ => 0.5 * PI,
                };
                let (local, pdf) = if half < 0.5 * PI {
                    let cos_max = half.cos();
                    (
                        warp::square_to_uniform_cone(u, cos_max),
                        warp::uniform_cone_pdf(cos_max),
                    )
                } else {
                    let local = warp::square_to_cosine_hemisphere(u);
                    (local, warp::cosine_hemisphere_pdf(local))
                };
                let d = Frame::from_normal(n).to_world(local);
                let pdf_dir = side_pdf * pdf;
                if !(pdf_dir > 0.0) {
                    return None;
                }
                let weight = self.emitted_cos(&lp, d, ctx) / (lp.pdf_pos * pdf_dir);
                Some(LeSample {
                    o: lp.p,
                    d,
                    weight,
                    min_travel: 0.0,
                })
            }
        }
    }

    /// A photon aimed at the targets: the target is chosen with `u_sel` in proportion to its
    /// solid angle (finite lights) or cross-section (lights at infinity).
    pub fn sample_le_towards(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        u_sel: f32,
        targets: &[Target],
        ctx: &LightCtx,
    ) -> Option<LeSample> {
        if targets.is_empty() {
            return None;
        }
        if matches!(self, Light::Distant(_) | Light::Environment(_)) {
            return self.sample_infinite(u_pos, u_dir, targets, u_sel, ctx);
        }
        // Cones from the light point (a point light's centre) towards each target, widened by
        // a point light's radius: a photon line of direction d passing within r of the centre
        // can reach the target only if d is within asin((R + r) / D) of it. A light point
        // inside a target sees it over the whole sphere.
        let (origin, widen, lp) = match self {
            Light::Point(l) => (l.position, l.radius, None),
            _ => {
                let lp = self.sample_point(u_pos)?;
                (lp.p, 0.0, Some(lp))
            }
        };
        let cones: Vec<(Vec3, f32, f32)> = targets
            .iter()
            .map(|t| {
                let to = t.center - origin;
                let d2 = to.length_squared();
                let r2 = (t.radius + widen) * (t.radius + widen);
                if d2 <= r2 * 1.0001 {
                    (Vec3::Z, -1.0, 4.0 * PI)
                } else {
                    let cos_max = (1.0 - r2 / d2).max(0.0).sqrt();
                    (to / d2.sqrt(), cos_max, 2.0 * PI * (1.0 - cos_max))
                }
            })
            .collect();
        let total: f32 = cones.iter().map(|c| c.2).sum();
        if !(total > 0.0) {
            return None;
        }
        let mut acc = 0.0;
        let mut chosen = cones.len() - 1;
        for (i, c) in cones.iter().enumerate() {
            acc += c.2 / total;
            if u_sel < acc {
                chosen = i;
                break;
            }
        }
        let (axis, cos_max, _) = cones[chosen];
        let d = Frame::from_normal(axis).to_world(warp::square_to_uniform_cone(u_dir, cos_max));
        // Mixture density over every cone containing d.
        let pdf_dir: f32 = cones
            .iter()
            .filter(|c| c.1 <= -1.0 || d.dot(c.0) >= c.1)
            .map(|c| {
                (c.2 / total)
                    * if c.1 <= -1.0 {
                        warp::UNIFORM_SPHERE_PDF
                    } else {
                        warp::uniform_cone_pdf(c.1)
                    }
            })
            .sum();
        let Some(lp) = lp else {
            let Light::Point(l) = self else { return None };
            return Self::point_photon(l, d, pdf_dir, u_pos);
        };
        if !(pdf_dir > 0.0) {
            return None;
        }
        let weight = self.emitted_cos(&lp, d, ctx) / (lp.pdf_pos * pdf_dir);
        Some(LeSample {
            o: lp.p,
            d,
            weight,
            min_travel: 0.0,
        })
    }

    /// Distant and environment lights: a direction, then a point on a disk perpendicular to it
    /// covering one of the targets (chosen by cross-section), placed upstream of the scene.
    fn sample_infinite(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        targets: &[Target],
        u_sel: f32,
        ctx: &LightCtx,
    ) -> Option<LeSample> {
        let (d, radiance_over_pdf) = match self {
            Light::Distant(l) => {
                let s = l.sample_li(u_dir)?;
                (-s.wi, s.li / s.pdf)
            }
            Light::Environment(l) => {
                let s = l.sample_li(u_dir)?;
                (-s.wi, s.li / s.pdf)
            }
            _ => return None,
        };
        let total: f32 = targets.iter().map(|t| t.radius * t.radius).sum();
        if !(total > 0.0) {
            return None;
        }
        let mut acc = 0.0;
        let mut chosen = targets.len() - 1;
        for (i, t) in targets.iter().enumerate() {
            acc += t.radius * t.radius / total;
            if u_sel < acc {
                chosen = i;
                break;
            }
        }
        let t = targets[chosen];
        let frame = Frame::from_normal(d);
        let q = warp::square_to_uniform_disk_concentric(u_pos) * t.radius;
        let on_disk = t.center + frame.s * q.x + frame.t * q.y;
        // Density over the plane: every target disk containing the point contributes.
        let pdf_pos: f32 = targets
            .iter()
            .filter(|o| {
                let rel = on_disk - o.center;
                (rel - d * rel.dot(d)).length_squared() <= o.radius * o.radius * 1.0001
            })
            .map(|o| (o.radius * o.radius / total) / (PI * o.radius * o.radius))
            .sum();
        if !(pdf_pos > 0.0) {
            return None;
        }
        let back = 2.0 * ctx.scene_radius + (t.center - ctx.scene_center).length() + t.radius;
        Some(LeSample {
            o: on_disk - d * back,
            d,
            weight: radiance_over_pdf / pdf_pos,
            min_travel: 0.0,
        })
    }
}
