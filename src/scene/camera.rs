//! Perspective camera with thin-lens depth of field (pbrt-v4 §5.2), following Blender's sensor
//! fit: the sensor width spans the larger image side for `auto`.

use super::desc::{CameraDesc, FilmDesc, SensorFit};
use crate::math::Transform;
use crate::sampling::warp::square_to_uniform_disk_concentric;
use glam::{Vec2, Vec3};

#[derive(Clone, Debug)]
pub struct Camera {
    to_world: Transform,
    /// Half extents of the image plane at distance 1.
    half: Vec2,
    shift: Vec2,
    width: f32,
    height: f32,
    near: f32,
    far: f32,
    /// Lens radius and focus distance in scene units; radius 0 is a pinhole.
    lens_radius: f32,
    focus: f32,
}

/// A camera ray: origin, unit direction, and the parametric range allowed by clipping.
#[derive(Clone, Copy, Debug)]
pub struct CameraRay {
    pub o: Vec3,
    pub d: Vec3,
    pub t_max: f32,
}

impl Camera {
    /// The description has been validated.
    pub fn new(desc: &CameraDesc, film: &FilmDesc) -> Camera {
        let (w, h) = (film.width as f32, film.height as f32);
        let horizontal = match desc.sensor_fit {
            SensorFit::Auto => w >= h,
            SensorFit::Horizontal => true,
            SensorFit::Vertical => false,
        };
        let sensor = if horizontal {
            desc.sensor_width
        } else {
            desc.sensor_height.unwrap_or(desc.sensor_width)
        };
        let fit_half = match desc.fov {
            Some(fov) => (0.5 * fov).tan(),
            None => 0.5 * sensor / desc.focal_length,
        };
        let half = if horizontal {
            Vec2::new(fit_half, fit_half * h / w)
        } else {
            Vec2::new(fit_half * w / h, fit_half)
        };
        let (lens_radius, focus) = match (desc.fstop, desc.focus_distance) {
            (Some(f), Some(d)) if f > 0.0 => (0.5 * desc.focal_length * desc.units_per_mm / f, d),
            _ => (0.0, 1.0),
        };
        Camera {
            to_world: Transform::from_rows(&desc.transform).unwrap_or_default(),
            half,
            shift: Vec2::from(desc.shift) * 2.0 * fit_half,
            width: w,
            height: h,
            near: desc.near,
            far: desc.far,
            lens_radius,
            focus,
        }
    }

    /// Ray through the film position `film` (pixels, x right, y down), with lens sample `u_lens`.
    pub fn generate_ray(&self, film: Vec2, u_lens: Vec2) -> CameraRay {
        let ndc = Vec2::new(
            film.x / self.width * 2.0 - 1.0,
            1.0 - film.y / self.height * 2.0,
        );
        let dir = Vec3::new(
            ndc.x * self.half.x + self.shift.x,
            ndc.y * self.half.y + self.shift.y,
            -1.0,
        );
        let (o_cam, d_cam) = if self.lens_radius > 0.0 {
            let lens = square_to_uniform_disk_concentric(u_lens) * self.lens_radius;
            let focus_point = dir * self.focus;
            let o = Vec3::new(lens.x, lens.y, 0.0);
            (o, (focus_point - o).normalize())
        } else {
            (Vec3::ZERO, dir.normalize())
        };
        // Clipping distances are depths along the view axis.
        let cos = -d_cam.z;
        let t_near = self.near / cos;
        let t_far = self.far / cos;
        let o = self.to_world.point(o_cam + d_cam * t_near);
        let d = self.to_world.vector(d_cam);
        let scale = d.length();
        CameraRay {
            o,
            d: d / scale,
            t_max: ((t_far - t_near) * scale).max(0.0),
        }
    }

    /// Angle subtended by one pixel at the image centre (radians, approximately).
    pub fn pixel_angle(&self) -> f32 {
        2.0 * self.half.x / self.width
    }

    pub fn position(&self) -> Vec3 {
        self.to_world.point(Vec3::ZERO)
    }

    /// World directions to camera space as Cycles writes its denoising normals: x right,
    /// y up, z away from the camera (a surface facing the camera has z < 0).
    pub fn world_to_camera(&self) -> glam::Mat3 {
        let axis = |a: Vec3| self.to_world.vector(a).normalize_or_zero();
        glam::Mat3::from_cols(axis(Vec3::X), axis(Vec3::Y), -axis(Vec3::Z)).transpose()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fov_spans_the_larger_side() {
        let desc = CameraDesc {
            fov: Some(std::f32::consts::FRAC_PI_2),
            ..Default::default()
        };
        let cam = Camera::new(
            &desc,
            &FilmDesc {
                width: 200,
                height: 100,
                transparent: false,
            },
        );
        let r = cam.generate_ray(Vec2::new(200.0, 50.0), Vec2::ZERO);
        // 90 degrees across the width: the right edge is at 45 degrees.
        assert!(
            (r.d - Vec3::new(1.0, 0.0, -1.0).normalize()).length() < 1e-5,
            "{:?}",
            r.d
        );
        let top = cam.generate_ray(Vec2::new(100.0, 0.0), Vec2::ZERO);
        assert!((top.d - Vec3::new(0.0, 0.5, -1.0).normalize()).length() < 1e-5);
    }

    #[test]
    fn lens_matches_blender_focal_length() {
        // 50 mm on a 36 mm sensor: tan(fov/2) = 18/50.
        let cam = Camera::new(
            &CameraDesc::default(),
            &FilmDesc {
                width: 100,
                height: 100,
                transparent: false,
            },
        );
        let r = cam.generate_ray(Vec2::new(100.0, 50.0), Vec2::ZERO);
        assert!((r.d.x / -r.d.z - 0.36).abs() < 1e-5);
    }

    #[test]
    fn thin_lens_rays_converge_on_the_focus_plane() {
        let desc = CameraDesc {
            fstop: Some(1.0),
            focus_distance: Some(4.0),
            ..Default::default()
        };
        let cam = Camera::new(
            &desc,
            &FilmDesc {
                width: 64,
                height: 64,
                transparent: false,
            },
        );
        let mut hits = vec![];
        for u in [
            Vec2::new(0.1, 0.2),
            Vec2::new(0.9, 0.5),
            Vec2::new(0.5, 0.99),
        ] {
            let r = cam.generate_ray(Vec2::new(10.0, 20.0), u);
            let t = (-4.0 - r.o.z) / r.d.z;
            hits.push(r.o + r.d * t);
        }
        assert!((hits[0] - hits[1]).length() < 1e-4 && (hits[0] - hits[2]).length() < 1e-4);
        let r0 = cam.generate_ray(Vec2::new(10.0, 20.0), Vec2::new(0.1, 0.2));
        assert!(
            r0.o.truncate().length() > 1e-3,
            "origins spread over the lens"
        );
    }
}
