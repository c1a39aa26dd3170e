use super::*;
use crate::geometry::shapes;
use crate::sampling::Rng;

fn hit(o: Vec3, d: Vec3, p: [Vec3; 3]) -> Option<TriHit> {
    intersect_triangle(&TriRay::new(o, d), f32::INFINITY, p[0], p[1], p[2])
}

const TRI: [Vec3; 3] = [Vec3::ZERO, Vec3::X, Vec3::Y];

#[test]
fn hits_inside_with_barycentrics_and_t() {
    let h = hit(Vec3::new(0.25, 0.5, 2.0), Vec3::new(0.0, 0.0, -2.0), TRI).expect("hit");
    assert!((h.t - 1.0).abs() < 1e-6);
    assert!((h.b1 - 0.25).abs() < 1e-6 && (h.b2 - 0.5).abs() < 1e-6);
    // Both faces are hit.
    let h = hit(Vec3::new(0.25, 0.25, -1.0), Vec3::Z, TRI).expect("back face");
    assert!((h.t - 1.0).abs() < 1e-6);
}

#[test]
fn misses_outside_behind_and_beyond_t_max() {
    assert!(hit(Vec3::new(0.8, 0.8, 1.0), -Vec3::Z, TRI).is_none());
    assert!(hit(Vec3::new(-0.1, 0.2, 1.0), -Vec3::Z, TRI).is_none());
    assert!(
        hit(Vec3::new(0.2, 0.2, 1.0), Vec3::Z, TRI).is_none(),
        "behind"
    );
    let r = TriRay::new(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z);
    assert!(
        intersect_triangle(&r, 1.0, TRI[0], TRI[1], TRI[2]).is_none(),
        "t_max is exclusive"
    );
    assert!(intersect_triangle(&r, 1.0001, TRI[0], TRI[1], TRI[2]).is_some());
}

#[test]
fn parallel_rays_miss() {
    // In the plane, through the triangle.
    assert!(hit(Vec3::new(-1.0, 0.2, 0.0), Vec3::X, TRI).is_none());
    // Parallel, above the plane.
    assert!(hit(Vec3::new(-1.0, 0.2, 0.5), Vec3::X, TRI).is_none());
    // Zero direction.
    assert!(hit(Vec3::new(0.2, 0.2, 1.0), Vec3::ZERO, TRI).is_none());
}

#[test]
fn degenerate_triangles_never_give_nan() {
    let mut rng = Rng::new(7, 0);
    let degenerate = [
        [Vec3::ZERO, Vec3::ZERO, Vec3::ZERO],
        [Vec3::ZERO, Vec3::X, Vec3::X * 2.0],
        [Vec3::ONE, Vec3::ONE, Vec3::new(1.0, 2.0, 3.0)],
        [Vec3::ZERO, Vec3::X, Vec3::X],
    ];
    for p in degenerate {
        assert!(is_degenerate(&p));
        for _ in 0..20_000 {
            let o = rng.vec3() * 4.0 - 2.0;
            let d = rng.vec3() * 2.0 - 1.0;
            // Rays aimed at the segment as well as random ones.
            let target = p[0] + (p[2] - p[0]) * rng.f32();
            for d in [d, target - o] {
                if let Some(h) = hit(o, d, p) {
                    assert!(
                        h.t.is_finite() && h.b1.is_finite() && h.b2.is_finite(),
                        "{h:?}"
                    );
                }
            }
        }
    }
    assert!(!is_degenerate(&TRI));
}

/// Rays through points on the mesh's edges and vertices (computed in floating point, so
/// off the exact edge by rounding) must hit at least one of the triangles.
#[test]
fn watertight_on_shared_edges_and_vertices() {
    let mesh = shapes::sphere(Vec3::new(0.3, -0.2, 0.1), 1.3, 17, 23);
    let tris: Vec<[Vec3; 3]> = (0..mesh.indices.len() as u32)
        .map(|t| mesh.triangle(t))
        .collect();
    let mut rng = Rng::new(11, 0);
    let mut rays = 0;
    for (ti, p) in tris.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (p[e], p[(e + 1) % 3]);
            for k in 0..6 {
                let s = if k == 0 { 0.0 } else { rng.f32() };
                let target = a + (b - a) * s;
                // From inside, and from outside in front of the triangle (a ray from
                // outside through a silhouette edge may rightly miss: the target point is
                // rounded off the edge).
                let inside = Vec3::new(0.3, -0.2, 0.1) + (rng.vec3() - 0.5) * 0.5;
                let n = face_normal(p).normalize();
                let outside = target + (n + (rng.vec3() - 0.5) * 0.6) * 3.0;
                for o in [inside, outside] {
                    let r = TriRay::new(o, target - o);
                    let n = tris
                        .iter()
                        .filter(|q| {
                            intersect_triangle(&r, f32::INFINITY, q[0], q[1], q[2]).is_some()
                        })
                        .count();
                    assert!(n >= 1, "ray through edge of triangle {ti} leaked");
                    rays += 1;
                }
            }
        }
    }
    assert!(rays > 10_000);
}

#[test]
fn watertight_on_a_quad_diagonal() {
    // Two triangles sharing the diagonal of a skewed planar quad; rays through points on
    // that diagonal (rounded, so slightly to one side of it, but always inside the quad).
    let (a, b, c, d) = (
        Vec3::new(0.1, 0.0, 0.3),
        Vec3::new(1.7, 0.2, 0.3),
        Vec3::new(1.9, 1.3, 0.3),
        Vec3::new(0.05, 1.1, 0.3),
    );
    let t1 = [a, b, c];
    let t2 = [a, c, d];
    let mut rng = Rng::new(3, 0);
    for i in 0..100_000 {
        // Interior points of the diagonal only: its ends are corners of the quad.
        let s = if i % 100 == 0 {
            0.5
        } else {
            rng.f32().max(1e-3)
        };
        let target = a + (c - a) * s;
        let o = target + Vec3::new(rng.f32() - 0.5, rng.f32() - 0.5, 1.0) * 3.0;
        let n = [t1, t2]
            .iter()
            .filter(|p| hit(o, target - o, **p).is_some())
            .count();
        assert!(n >= 1, "ray {i} through the shared edge leaked");
    }
}
