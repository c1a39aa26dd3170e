use super::*;
use crate::geometry::shapes;
use crate::geometry::triangle::face_normal;
use crate::math::Transform;
use crate::sampling::Rng;
use glam::{Quat, Vec2};

fn soup(n: usize, rng: &mut Rng, size: f32) -> MeshGeom {
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for t in 0..n as u32 {
        let c = rng.vec3() * 4.0 - 2.0;
        for _ in 0..3 {
            positions.push(c + (rng.vec3() - 0.5) * size);
        }
        indices.push([3 * t, 3 * t + 1, 3 * t + 2]);
    }
    MeshGeom {
        material_ids: (0..n as u32).collect(),
        attributes: Vec::new(),
        positions,
        indices,
        normals: None,
        uvs: None,
    }
}

fn tf(m: Mat4) -> Transform {
    Transform::new(m).expect("invertible")
}

fn transforms() -> Vec<Transform> {
    vec![
        Transform::IDENTITY,
        tf(Mat4::from_scale_rotation_translation(
            Vec3::new(0.5, 2.0, 1.3),
            Quat::from_axis_angle(Vec3::new(1.0, 2.0, -0.5).normalize(), 0.9),
            Vec3::new(3.0, -1.0, 0.5),
        )),
        tf(Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0))
            * Mat4::from_translation(Vec3::new(2.0, 2.0, 0.0))),
        tf(Mat4::from_rotation_z(2.0) * Mat4::from_scale(Vec3::new(0.3, -1.7, 0.9))),
        // Sheared.
        tf(Mat4::from_cols_array(&[
            1.0, 0.2, 0.0, 0.0, 0.0, 1.0, 0.4, 0.0, 0.3, 0.0, 1.0, 0.0, -3.0, 0.0, 1.0, 1.0,
        ])),
    ]
}

/// Closest hit by testing every triangle of every instance, with the same per-instance
/// ray transform as the accel.
fn brute(acc: &Accel, ray: &Ray) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for (ii, inst) in acc.instances.iter().enumerate() {
        let Some(mesh) = acc.meshes.get(inst.mesh as usize) else {
            continue;
        };
        let (r, dt) = if acc.inst[ii].identity {
            (RayCtx::new(ray.o, ray.d), 0.0)
        } else {
            object_ray(&inst.transform.inv, ray.o, ray.d)
        };
        for prim in 0..mesh.indices.len() as u32 {
            let p = mesh.triangle(prim);
            if is_degenerate(&p) {
                continue;
            }
            let t_max = best.map_or(ray.t_max, |h| h.t);
            if let Some(h) = intersect_triangle(&r.tri, t_max - dt, p[0], p[1], p[2]) {
                if h.t + dt < t_max {
                    best = Some(Hit {
                        t: h.t + dt,
                        instance: ii as u32,
                        prim,
                        b1: h.b1,
                        b2: h.b2,
                    });
                }
            }
        }
    }
    best
}

fn random_ray(rng: &mut Rng, scale: f32) -> Ray {
    let o = (rng.vec3() * 2.0 - 1.0) * scale;
    let d = crate::sampling::warp::square_to_uniform_sphere(rng.vec2()) * (0.1 + 3.0 * rng.f32());
    let t_max = if rng.f32() < 0.3 {
        rng.f32() * 3.0
    } else {
        f32::INFINITY
    };
    Ray::with_t_max(o, d, t_max)
}

#[test]
fn empty_scenes_hit_nothing() {
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    let cases = [
        Accel::build(vec![], vec![]),
        Accel::build(vec![MeshGeom::default()], vec![]),
        Accel::build(
            vec![MeshGeom::default()],
            vec![Instance {
                mesh: 0,
                transform: Transform::IDENTITY,
            }],
        ),
        Accel::build(
            vec![],
            vec![Instance {
                mesh: 3,
                transform: Transform::IDENTITY,
            }],
        ),
        Accel::default(),
    ];
    for a in cases {
        assert!(a.intersect(&ray).is_none());
        assert!(!a.occluded(&ray));
        assert!(a.bounds().is_empty());
        assert_eq!(a.triangle_world(0, 0), [Vec3::ZERO; 3]);
        assert!(a.mesh(9).indices.is_empty());
    }
}

