//! Robustness of ray spawning (pbrt-v4 §6.8): rays leaving a surface never re-hit it,
//! rays continuing through a closed surface neither get stuck nor leak, and shadow rays
//! between two surface points are not blocked by those surfaces. Every check runs near
//! the origin, far from it (1e5), and far from it inside a 1e-3 scaled instance.

use glam::{Mat4, Vec3};
use photonmap::geometry::{shapes, Accel, Instance, MeshGeom, Ray, SurfaceInteraction};
use photonmap::math::{Frame, Transform};
use photonmap::sampling::{warp, Rng};

/// Where the scene sits in the world.
#[derive(Clone, Copy, Debug)]
enum Placement {
    /// Vertices near the origin, identity instances.
    Origin,
    /// Vertices stored at 1e5 in the mesh itself, identity instances.
    BakedFar,
    /// Meshes near the origin, instanced with a 1e5 translation.
    TranslatedFar,
    /// Meshes 1000 times larger, instanced with a 1e-3 scale and a 1e5 translation.
    ScaledFar,
}

const PLACEMENTS: [Placement; 4] = [
    Placement::Origin,
    Placement::BakedFar,
    Placement::TranslatedFar,
    Placement::ScaledFar,
];

const FAR: Vec3 = Vec3::new(1.0e5, -1.0e5, 0.7e5);

/// A unit sphere (instance 0) and a box beside it (instance 1); returns the accel and the
/// world centre of the sphere.
fn scene(place: Placement, box_lo: Vec3, box_hi: Vec3) -> (Accel, Vec3) {
    let (obj_scale, obj_offset, m) = match place {
        Placement::Origin => (1.0, Vec3::ZERO, Mat4::IDENTITY),
        Placement::BakedFar => (1.0, FAR, Mat4::IDENTITY),
        Placement::TranslatedFar => (1.0, Vec3::ZERO, Mat4::from_translation(FAR)),
        Placement::ScaledFar => (
            1000.0,
            Vec3::ZERO,
            Mat4::from_translation(FAR) * Mat4::from_scale(Vec3::splat(1e-3)),
        ),
    };
    let sphere = shapes::sphere(obj_offset, obj_scale, 48, 64);
    let cube = shapes::cuboid(
        obj_offset + box_lo * obj_scale,
        obj_offset + box_hi * obj_scale,
    );
    let t = Transform::new(m).expect("invertible");
    let meshes: Vec<MeshGeom> = vec![sphere, cube];
    let instances = vec![
        Instance {
            mesh: 0,
            transform: t,
        },
        Instance {
            mesh: 1,
            transform: t,
        },
    ];
    let center = if matches!(
        place,
        Placement::BakedFar | Placement::TranslatedFar | Placement::ScaledFar
    ) {
        FAR
    } else {
        Vec3::ZERO
    };
    (Accel::build(meshes, instances), center)
}

/// How deep `o` lies inside the unit sphere at `center` or the box beside it (negative
/// when outside both). The sphere's tessellation lies between radius 0.99 and 1.
fn depth_inside(o: Vec3, center: Vec3) -> f32 {
    let sphere = 0.99 - (o - center).length();
    let q = o - center - Vec3::new(4.0, 0.0, 0.0);
    let cube = (Vec3::ONE - q.abs()).min_element();
    sphere.max(cube)
}

fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// Cosine-distributed direction on the side of the surface that `wo` is on.
fn hemisphere(si: &SurfaceInteraction, rng: &mut Rng) -> Vec3 {
    let n = if si.ng.dot(si.wo) < 0.0 {
        -si.ng
    } else {
        si.ng
    };
    Frame::from_normal(n).to_world(warp::square_to_cosine_hemisphere(rng.vec2()))
}

/// Primary rays from inside the sphere, from inside the box, and from outside.
fn primary(rng: &mut Rng, center: Vec3, i: u32) -> Ray {
    let dir = warp::square_to_uniform_sphere(rng.vec2());
    match i % 3 {
        0 => Ray::new(center + (rng.vec3() - 0.5) * 0.8, dir),
        1 => Ray::new(
            center + Vec3::new(4.0, 0.0, 0.0) + (rng.vec3() - 0.5) * 1.5,
            dir,
        ),
        _ => {
            let o = center + Vec3::new(2.0, 0.0, 0.0) + dir * 8.0;
            let target = center + Vec3::new(2.0 * rng.f32(), 0.0, 0.0) + (rng.vec3() - 0.5) * 2.2;
            Ray::new(o, target - o)
        }
    }
}

