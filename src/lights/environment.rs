//! Environment light: a constant colour, or a lat-long image importance-sampled by luminance
//! (pbrt-v4 §12.5.2).
//!
//! | parameter | meaning |
//! |---|---|
//! | `color` x `strength` | radiance scale |
//! | `texture` | lat-long image; direction d (local, +Z up) maps to u = 0.5 - atan2(d.y, d.x)/2pi, v = 0.5 + asin(d.z)/pi; negative texels count as 0 (as in material colours) |
//! | `transform` | environment-to-world |

use super::LightSample;
use crate::materials::texture::Texture;
use crate::math::{luminance, Frame, Spectrum, Transform, INV_4PI, INV_PI, PI};
use crate::sampling::{warp, Distribution2D};
use glam::{Vec2, Vec3};

#[derive(Clone, Debug)]
pub struct EnvironmentLight {
    pub scale: Spectrum,
    pub image: Option<(Texture, Distribution2D)>,
    pub to_world: Transform,
}

/// Lat-long (u, v) of a local direction.
pub fn dir_to_uv(d: Vec3) -> Vec2 {
    let u = 0.5 - d.y.atan2(d.x) * (0.5 / PI);
    let v = 0.5 + d.z.clamp(-1.0, 1.0).asin() / PI;
    Vec2::new(u.rem_euclid(1.0), v)
}

/// Local direction of lat-long (u, v).
pub fn uv_to_dir(uv: Vec2) -> Vec3 {
    let phi = 2.0 * PI * (0.5 - uv.x);
    let lat = PI * (uv.y - 0.5);
    Vec3::new(phi.cos() * lat.cos(), phi.sin() * lat.cos(), lat.sin())
}

/// The image's radiance at `uv`: negative texels are clamped to 0 (a negative radiance would
/// give negative pixels and a negative sampling weight).
fn texel(tex: &Texture, uv: Vec2) -> Spectrum {
    tex.eval_rgb(uv).max(Vec3::ZERO)
}

impl EnvironmentLight {
    pub fn new(scale: Spectrum, texture: Option<Texture>, to_world: Transform) -> Self {
        let image = texture.map(|tex| {
            // Distribution over (u, v) with v = 0 at the bottom; weight by cos(latitude).
            let (w, h) = (tex.width().max(1), tex.height().max(1));
            let (w, h) = (w.min(1024), h.min(512));
            let mut f = vec![0.0f32; w * h];
            for j in 0..h {
                let v = (j as f32 + 0.5) / h as f32;
                let cos_lat = (PI * (v - 0.5)).cos();
                for i in 0..w {
                    let u = (i as f32 + 0.5) / w as f32;
                    f[j * w + i] = (luminance(texel(&tex, Vec2::new(u, v))) + 1e-6) * cos_lat;
                }
            }
            let dist = Distribution2D::new(&f, w, h);
            (tex, dist)
        });
        EnvironmentLight {
            scale,
            image,
            to_world,
        }
    }

    /// Radiance arriving from world direction `d` (pointing away from the scene).
    pub fn le(&self, d: Vec3) -> Spectrum {
        match &self.image {
            None => self.scale,
            Some((tex, _)) => {
                let local = self.to_world.inv_vector(d).normalize_or_zero();
                self.scale * texel(tex, dir_to_uv(local))
            }
        }
    }

    /// A direction towards the environment: uniform over the sphere for photon emission and
    /// points in a medium, see [`sample_li_about`](Self::sample_li_about) for surfaces.
    pub fn sample_li(&self, u: Vec2) -> Option<LightSample> {
        self.sample_li_about(Vec3::ZERO, u)
    }

    /// A direction towards the environment seen from a surface whose reflection faces `n`
    /// (zero for a point in a medium or a surface that transmits): a constant world is
    /// sampled by cos(wi, n) / pi over that hemisphere, as the diffuse part weighs it, instead
    /// of uniformly over the sphere, half of which lies behind the surface; an image by its
    /// luminance.
    pub fn sample_li_about(&self, n: Vec3, u: Vec2) -> Option<LightSample> {
        let (wi, pdf) = match &self.image {
            None if n != Vec3::ZERO => {
                let local = warp::square_to_cosine_hemisphere(u);
                let pdf = warp::cosine_hemisphere_pdf(local);
                if pdf <= 0.0 {
                    return None;
                }
                (Frame::from_normal(n).to_world(local).normalize(), pdf)
            }
            None => (warp::square_to_uniform_sphere(u), INV_4PI),
            Some((_, dist)) => {
                let (uv, pdf_uv) = dist.sample(u);
                let local = uv_to_dir(uv);
                let cos_lat = local.truncate().length();
                if cos_lat <= 0.0 {
                    return None;
                }
                let wi = self.to_world.vector(local).normalize();
                (wi, pdf_uv / (2.0 * PI * PI * cos_lat))
            }
        };
        Some(LightSample {
            wi,
            li: self.le(wi),
            pdf,
            dist: f32::INFINITY,
            p: Vec3::ZERO,
            n: Vec3::ZERO,
            delta: false,
        })
    }

    /// The density of [`sample_li_about`](Self::sample_li_about) about `n` in direction `wi`.
    pub fn pdf_li_about(&self, n: Vec3, wi: Vec3) -> f32 {
        match &self.image {
            None if n != Vec3::ZERO => wi.dot(n).max(0.0) * INV_PI,
            None => INV_4PI,
            Some((_, dist)) => {
                let local = self.to_world.inv_vector(wi).normalize_or_zero();
                let uv = dir_to_uv(local);
                let cos_lat = local.truncate().length();
                if cos_lat <= 0.0 {
                    return 0.0;
                }
                dist.pdf(uv) / (2.0 * PI * PI * cos_lat)
            }
        }
    }

    /// Power through a disk covering the scene: pi R^2 x pi x mean radiance.
    pub fn power(&self, scene_radius: f32) -> Spectrum {
        let mean = match &self.image {
            None => self.scale,
            Some((tex, _)) => {
                let n = 64;
                let mut s = Spectrum::ZERO;
                let mut wsum = 0.0;
                for j in 0..n {
                    for i in 0..2 * n {
                        let uv = Vec2::new(
                            (i as f32 + 0.5) / (2 * n) as f32,
                            (j as f32 + 0.5) / n as f32,
                        );
                        let w = (PI * (uv.y - 0.5)).cos();
                        s += tex.eval_rgb(uv) * w;
                        wsum += w;
                    }
                }
                self.scale * s / wsum
            }
        };
        mean * (PI * PI * scene_radius * scene_radius)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lat_long_round_trip_and_blender_orientation() {
        // Blender: u = 0.5 looks down +X, the top row is +Z.
        assert!((uv_to_dir(Vec2::new(0.5, 0.5)) - Vec3::X).length() < 1e-6);
        assert!((uv_to_dir(Vec2::new(0.5, 1.0)) - Vec3::Z).length() < 1e-6);
        for (u, v) in [(0.1, 0.2), (0.7, 0.9), (0.99, 0.5)] {
            let uv = Vec2::new(u, v);
            assert!((dir_to_uv(uv_to_dir(uv)) - uv).length() < 1e-5);
        }
    }
}