#[test]
fn closest_and_any_hit_match_brute_force_with_instancing() {
    let mut rng = Rng::new(42, 0);
    let meshes = vec![
        soup(400, &mut rng, 0.6),
        soup(50, &mut rng, 1.5),
        shapes::sphere(Vec3::ZERO, 1.0, 12, 16),
    ];
    let mut instances = Vec::new();
    for (k, t) in transforms().into_iter().enumerate() {
        instances.push(Instance {
            mesh: (k % 3) as u32,
            transform: t,
        });
        instances.push(Instance {
            mesh: ((k + 1) % 3) as u32,
            transform: t,
        });
    }
    let acc = Accel::build(meshes, instances);
    let mut hits = 0;
    for i in 0..6000 {
        let ray = random_ray(&mut rng, 4.0);
        let a = acc.intersect(&ray);
        let b = brute(&acc, &ray);
        match (a, b) {
            (None, None) => {}
            (Some(a), Some(b)) => {
                hits += 1;
                assert!(a.t < ray.t_max);
                if (a.instance, a.prim) != (b.instance, b.prim) {
                    assert!((a.t - b.t).abs() <= 1e-5 * a.t, "ray {i}: {a:?} vs {b:?}");
                } else {
                    assert_eq!(a, b, "ray {i}");
                }
            }
            _ => panic!("ray {i}: {a:?} vs brute force {b:?}"),
        }
        assert_eq!(acc.occluded(&ray), b.is_some(), "any-hit of ray {i}");
    }
    assert!(hits > 1000, "{hits}");
}

#[test]
fn hits_agree_with_world_space_triangles() {
    let mut rng = Rng::new(9, 0);
    let meshes = vec![soup(300, &mut rng, 0.8)];
    let instances: Vec<Instance> = transforms()
        .into_iter()
        .map(|t| Instance {
            mesh: 0,
            transform: t,
        })
        .collect();
    let acc = Accel::build(meshes, instances);
    let world: Vec<(u32, u32, [Vec3; 3])> = (0..acc.instances().len() as u32)
        .flat_map(|i| (0..300u32).map(move |p| (i, p)))
        .map(|(i, p)| (i, p, acc.triangle_world(i, p)))
        .collect();
    let mut mismatched = 0;
    let n = 3000;
    for _ in 0..n {
        let ray = random_ray(&mut rng, 4.0);
        let r = TriRay::new(ray.o, ray.d);
        let mut best: Option<(f32, u32, u32)> = None;
        for (i, p, q) in &world {
            let t_max = best.map_or(ray.t_max, |b| b.0);
            if let Some(h) = intersect_triangle(&r, t_max, q[0], q[1], q[2]) {
                best = Some((h.t, *i, *p));
            }
        }
        match (acc.intersect(&ray), best) {
            (None, None) => {}
            (Some(a), Some(b)) if (a.instance, a.prim) == (b.1, b.2) => {
                assert!((a.t - b.0).abs() <= 1e-4 * a.t.max(1.0), "{a:?} vs {b:?}");
            }
            _ => mismatched += 1,
        }
    }
    // Only rays grazing an edge, or t_max within rounding of a hit, may differ.
    assert!(mismatched <= n / 500, "{mismatched} of {n}");
}

#[test]
fn interaction_geometry() {
    let mut mesh = shapes::sphere(Vec3::ZERO, 1.0, 10, 14);
    mesh.normals = Some(mesh.positions.iter().map(|p| p.normalize()).collect());
    mesh.material_ids = (0..mesh.indices.len() as u32).map(|i| i % 5).collect();
    let mut rng = Rng::new(3, 0);
    let instances: Vec<Instance> = transforms()
        .into_iter()
        .map(|t| Instance {
            mesh: 0,
            transform: t,
        })
        .collect();
    let acc = Accel::build(vec![mesh.clone()], instances);
    let mut checked = 0;
    for i in 0..4000 {
        // Aimed at an instance's centre, from 5 units away.
        let c = acc.instances()[i % acc.instances().len()]
            .transform
            .point(Vec3::ZERO);
        let o = c + crate::sampling::warp::square_to_uniform_sphere(rng.vec2()) * 5.0;
        let ray = Ray::new(o, (c + (rng.vec3() - 0.5) - o) * (0.2 + rng.f32()));
        let Some(h) = acc.intersect(&ray) else {
            continue;
        };
        let si = acc.interaction(&ray, &h);
        let w = acc.triangle_world(h.instance, h.prim);
        let wn = face_normal(&w).normalize();
        assert!(
            si.ng.dot(wn) > 0.999,
            "ng follows world winding: {:?} vs {wn:?}",
            si.ng
        );
        assert!((si.ng.length() - 1.0).abs() < 1e-5 && (si.ns.length() - 1.0).abs() < 1e-5);
        // Outward vertex normals: ns on the side of the outward object-space winding, which
        // is the side of ng unless the instance mirrors the mesh (ng follows world winding).
        let mirrored = acc.instances()[h.instance as usize]
            .transform
            .swaps_handedness();
        let side = if mirrored { -1.0 } else { 1.0 };
        assert!(side * si.ns.dot(si.ng) > 0.5, "{:?} {:?}", si.ns, si.ng);
        let at = ray.at(h.t);
        assert!(
            (si.p - at).length() < 1e-4 * (1.0 + at.length()),
            "{:?} vs {at:?}",
            si.p
        );
        assert!(si.p_error.cmpge(Vec3::ZERO).all() && si.p_error.max_element() < 1e-4);
        assert_eq!(si.uv, Vec2::new(h.b1, h.b2));
        assert_eq!(si.material, h.prim % 5);
        assert!((si.wo - (-ray.d.normalize())).length() < 1e-6);
        assert!(
            si.dpdu.is_finite()
                && si.dpdu.length() > 0.0
                && si.dpdu.dot(si.ng).abs() < 1e-3 * si.dpdu.length()
        );
        checked += 1;
    }
    assert!(checked > 500);
}

