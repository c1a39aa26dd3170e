//! `emission`: emitters and the background seen directly. Through a specular chain the same
//! radiance lands in `specular` instead.

use crate::geometry::SurfaceInteraction;
use crate::math::Spectrum;
use crate::scene::Scene;

/// Radiance emitted by the surface towards the ray's origin (both faces emit, as in Cycles).
pub fn surface_emission(scene: &Scene, si: &SurfaceInteraction) -> Spectrum {
    match scene.materials.get(si.material as usize) {
        Some(m) if m.is_emissive() => scene.emission_at(m, si),
        _ => Spectrum::ZERO,
    }
}

/// Radiance of everything at infinity along an escaping ray.
pub fn background(scene: &Scene, d: glam::Vec3) -> Spectrum {
    scene.background(d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Ray;
    use crate::render::terms::testing;
    use crate::scene::SceneHit;
    use glam::Vec3;

    fn glowing_floor(strength: f32) -> Scene {
        testing::scene(serde_json::json!({
            "materials": [{"type": "emission", "name": "glow", "color": [1.0, 0.5, 0.25],
                           "strength": strength}],
            "meshes": [testing::floor(0)],
            "environment": {"color": [0.2, 0.3, 0.4], "strength": 0.5},
        }))
    }

    #[test]
    fn an_emissive_surface_gives_colour_times_strength_from_both_faces() {
        let sc = glowing_floor(2.0);
        let (si, _) = testing::hit_below(&sc, 0.3);
        assert_eq!(surface_emission(&sc, &si), Spectrum::new(2.0, 1.0, 0.5));
        let up = Ray {
            o: Vec3::new(0.3, 0.0, -2.0),
            d: Vec3::Z,
            t_max: f32::INFINITY,
        };
        let SceneHit::Surface(back) = sc.intersect(&up) else {
            panic!("the ray from below hits the floor");
        };
        assert_eq!(surface_emission(&sc, &back), Spectrum::new(2.0, 1.0, 0.5));
        // Strength 2% higher is 2% more light.
        let brighter = glowing_floor(2.04);
        let (si, _) = testing::hit_below(&brighter, 0.3);
        assert!((surface_emission(&brighter, &si).x - 2.04).abs() < 1e-6);
    }

    #[test]
    fn a_diffuse_surface_emits_nothing_and_an_escaping_ray_sees_the_world() {
        let sc = testing::scene(serde_json::json!({
            "materials": [{"type": "diffuse", "name": "grey", "color": [0.5, 0.5, 0.5]}],
            "meshes": [testing::floor(0)],
            "environment": {"color": [0.2, 0.3, 0.4], "strength": 0.5},
        }));
        let (si, _) = testing::hit_below(&sc, 0.0);
        assert_eq!(surface_emission(&sc, &si), Spectrum::ZERO);
        for d in [Vec3::Z, Vec3::X, Vec3::new(0.3, -0.4, 0.866).normalize()] {
            let bg = background(&sc, d);
            assert!(
                (bg - Spectrum::new(0.1, 0.15, 0.2)).abs().max_element() < 1e-6,
                "{bg}"
            );
        }
    }
}
