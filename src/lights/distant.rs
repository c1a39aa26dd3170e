//! Distant (sun) light.
//!
//! | parameter | meaning |
//! |---|---|
//! | `direction` | direction the light travels |
//! | `irradiance` E (W/m^2) x `color` | irradiance on a surface facing the light |
//! | `angle` | angular diameter; 0 is a delta light, otherwise a disk of radiance E / (pi sin^2(angle/2)) |

use super::LightSample;
use crate::math::{Frame, Spectrum, PI};
use crate::sampling::warp;
use glam::{Vec2, Vec3};

#[derive(Clone, Debug)]
pub struct DistantLight {
    /// Unit direction towards the light.
    pub to_light: Vec3,
    pub irradiance: Spectrum,
    pub cos_half_angle: f32,
    radiance: Spectrum,
}

impl DistantLight {
    pub fn new(direction: Vec3, irradiance: f32, color: Spectrum, angle: f32) -> Self {
        let half = 0.5 * angle;
        let cos_half_angle = if half > 1e-6 { half.cos() } else { 1.0 };
        let sin2 = half.sin() * half.sin();
        let e = color * irradiance;
        let radiance = if cos_half_angle < 1.0 {
            e / (PI * sin2)
        } else {
            Spectrum::ZERO
        };
        DistantLight {
            to_light: -direction.normalize(),
            irradiance: e,
            cos_half_angle,
            radiance,
        }
    }

    pub fn sample_li(&self, u: Vec2) -> Option<LightSample> {
        if self.cos_half_angle >= 1.0 {
            return Some(LightSample {
                wi: self.to_light,
                li: self.irradiance,
                pdf: 1.0,
                dist: f32::INFINITY,
                p: Vec3::ZERO,
                n: Vec3::ZERO,
                delta: true,
            });
        }
        let wi = Frame::from_normal(self.to_light)
            .to_world(warp::square_to_uniform_cone(u, self.cos_half_angle));
        Some(LightSample {
            wi,
            li: self.radiance,
            pdf: warp::uniform_cone_pdf(self.cos_half_angle),
            dist: f32::INFINITY,
            p: Vec3::ZERO,
            n: Vec3::ZERO,
            delta: false,
        })
    }

    pub fn pdf_li(&self, wi: Vec3) -> f32 {
        if self.cos_half_angle < 1.0 && wi.dot(self.to_light) > self.cos_half_angle {
            warp::uniform_cone_pdf(self.cos_half_angle)
        } else {
            0.0
        }
    }

    /// Radiance seen by a ray escaping along `d`.
    pub fn le(&self, d: Vec3) -> Spectrum {
        if self.cos_half_angle < 1.0 && d.normalize().dot(self.to_light) > self.cos_half_angle {
            self.radiance
        } else {
            Spectrum::ZERO
        }
    }

    /// Power through a disk covering the scene.
    pub fn power(&self, scene_radius: f32) -> Spectrum {
        self.irradiance * (PI * scene_radius * scene_radius)
    }
}
