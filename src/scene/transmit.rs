//! Rays through media and their invisible boundaries: transmittance for shadow rays, and the
//! first visible surface with the transmittance up to it.

use super::{LightHit, Scene, SceneHit};
use crate::geometry::{Ray, SurfaceInteraction};
use crate::math::Spectrum;
use crate::media::MediumStack;

/// Null-surface crossings followed before giving up (a ray grazing many boundaries).
const MAX_CROSSINGS: u32 = 64;

impl Scene {
    /// Whether the ray, continuing through `si`, enters the mesh (against its outward normal).
    pub fn update_stack(&self, stack: &mut MediumStack, si: &SurfaceInteraction, dir: glam::Vec3) {
        if let Some(Some(m)) = self.instance_medium.get(si.instance as usize) {
            // `si.ng` follows the winding (outward); eye and photon passes may have flipped
            // it for shading, so the caller passes the unflipped interaction.
            stack.cross(*m, dir.dot(si.ng) < 0.0);
        }
    }

    fn is_null(&self, si: &SurfaceInteraction) -> bool {
        self.materials
            .get(si.material as usize)
            .is_some_and(|m| m.is_null())
    }

    /// Transmittance along a shadow ray (its `t_max` marks the light): 0 when an opaque
    /// surface blocks it, else the product of the media's transmittances through any
    /// invisible boundaries. Without media this is the plain any-hit test.
    pub fn transmittance(&self, ray: &Ray, stack: &MediumStack) -> Spectrum {
        if !self.has_media() && !self.transparent {
            return if self.accel.occluded(ray) {
                Spectrum::ZERO
            } else {
                Spectrum::ONE
            };
        }
        let mut stack = *stack;
        let mut ray = *ray;
        let target = if ray.t_max.is_finite() {
            Some(ray.o + ray.d * ray.t_max)
        } else {
            None
        };
        let mut t = Spectrum::ONE;
        let mut transparent_hits = 0u32;
        for _ in 0..MAX_CROSSINGS {
            let hit = self.accel.intersect(&ray);
            let seg = match &hit {
                Some(h) => h.t * ray.d.length(),
                None => ray.t_max * ray.d.length(),
            };
            if let Some(m) = stack.current(self.world_medium) {
                t *= self.media[m as usize].transmittance_along(ray.o, ray.d.normalize(), seg);
            }
            let Some(h) = hit else { return t };
            let mut si = self.accel.interaction(&ray, &h);
            si.path = shadow_path(transparent_hits);
            if !self.is_null(&si) {
                // A transparent surface lets its transparency through (Cycles' transparent
                // shadows), up to the transparent bounce limit.
                let pass = match self.materials.get(si.material as usize) {
                    Some(m) if self.transparent => self.transparency(m, &si),
                    _ => Spectrum::ZERO,
                };
                transparent_hits += 1;
                if transparent_hits > super::shading::MAX_TRANSPARENT {
                    return Spectrum::ZERO;
                }
                t *= pass;
            }
            if t.max_element() <= 0.0 {
                return Spectrum::ZERO;
            }
            self.update_stack(&mut stack, &si, ray.d);
            ray = match target {
                Some(p) => si.spawn_ray_to(p),
                None => si.spawn_ray(ray.d),
            };
        }
        Spectrum::ZERO
    }

    /// The first visible thing along the ray, passing invisible boundaries (updating
    /// `stack`), with the media's transmittance up to it.
    pub fn intersect_through(&self, ray: &Ray, stack: &mut MediumStack) -> (SceneHit, Spectrum) {
        self.intersect_through_lights(ray, stack, false, None)
    }

