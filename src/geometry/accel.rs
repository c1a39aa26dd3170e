//! Two-level acceleration structure: one 4-wide BVH ([`WideBvh`]) per mesh over its
//! triangles in object space (the BLAS) and one over the instances' world bounds (the TLAS). Instances share
//! their mesh and its BLAS; rays are carried into object space per instance, except for
//! identity transforms, which use the world ray as is.

mod surface;

use super::bvh::{transform_bounds, BoxRay};
use super::bvh_simd::prefetch;
use super::bvh_wide::WideBvh;
use super::huge_pages;
use super::interaction::transform_point_error;
use super::mesh::{Instance, MeshGeom};
use super::ray::Ray;
use super::triangle::{intersect_triangle, intersect_triangle_from_volume, is_degenerate, TriRay};
use crate::math::Bounds3;
use glam::{Mat4, Vec3};
use std::sync::atomic::{AtomicBool, Ordering};

static EMPTY_MESH: MeshGeom = MeshGeom {
    positions: Vec::new(),
    indices: Vec::new(),
    normals: None,
    uvs: None,
    material_ids: Vec::new(),
    attributes: Vec::new(),
};

/// Closest hit of a ray.
///
/// | field | meaning |
/// |-------|---------|
/// | `t` | ray parameter of the hit, `0 < t < ray.t_max` |
/// | `instance` | index into [`Accel::instances`] |
/// | `prim` | triangle index in the instance's mesh |
/// | `b1`, `b2` | barycentrics of vertices 1 and 2 (`b0 = 1 − b1 − b2`) |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub instance: u32,
    pub prim: u32,
    pub b1: f32,
    pub b2: f32,
}

/// 4-wide BVH of one mesh, with its non-degenerate triangles copied in leaf order for
/// locality (a leaf's triangles are read from one contiguous range, without the index list).
#[derive(Clone, Debug, Default)]
struct Blas {
    bvh: WideBvh,
    tris: Vec<[Vec3; 3]>,
}

/// Per-instance data used while tracing.
#[derive(Clone, Copy, Debug)]
struct InstData {
    identity: bool,
    swaps_handedness: bool,
}

/// Per-ray constants in one space (world, or an instance's object space).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RayCtx {
    pub(crate) boxr: BoxRay,
    pub(crate) tri: TriRay,
}

impl RayCtx {
    #[inline]
    pub(crate) fn new(o: Vec3, d: Vec3) -> Self {
        RayCtx {
            boxr: BoxRay::new(o, d),
            tri: TriRay::new(o, d),
        }
    }
}

/// The ray scene: meshes, their instances and the two-level BVH over them.
#[derive(Clone, Debug, Default)]
pub struct Accel {
    meshes: Vec<MeshGeom>,
    /// Whether some mesh carries named attributes.
    any_attributes: bool,
    blas: Vec<Blas>,
    instances: Vec<Instance>,
    inst: Vec<InstData>,
    top: WideBvh,
}

impl Blas {
    fn build(mesh: &MeshGeom, cancel: Option<&AtomicBool>) -> Option<Blas> {
        let n = mesh.indices.len();
        let mut bounds = Vec::with_capacity(n);
        let mut cents = Vec::with_capacity(n);
        for t in 0..n as u32 {
            let p = mesh.triangle(t);
            if is_degenerate(&p) {
                bounds.push(Bounds3::EMPTY);
                cents.push(Vec3::ZERO);
                continue;
            }
            let mut b = Bounds3::from_point(p[0]);
            b.extend(p[1]);
            b.extend(p[2]);
            bounds.push(b);
            cents.push(b.center());
        }
        let bvh = WideBvh::build_cancellable(&bounds, &cents, cancel)?;
        let mut tris = Vec::with_capacity(bvh.prims.len());
        huge_pages::advise(&mut tris);
        tris.extend(bvh.prims.iter().map(|&i| mesh.triangle(i)));
        Some(Blas { bvh, tris })
    }