#[test]
fn degenerate_inputs() {
    let tri = MeshGeom {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        indices: vec![[0, 1, 2]],
        ..Default::default()
    };
    // One triangle.
    let one = Accel::build(
        vec![tri.clone()],
        vec![Instance {
            mesh: 0,
            transform: Transform::IDENTITY,
        }],
    );
    let down = Ray::new(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z);
    let h = one.intersect(&down).expect("hit");
    assert!((h.t - 1.0).abs() < 1e-6 && h.prim == 0);
    assert!(one.occluded(&down));
    assert!(one
        .intersect(&Ray::new(Vec3::new(0.9, 0.9, 1.0), -Vec3::Z))
        .is_none());

    // Coincident triangles, zero-area triangles and out-of-range indices mixed in.
    let mut m = MeshGeom {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::X * 2.0],
        ..Default::default()
    };
    for i in 0..1000 {
        m.indices.push(if i % 3 == 0 {
            [0, 1, 3]
        } else if i % 7 == 0 {
            [0, 9, 1]
        } else {
            [0, 1, 2]
        });
    }
    let acc = Accel::build(
        vec![m],
        vec![Instance {
            mesh: 0,
            transform: Transform::IDENTITY,
        }],
    );
    let h = acc.intersect(&down).expect("hit");
    assert!((h.t - 1.0).abs() < 1e-6);
    assert!(acc.occluded(&down));
    let mut rng = Rng::new(1, 0);
    for _ in 0..2000 {
        let ray = random_ray(&mut rng, 2.0);
        if let Some(h) = acc.intersect(&ray) {
            assert!(h.t.is_finite() && h.b1.is_finite() && h.b2.is_finite());
            let [a, b, c] = acc.mesh(0).indices[h.prim as usize];
            assert_eq!(
                [a, b, c],
                [0, 1, 2],
                "only the non-degenerate triangle is hit"
            );
        }
    }
}

#[test]
fn million_triangles_with_one_centroid() {
    let n = 1_000_000u32;
    let c = Vec3::new(0.5, -0.25, 2.0);
    let mut positions = Vec::with_capacity(3 * n as usize);
    for k in 0..n {
        let a = k as f32 * 0.618_034 * std::f32::consts::TAU;
        let q = Quat::from_axis_angle(Vec3::new(a.cos(), a.sin(), 0.3).normalize(), a * 1.7);
        let s = 0.1 + (k % 97) as f32 * 0.01;
        let offs = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(-0.5, 0.8, 0.0),
            Vec3::new(-0.5, -0.8, 0.0),
        ];
        for o in offs {
            positions.push(c + q * o * s);
        }
    }
    let mesh = MeshGeom {
        indices: (0..n).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect(),
        positions,
        ..Default::default()
    };
    let start = std::time::Instant::now();
    let acc = Accel::build(
        vec![mesh],
        vec![Instance {
            mesh: 0,
            transform: Transform::IDENTITY,
        }],
    );
    let secs = start.elapsed().as_secs_f32();
    assert!(secs < 60.0, "build took {secs} s");
    let mut rng = Rng::new(2, 0);
    for _ in 0..8 {
        let o = c + crate::sampling::warp::square_to_uniform_sphere(rng.vec2()) * 3.0;
        let target = c + (rng.vec3() - 0.5) * 0.2;
        let ray = Ray::new(o, target - o);
        let a = acc.intersect(&ray);
        let b = brute(&acc, &ray);
        assert_eq!(a.map(|h| h.t), b.map(|h| h.t));
        assert_eq!(acc.occluded(&ray), b.is_some());
    }
}