#[test]
fn spawned_rays_never_self_intersect() {
    let mut spawned = 0u32;
    let mut self_hits = 0u32;
    for (pi, place) in PLACEMENTS.into_iter().enumerate() {
        let (acc, center) = scene(place, Vec3::new(3.0, -1.0, -1.0), Vec3::new(5.0, 1.0, 1.0));
        let mut rng = Rng::new(17, pi as u64);
        for i in 0..30_000 {
            let ray = primary(&mut rng, center, i);
            let Some(hit) = acc.intersect(&ray) else {
                continue;
            };
            let si = acc.interaction(&ray, &hit);
            let outside = si.ng.dot(si.wo) > 0.0;
            for dir in [reflect(ray.d.normalize(), si.ng), hemisphere(&si, &mut rng)] {
                let r2 = si.spawn_ray(dir);
                spawned += 1;
                if let Some(h2) = acc.intersect(&r2) {
                    // Both solids are convex: leaving one from outside never meets it again,
                    // and from inside never meets the same (planar) triangle.
                    let same = if outside {
                        h2.instance == hit.instance
                    } else {
                        (h2.instance, h2.prim) == (hit.instance, hit.prim)
                    };
                    if same {
                        self_hits += 1;
                        if self_hits < 5 {
                            eprintln!(
                                "{place:?}: self-hit at t = {} from {:?} (outside = {outside})",
                                h2.t, si.p
                            );
                        }
                    }
                }
            }
        }
    }
    assert!(spawned >= 100_000, "{spawned} spawned rays");
    assert_eq!(
        self_hits, 0,
        "self-intersections among {spawned} spawned rays"
    );
}

#[test]
fn rays_pass_through_closed_surfaces() {
    let mut passes = 0u32;
    let mut odd = 0u32;
    for (pi, place) in PLACEMENTS.into_iter().enumerate() {
        let (acc, center) = scene(place, Vec3::new(3.0, -1.0, -1.0), Vec3::new(5.0, 1.0, 1.0));
        let mut rng = Rng::new(23, pi as u64);
        for _ in 0..20_000 {
            // From outside, towards the sphere or the box.
            let dir = warp::square_to_uniform_sphere(rng.vec2());
            let aim = if rng.f32() < 0.5 {
                center
            } else {
                center + Vec3::new(4.0, 0.0, 0.0)
            };
            let o = aim + dir * 10.0;
            let target = aim + (rng.vec3() - 0.5) * 1.9;
            let mut ray = Ray::new(o, target - o);
            // Follow the ray through every surface it meets. It must never get stuck on
            // one, and must not leak: when it finally escapes, its origin is outside both
            // solids, up to the rounding-error bound of the points it went through (a ray
            // that clips an edge may enter and leave within that bound, with one hit).
            let mut steps = 0;
            let mut crossings = 0;
            let mut err = 0.0f32;
            while let Some(h) = acc.intersect(&ray) {
                steps += 1;
                assert!(steps <= 8, "{place:?}: ray stuck after {steps} hits");
                let si = acc.interaction(&ray, &h);
                err = err.max(si.p_error.max_element());
                ray = si.spawn_ray(ray.d);
                crossings += 1;
            }
            let depth = depth_inside(ray.o, center);
            assert!(
                depth <= 4.0 * err + 1e-6,
                "{place:?}: leaked, escaped from {depth} inside a solid"
            );
            odd += crossings % 2;
            passes += 1;
        }
    }
    assert!(passes >= 80_000);
    // Odd counts only come from rays clipping an edge within the error bound.
    assert!(
        odd * 200 < passes,
        "{odd} of {passes} rays crossed an odd number of surfaces"
    );
}

#[test]
fn shadow_rays_between_facing_surfaces_are_unoccluded() {
    let mut tested = 0u32;
    for (pi, place) in PLACEMENTS.into_iter().enumerate() {
        // An empty room: a box beside the sphere, seen from inside.
        let (acc, center) = scene(
            place,
            Vec3::new(-3.0, -2.0, -2.5),
            Vec3::new(-1.2, 2.0, 2.5),
        );
        let inside = center + Vec3::new(-2.1, 0.0, 0.0);
        let mut rng = Rng::new(31, pi as u64);
        let mut pts: Vec<SurfaceInteraction> = Vec::new();
        while pts.len() < 600 {
            let ray = Ray::new(
                inside + (rng.vec3() - 0.5) * 0.5,
                warp::square_to_uniform_sphere(rng.vec2()),
            );
            if let Some(h) = acc.intersect(&ray) {
                if h.instance == 1 {
                    pts.push(acc.interaction(&ray, &h));
                }
            }
        }
        for a in &pts {
            for b in pts.iter().step_by(7) {
                // Points on walls that face each other.
                if a.ng.dot(b.ng) > -0.5 {
                    continue;
                }
                let r = a.spawn_ray_to_interaction(b.p, b.p_error, b.ng);
                assert!(
                    !acc.occluded(&r),
                    "{place:?}: {:?} -> {:?} occluded",
                    a.p,
                    b.p
                );
                if matches!(place, Placement::Origin) {
                    assert!(!acc.occluded(&a.spawn_ray_to(b.p)));
                }
                tested += 1;
            }
        }
    }
    assert!(tested > 5_000, "{tested}");
}