    /// Closest hit in this BLAS below `t_max`: (t, prim, b1, b2).
    #[inline(always)]
    fn closest(&self, r: &RayCtx, t_max: f32) -> Option<(f32, u32, f32, f32)> {
        self.closest_with(r, t_max, intersect_triangle)
    }

    /// [`Blas::closest`] with the triangle test `test`.
    #[inline(always)]
    fn closest_with(
        &self,
        r: &RayCtx,
        t_max: f32,
        test: impl Fn(&TriRay, f32, Vec3, Vec3, Vec3) -> Option<super::triangle::TriHit>,
    ) -> Option<(f32, u32, f32, f32)> {
        let mut t = t_max;
        let mut best = None;
        let hint = |first, count| {
            prefetch(&self.tris, first, count);
            prefetch(&self.bvh.prims, first, count);
        };
        self.bvh
            .traverse_with_hint(&r.boxr, &mut t, hint, |first, count, t_max| {
                for k in first..first + count {
                    let Some(p) = self.tris.get(k) else { continue };
                    if let Some(h) = test(&r.tri, *t_max, p[0], p[1], p[2]) {
                        *t_max = h.t;
                        best = Some((h.t, k as u32, h.b1, h.b2));
                    }
                }
                false
            });
        best.map(|(t, k, b1, b2)| {
            (
                t,
                self.bvh.prims.get(k as usize).copied().unwrap_or(0),
                b1,
                b2,
            )
        })
    }

    /// Whether any triangle is hit below `t_max`.
    #[inline(always)]
    fn any(&self, r: &RayCtx, t_max: f32) -> bool {
        let mut t = t_max;
        self.bvh.traverse(&r.boxr, &mut t, |first, count, t_max| {
            self.tris
                .get(first..first + count)
                .unwrap_or(&[])
                .iter()
                .any(|p| intersect_triangle(&r.tri, *t_max, p[0], p[1], p[2]).is_some())
        })
    }
}

/// Carries a world ray into object space with the inverse transform `inv`, moving the
/// origin forward past its rounding error (pbrt-v4 `Transform::ApplyInverse(Ray)`).
/// Returns the object-space constants and the parameter shift `dt`: object-space hits
/// at `t'` are at `t' + dt` along the world ray.
#[inline]
pub(crate) fn object_ray(inv: &Mat4, o: Vec3, d: Vec3) -> (RayCtx, f32) {
    let oo = inv.transform_point3(o);
    let od = inv.transform_vector3(d);
    let err = transform_point_error(inv, o, Vec3::ZERO);
    let len2 = od.length_squared();
    let mut dt = 0.0;
    let mut oo2 = oo;
    if len2 > 0.0 {
        dt = od.abs().dot(err) / len2;
        if dt.is_finite() {
            oo2 = oo + od * dt;
        } else {
            dt = 0.0;
        }
    }
    (RayCtx::new(oo2, od), dt)
}

impl Accel {
    /// Builds the acceleration structure. Never panics: empty meshes, an empty instance
    /// list, instances of missing meshes and degenerate triangles are all allowed (they
    /// are simply never hit).
    ///
    /// | parameter | meaning |
    /// |-----------|---------|
    /// | `meshes` | object-space meshes, shared by the instances that reference them |
    /// | `instances` | placements of meshes in the world |
    pub fn build(meshes: Vec<MeshGeom>, instances: Vec<Instance>) -> Accel {
        Self::build_cancellable(meshes, instances, None).expect("not cancelled")
    }

