//! Photon emission (Jensen 2001, §5.1): a ray leaving a light, with the flux it carries.
//!
//! Each light kind has its own sampling: point lights uniformly over the sphere (spots over
//! their cone), area and emissive surfaces at a uniform point with a cosine-weighted direction,
//! distant and environment lights through a disk covering the scene. `sample_le_towards` aims
//! the same emission at bounding spheres of specular objects, for the caustic map (§5.1.4,
//! "projection maps"), with the density of every overlapping target accounted for, so the
//! estimate stays unbiased for every path whose first hit is inside a target.

use super::{Light, LightCtx};
use crate::math::{Frame, Spectrum, PI};
use crate::sampling::warp;
use glam::{Vec2, Vec3};

/// A photon leaving a light: origin, unit direction, and flux weight Le |cos| / (pdf_pos pdf_dir).
#[derive(Clone, Copy, Debug)]
pub struct LeSample {
    pub o: Vec3,
    pub d: Vec3,
    pub weight: Spectrum,
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
            Light::Point(l) if l.radius == 0.0 => Some(LightPoint {
                p: l.position,
                n: Vec3::ZERO,
                pdf_pos: 1.0,
                two_sided: false,
                uv: Vec2::ZERO,
            }),
            Light::Point(l) => {
                let n = warp::square_to_uniform_sphere(u);
                let area = 4.0 * PI * l.radius * l.radius;
                Some(LightPoint {
                    p: l.position + n * l.radius,
                    n,
                    pdf_pos: 1.0 / area,
                    two_sided: false,
                    uv: Vec2::ZERO,
                })
            }
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

    /// Radiance (or intensity, for a point) leaving `lp` along `d`, times |cos| to the normal.
    fn emitted_cos(&self, lp: &LightPoint, d: Vec3, ctx: &LightCtx) -> Spectrum {
        let cos = if lp.n == Vec3::ZERO { 1.0 } else { d.dot(lp.n) };
        if cos <= 0.0 && !(lp.two_sided && cos < 0.0) {
            return Spectrum::ZERO;
        }
        let cos = cos.abs();
        match self {
            Light::Point(l) if l.radius == 0.0 => {
                l.intensity * l.spot.map_or(1.0, |s| s.attenuation(d))
            }
            Light::Point(l) => l.le(lp.p) * cos,
            Light::Area(a) => a.radiance * cos,
            Light::Triangle(t) => t.emission(lp.uv, ctx) * cos,
            _ => Spectrum::ZERO,
        }
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
            _ => {
                let lp = self.sample_point(u_pos)?;
                let (d, pdf_dir) = match self {
                    Light::Point(l) if l.radius == 0.0 => match l.spot {
                        Some(s) => {
                            let d = Frame::from_normal(s.axis)
                                .to_world(warp::square_to_uniform_cone(u_dir, s.cos_half));
                            (d, warp::uniform_cone_pdf(s.cos_half))
                        }
                        None => (
                            warp::square_to_uniform_sphere(u_dir),
                            warp::UNIFORM_SPHERE_PDF,
                        ),
                    },
                    _ => {
                        // Cosine-weighted about the normal; a two-sided emitter picks a face.
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
                        let local = warp::square_to_cosine_hemisphere(u);
                        (
                            Frame::from_normal(n).to_world(local),
                            side_pdf * warp::cosine_hemisphere_pdf(local),
                        )
                    }
                };
                if !(pdf_dir > 0.0) {
                    return None;
                }
                let weight = self.emitted_cos(&lp, d, ctx) / (lp.pdf_pos * pdf_dir);
                Some(LeSample { o: lp.p, d, weight })
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
        let lp = self.sample_point(u_pos)?;
        // Cones towards each target; a light point inside a target sees it over the whole sphere.
        let cones: Vec<(Vec3, f32, f32)> = targets
            .iter()
            .map(|t| {
                let to = t.center - lp.p;
                let d2 = to.length_squared();
                let r2 = t.radius * t.radius;
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
        if !(pdf_dir > 0.0) {
            return None;
        }
        let weight = self.emitted_cos(&lp, d, ctx) / (lp.pdf_pos * pdf_dir);
        Some(LeSample { o: lp.p, d, weight })
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
        })
    }
}