/// Distance from `p` to the triangle `t` (closest point after Ericson, "Real-Time Collision
/// Detection", §5.1.5).
fn point_triangle_distance(p: Vec3, t: [Vec3; 3]) -> f32 {
    let [a, b, c] = t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return p.distance(a);
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return p.distance(b);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return p.distance(a + ab * (d1 / (d1 - d3)));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return p.distance(c);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return p.distance(a + ac * (d2 / (d2 - d6)));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return p.distance(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    }
    let denom = 1.0 / (va + vb + vc);
    p.distance(a + ab * (vb * denom) + ac * (vc * denom))
}

#[test]
fn any_surface_near_never_misses_a_triangle_within_the_radius() {
    let mut rng = Rng::new(7, 0);
    let mesh = soup(300, &mut rng, 0.3);
    let n = mesh.indices.len() as u32;
    let instances: Vec<Instance> = transforms()
        .into_iter()
        .map(|transform| Instance { mesh: 0, transform })
        .collect();
    let count = instances.len() as u32;
    let accel = Accel::build(vec![mesh], instances);
    let (mut near, mut far, mut far_said_no) = (0, 0, 0);
    for _ in 0..3000 {
        let p = rng.vec3() * 12.0 - 6.0;
        let r = 0.02 + 0.5 * rng.f32();
        let d = (0..count)
            .flat_map(|i| (0..n).map(move |t| (i, t)))
            .map(|(i, t)| point_triangle_distance(p, accel.triangle_world(i, t)))
            .fold(f32::INFINITY, f32::min);
        let said = accel.any_surface_near(p, r);
        if d <= r {
            near += 1;
            assert!(said, "a triangle at {d} from {p} within r = {r} was missed");
        } else if d > 3.0 * r {
            far += 1;
            far_said_no += usize::from(!said);
        }
    }
    assert!(near > 50 && far > 500, "near {near}, far {far}");
    // Conservative, but not everywhere true: most points far from every triangle are told so.
    assert!(
        far_said_no * 10 > far * 8,
        "{far_said_no} of {far} far points told apart"
    );
}

/// A grid of unit squares (two triangles each) with coplanar duplicates and zero-area
/// triangles, placed twice (identity and rotated); rays aimed at its vertices and edge
/// midpoints, and along the axes through them, find the brute-force hits.
#[test]
fn grid_with_shared_edges_matches_brute_force() {
    let n = 20u32;
    let mut m = MeshGeom::default();
    for j in 0..=n {
        for i in 0..=n {
            m.positions.push(Vec3::new(i as f32, j as f32, 0.0));
        }
    }
    let v = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            m.indices.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            m.indices.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
            if (i + j) % 4 == 0 {
                m.indices.push([v(i + 1, j), v(i + 1, j + 1), v(i, j)]);
                m.indices.push([v(i, j), v(i, j), v(i + 1, j + 1)]);
            }
        }
    }
    let acc = Accel::build(
        vec![m],
        vec![
            Instance {
                mesh: 0,
                transform: Transform::IDENTITY,
            },
            Instance {
                mesh: 0,
                transform: tf(
                    Mat4::from_translation(Vec3::new(0.0, 0.0, -2.0)) * Mat4::from_rotation_x(0.3)
                ),
            },
        ],
    );
    let mut rng = Rng::new(17, 0);
    let mut hits = 0;
    for k in 0..8000 {
        let cell = |rng: &mut Rng| rng.below(n) as f32;
        let half = if k % 3 == 0 { 0.5 } else { 0.0 };
        let target = Vec3::new(cell(&mut rng) + half, cell(&mut rng), 0.0);
        let ray = if k % 2 == 0 {
            Ray::new(target + Vec3::Z * 3.0, -Vec3::Z)
        } else {
            let o = Vec3::new(
                rng.f32() * n as f32,
                rng.f32() * n as f32,
                1.0 + 5.0 * rng.f32(),
            );
            Ray::new(o, target - o)
        };
        let (a, b) = (acc.intersect(&ray), brute(&acc, &ray));
        match (a, b) {
            (None, None) => {}
            (Some(a), Some(b)) => {
                hits += 1;
                assert!(
                    (a.t - b.t).abs() <= 4.0 * f32::EPSILON * b.t,
                    "ray {k}: {a:?} vs {b:?}"
                );
            }
            _ => panic!("ray {k}: {a:?} vs brute force {b:?}"),
        }
        assert_eq!(acc.occluded(&ray), b.is_some(), "any-hit of ray {k}");
    }
    assert!(hits > 7000, "{hits}");
}