    /// As [`Accel::build`], giving up (`None`) soon after `cancel` is set: it is read before
    /// each mesh and within large BVH builds.
    pub fn build_cancellable(
        meshes: Vec<MeshGeom>,
        instances: Vec<Instance>,
        cancel: Option<&AtomicBool>,
    ) -> Option<Accel> {
        use rayon::prelude::*;
        let blas: Vec<Blas> = meshes
            .par_iter()
            .map(|m| {
                if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                    return None;
                }
                Blas::build(m, cancel)
            })
            .collect::<Option<_>>()?;
        let mut wb = Vec::with_capacity(instances.len());
        let mut inst = Vec::with_capacity(instances.len());
        for i in &instances {
            let b = blas
                .get(i.mesh as usize)
                .map(|bl| bl.bvh.bounds())
                .unwrap_or(Bounds3::EMPTY);
            let identity = i.transform.m == Mat4::IDENTITY;
            wb.push(if identity {
                b
            } else {
                transform_bounds(&i.transform.m, &b)
            });
            inst.push(InstData {
                identity,
                swaps_handedness: i.transform.swaps_handedness(),
            });
        }
        let cents: Vec<Vec3> = wb.iter().map(|b| b.center()).collect();
        let top = WideBvh::build_cancellable(&wb, &cents, cancel)?;
        let any_attributes = meshes.iter().any(|m| !m.attributes.is_empty());
        Some(Accel {
            meshes,
            any_attributes,
            blas,
            instances,
            inst,
            top,
        })
    }

    /// Closest hit with `0 < t < ray.t_max`, or `None`.
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let world = RayCtx::new(ray.o, ray.d);
        let mut t_max = ray.t_max;
        let mut best = None;
        self.top
            .traverse(&world.boxr, &mut t_max, |first, count, t_max| {
                for k in first..first + count {
                    let Some(&ii) = self.top.prims.get(k) else {
                        continue;
                    };
                    let (Some(id), Some(inst)) =
                        (self.inst.get(ii as usize), self.instances.get(ii as usize))
                    else {
                        continue;
                    };
                    let Some(blas) = self.blas.get(inst.mesh as usize) else {
                        continue;
                    };
                    let found = if id.identity {
                        blas.closest(&world, *t_max)
                    } else {
                        let (r, dt) = object_ray(&inst.transform.inv, ray.o, ray.d);
                        blas.closest(&r, *t_max - dt)
                            .map(|(t, p, b1, b2)| (t + dt, p, b1, b2))
                    };
                    if let Some((t, prim, b1, b2)) = found {
                        if t < *t_max {
                            *t_max = t;
                            best = Some(Hit {
                                t,
                                instance: ii,
                                prim,
                                b1,
                                b2,
                            });
                        }
                    }
                }
                false
            });
        best
    }

    /// Closest hit of `ray` on instance `instance` alone, with `0 < t < ray.t_max`.
    pub fn intersect_instance(&self, ray: &Ray, instance: u32) -> Option<Hit> {
        self.instance_closest(ray, instance, intersect_triangle)
    }

    /// [`Accel::intersect_instance`] for a ray that starts inside a volume, not on a
    /// surface: a hit at any computed `t > 0` counts
    /// ([`super::triangle::intersect_triangle_from_volume`]).
    pub fn intersect_instance_from_volume(&self, ray: &Ray, instance: u32) -> Option<Hit> {
        self.instance_closest(ray, instance, intersect_triangle_from_volume)
    }

    fn instance_closest(
        &self,
        ray: &Ray,
        instance: u32,
        test: impl Fn(&TriRay, f32, Vec3, Vec3, Vec3) -> Option<super::triangle::TriHit>,
    ) -> Option<Hit> {
        let id = self.inst.get(instance as usize)?;
        let inst = self.instances.get(instance as usize)?;
        let blas = self.blas.get(inst.mesh as usize)?;
        let found = if id.identity {
            blas.closest_with(&RayCtx::new(ray.o, ray.d), ray.t_max, test)
        } else {
            let (r, dt) = object_ray(&inst.transform.inv, ray.o, ray.d);
            blas.closest_with(&r, ray.t_max - dt, test)
                .map(|(t, p, b1, b2)| (t + dt, p, b1, b2))
        };
        found.map(|(t, prim, b1, b2)| Hit {
            t,
            instance,
            prim,
            b1,
            b2,
        })
    }

    /// Whether a triangle may lie within distance `r` of `p`: `false` means none does. The
    /// test is conservative (bounding boxes against the sphere's box, carried into object
    /// space by each instance's inverse), so `true` may also be said of a triangle a little
    /// farther away.
    pub fn any_surface_near(&self, p: Vec3, r: f32) -> bool {
        let q = Bounds3 {
            min: p - Vec3::splat(r),
            max: p + Vec3::splat(r),
        };
        self.top.any_overlapping(&q, |first, count| {
            (first..first + count).any(|k| {
                let Some(&ii) = self.top.prims.get(k) else {
                    return false;
                };
                let (Some(id), Some(inst)) =
                    (self.inst.get(ii as usize), self.instances.get(ii as usize))
                else {
                    return false;
                };
                let Some(blas) = self.blas.get(inst.mesh as usize) else {
                    return false;
                };
                let qo = if id.identity {
                    q
                } else {
                    transform_bounds(&inst.transform.inv, &q)
                };
                blas.bvh.any_overlapping(&qo, |first, count| {
                    blas.tris
                        .get(first..first + count)
                        .unwrap_or(&[])
                        .iter()
                        .any(|t| {
                            let mut b = Bounds3::from_point(t[0]);
                            b.extend(t[1]);
                            b.extend(t[2]);
                            b.overlaps(&qo)
                        })
                })
            })
        })
    }

    /// Whether anything is hit with `0 < t < ray.t_max` (stops at the first hit found).
    pub fn occluded(&self, ray: &Ray) -> bool {
        let world = RayCtx::new(ray.o, ray.d);
        let mut t_max = ray.t_max;
        self.top
            .traverse(&world.boxr, &mut t_max, |first, count, t_max| {
                for k in first..first + count {
                    let Some(&ii) = self.top.prims.get(k) else {
                        continue;
                    };
                    let (Some(id), Some(inst)) =
                        (self.inst.get(ii as usize), self.instances.get(ii as usize))
                    else {
                        continue;
                    };
                    let Some(blas) = self.blas.get(inst.mesh as usize) else {
                        continue;
                    };
                    let hit = if id.identity {
                        blas.any(&world, *t_max)
                    } else {
                        let (r, dt) = object_ray(&inst.transform.inv, ray.o, ray.d);
                        blas.any(&r, *t_max - dt)
                    };
                    if hit {
                        return true;
                    }
                }
                false
            })
    }

    /// World bounds of the scene (empty when nothing can be hit).
    pub fn bounds(&self) -> Bounds3 {
        self.top.bounds()
    }

    /// Mesh `i` (an empty mesh when `i` is out of range).
    pub fn mesh(&self, i: u32) -> &MeshGeom {
        self.meshes.get(i as usize).unwrap_or(&EMPTY_MESH)
    }

    /// All meshes.
    pub fn meshes(&self) -> &[MeshGeom] {
        &self.meshes
    }

    /// All instances, in the order given to [`Accel::build`].
    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// World-space vertices of triangle `prim` of `instance` (zeros when out of range).
    pub fn triangle_world(&self, instance: u32, prim: u32) -> [Vec3; 3] {
        let Some(inst) = self.instances.get(instance as usize) else {
            return [Vec3::ZERO; 3];
        };
        let Some(mesh) = self.meshes.get(inst.mesh as usize) else {
            return [Vec3::ZERO; 3];
        };
        let p = mesh.triangle(prim);
        if self.inst.get(instance as usize).is_none_or_identity() {
            p
        } else {
            p.map(|v| inst.transform.point(v))
        }
    }
}

trait IdentityFlag {
    fn is_none_or_identity(&self) -> bool;
}

impl IdentityFlag for Option<&InstData> {
    fn is_none_or_identity(&self) -> bool {
        self.map_or(true, |d| d.identity)
    }
}

#[cfg(test)]
#[path = "accel_tests.rs"]
mod tests;