    /// As [`Scene::intersect_through`], also handing every analytic light crossed on the way
    /// to `on_light`, with the media's transmittance up to it. With `transparent`, partly
    /// transparent surfaces that do not emit are passed too, their transparency taken into
    /// the transmittance as a shadow ray takes it ([`Scene::transmittance`]): what a light
    /// sample and a BSDF sample of the same direct estimate see must be the same.
    pub fn intersect_through_lights(
        &self,
        ray: &Ray,
        stack: &mut MediumStack,
        transparent: bool,
        mut on_light: Option<&mut dyn FnMut(LightHit, Spectrum)>,
    ) -> (SceneHit, Spectrum) {
        let mut ray = *ray;
        let mut t = Spectrum::ONE;
        let mut transparent_hits = 0u32;
        for _ in 0..MAX_CROSSINGS {
            let hit = self.intersect(&ray);
            let len = ray.d.length();
            let t_end = match &hit {
                SceneHit::Surface(si) => si.t,
                SceneHit::Miss => f32::INFINITY,
            };
            let medium = stack.current(self.world_medium);
            if let Some(f) = on_light.as_mut() {
                self.lights_crossed(&ray, t_end, |lh| {
                    let tr = match medium {
                        Some(m) => self.media[m as usize].transmittance_along(
                            ray.o,
                            ray.d / len,
                            lh.t * len,
                        ),
                        None => Spectrum::ONE,
                    };
                    f(lh, t * tr);
                });
            }
            if let Some(m) = medium {
                t *= self.media[m as usize].transmittance_along(ray.o, ray.d / len, t_end * len);
            }
            match hit {
                SceneHit::Surface(si) if self.is_null(&si) => {
                    self.update_stack(stack, &si, ray.d);
                    ray = si.spawn_ray(ray.d);
                }
                SceneHit::Surface(mut si)
                    if transparent
                        && self.transparent
                        && !self.emissive.contains_key(&(si.instance, si.prim)) =>
                {
                    si.path = shadow_path(transparent_hits);
                    let pass = self
                        .materials
                        .get(si.material as usize)
                        .map_or(Spectrum::ZERO, |m| self.transparency(m, &si));
                    if pass.max_element() <= 0.0 {
                        return (SceneHit::Surface(si), t);
                    }
                    transparent_hits += 1;
                    if transparent_hits > super::shading::MAX_TRANSPARENT {
                        return (SceneHit::Miss, Spectrum::ZERO);
                    }
                    t *= pass;
                    self.update_stack(stack, &si, ray.d);
                    ray = si.spawn_ray(ray.d);
                }
                other => return (other, t),
            }
        }
        (SceneHit::Miss, Spectrum::ZERO)
    }
}

impl Scene {
    /// The media containing point `p`: a ray from `p` in a fixed direction leaves every mesh
    /// medium that contains `p` through a boundary facing along the ray (its first crossing of
    /// that mesh is an exit).
    pub fn medium_stack_at(&self, p: glam::Vec3) -> MediumStack {
        let mut stack = MediumStack::default();
        if !self.instance_medium.iter().any(Option::is_some) {
            return stack;
        }
        let dir = glam::Vec3::new(0.267, 0.534, 0.802).normalize();
        let mut seen: Vec<u32> = Vec::new();
        let mut ray = Ray {
            o: p,
            d: dir,
            t_max: f32::INFINITY,
        };
        let mut inside: Vec<u32> = Vec::new();
        for _ in 0..1024 {
            let Some(h) = self.accel.intersect(&ray) else {
                break;
            };
            let si = self.accel.interaction(&ray, &h);
            if !seen.contains(&si.instance) {
                seen.push(si.instance);
                if let Some(Some(m)) = self.instance_medium.get(si.instance as usize) {
                    if dir.dot(si.ng) > 0.0 {
                        inside.push(*m);
                    }
                }
            }
            ray = si.spawn_ray(dir);
        }
        // Outermost first: the exits seen last belong to the enclosing meshes.
        for m in inside.into_iter().rev() {
            stack.cross(m, true);
        }
        stack
    }
}

/// A shadow ray that has passed `crossed` transparent surfaces (a BSDF sample of a direct
/// estimate sees the surfaces it passes as its light samples' shadow rays do).
fn shadow_path(crossed: u32) -> crate::geometry::RayPath {
    crate::geometry::RayPath {
        transparent_depth: crossed.min(255) as u8,
        ..crate::geometry::RayPath::SHADOW_RAY
    }
}
