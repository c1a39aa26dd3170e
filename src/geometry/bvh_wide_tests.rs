use super::*;
use crate::geometry::bvh::Bvh;
use crate::geometry::triangle::{intersect_triangle, TriRay};
use crate::sampling::Rng;

fn tri_bounds(tris: &[[Vec3; 3]]) -> (Vec<Bounds3>, Vec<Vec3>) {
    let b: Vec<Bounds3> = tris
        .iter()
        .map(|t| {
            let mut b = Bounds3::from_point(t[0]);
            b.extend(t[1]);
            b.extend(t[2]);
            b
        })
        .collect();
    let c = b.iter().map(|b| b.center()).collect();
    (b, c)
}

/// A grid of `n × n` unit squares in the plane `z = 0`, two triangles each, so that many
/// edges and vertices are shared and rays can be aimed exactly at them; every fifth square
/// is also covered by a coplanar duplicate (exact ties) and a zero-area triangle.
fn grid(n: u32) -> Vec<[Vec3; 3]> {
    let mut tris = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (i as f32, j as f32);
            let p = |dx: f32, dy: f32| Vec3::new(x + dx, y + dy, 0.0);
            tris.push([p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0)]);
            tris.push([p(0.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)]);
            if (i + j) % 5 == 0 {
                tris.push([p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0)]);
                tris.push([p(0.0, 0.0), p(0.5, 0.5), p(1.0, 1.0)]);
            }
        }
    }
    tris
}

/// Random triangles of size about `size` in the cube [0, 10]³, some of them coplanar
/// copies of others moved within their plane.
fn soup(n: usize, size: f32, rng: &mut Rng) -> Vec<[Vec3; 3]> {
    let mut tris: Vec<[Vec3; 3]> = Vec::new();
    while tris.len() < n {
        let c = rng.vec3() * 10.0;
        let t = [
            c + (rng.vec3() - 0.5) * size,
            c + (rng.vec3() - 0.5) * size,
            c + (rng.vec3() - 0.5) * size,
        ];
        tris.push(t);
        if rng.f32() < 0.1 {
            let (u, v) = (rng.f32() * 0.3, rng.f32() * 0.3);
            let shift = (t[1] - t[0]) * u + (t[2] - t[0]) * v;
            tris.push(t.map(|p| p + shift));
        }
    }
    tris
}

/// Rays: random ones, axis-aligned ones through grid vertices and edge midpoints (zero
/// direction components), and rays aimed at vertices and edge midpoints of the grid.
fn rays(rng: &mut Rng, n: usize, extent: f32) -> Vec<(Vec3, Vec3)> {
    let mut out = Vec::new();
    for k in 0..n {
        let cell = |rng: &mut Rng| (rng.f32() * extent).floor();
        match k % 4 {
            0 => out.push((rng.vec3() * (extent + 2.0) - 1.0, rng.vec3() * 2.0 - 1.0)),
            1 => {
                let (x, y) = (cell(rng), cell(rng));
                let h = if k % 8 == 1 { 0.5 } else { 0.0 };
                out.push((Vec3::new(x + h, y, 3.0), Vec3::new(0.0, 0.0, -1.0)));
            }
            2 => {
                let target = Vec3::new(cell(rng) + 0.5, cell(rng) + 0.5, 0.0);
                let o = Vec3::new(rng.f32(), rng.f32(), 1.0) * extent;
                out.push((o, target - o));
            }
            _ => {
                let target = Vec3::new(cell(rng), cell(rng), 0.0);
                let o = Vec3::new(rng.f32(), rng.f32(), 0.5) * extent;
                out.push((o, target - o));
            }
        }
    }
    out
}

/// Closest hit through a traversal: the leaves visited with the `t_max` each saw, and the
/// hit (t bits, leaf-order index, barycentric bits).
type Walk = (Vec<(usize, usize, u32)>, Option<(u32, usize, u32, u32)>);

fn walk(
    traverse: impl Fn(&BoxRay, &mut f32, &mut dyn FnMut(usize, usize, &mut f32) -> bool) -> bool,
    tris: &[[Vec3; 3]],
    order: &[u32],
    o: Vec3,
    d: Vec3,
    t_max: f32,
) -> Walk {
    let tr = TriRay::new(o, d);
    let mut visits = Vec::new();
    let mut best = None;
    let mut t = t_max;
    traverse(&BoxRay::new(o, d), &mut t, &mut |first, count, t_max| {
        visits.push((first, count, t_max.to_bits()));
        for k in first..first + count {
            let p = tris[order[k] as usize];
            if let Some(h) = intersect_triangle(&tr, *t_max, p[0], p[1], p[2]) {
                *t_max = h.t;
                best = Some((h.t.to_bits(), k, h.b1.to_bits(), h.b2.to_bits()));
            }
        }
        false
    });
    (visits, best)
}

/// The wide walk visits the same leaves, with the same `t_max`, as the binary walk, and
/// returns the same hit; both agree with brute force: the same hit or miss, at the same
/// `t` up to a few ulps (a triangle in the plane of its box's face can be hit an ulp or two
/// before the box's computed entry distance, so that a subtree is skipped for a hit at a
/// `t` an ulp or two farther; the binary walk does the same).
fn same_walks(tris: &[[Vec3; 3]], rays: &[(Vec3, Vec3)]) -> usize {
    let (b, c) = tri_bounds(tris);
    let bin = Bvh::build(&b, &c);
    let wide = WideBvh::build(&b, &c);
    assert_eq!(bin.prims, wide.prims, "same leaf order");
    let mut hits = 0;
    for (i, &(o, d)) in rays.iter().enumerate() {
        for t_max in [f32::INFINITY, 4.0] {
            let a = walk(
                |r, t, f| bin.traverse(r, t, f),
                tris,
                &bin.prims,
                o,
                d,
                t_max,
            );
            let w = walk(
                |r, t, f| wide.traverse(r, t, f),
                tris,
                &wide.prims,
                o,
                d,
                t_max,
            );
            assert_eq!(a, w, "ray {i}: {o} {d}");
            // Brute force: the smallest t over all triangles.
            let tr = TriRay::new(o, d);
            let brute = tris
                .iter()
                .filter_map(|p| intersect_triangle(&tr, t_max, p[0], p[1], p[2]))
                .map(|h| h.t)
                .fold(f32::INFINITY, f32::min);
            match w.1 {
                Some((t, k, ..)) => {
                    hits += 1;
                    let t = f32::from_bits(t);
                    assert!(
                        t >= brute && t <= brute * (1.0 + 4.0 * f32::EPSILON),
                        "ray {i}: closest t {t} vs {brute}"
                    );
                    let p = tris[wide.prims[k] as usize];
                    assert!(intersect_triangle(&tr, t_max, p[0], p[1], p[2]).is_some());
                }
                None => assert_eq!(brute, f32::INFINITY, "ray {i}: missed a hit"),
            }
        }
    }
    hits
}

#[test]
fn wide_walk_equals_binary_walk_on_a_grid_with_shared_edges() {
    let tris = grid(24);
    let mut rng = Rng::new(3, 0);
    let hits = same_walks(&tris, &rays(&mut rng, 4000, 24.0));
    assert!(hits > 3000, "{hits}");
}

#[test]
fn wide_walk_equals_binary_walk_on_random_soups() {
    let mut rng = Rng::new(11, 0);
    for (n, size) in [
        (1, 2.0),
        (3, 2.0),
        (9, 1.0),
        (40, 1.0),
        (700, 0.8),
        (5000, 0.3),
    ] {
        let tris = soup(n, size, &mut rng);
        let rays = rays(&mut rng, 1500, 10.0);
        same_walks(&tris, &rays);
    }
}

/// Every primitive appears once; each lane's box contains its subtree; empty lanes only
/// follow a leaf half; the halves' unions are the binary nodes' boxes.
#[test]
fn structure_is_valid_and_deterministic() {
    let mut rng = Rng::new(2, 0);
    let tris = soup(30_000, 0.4, &mut rng);
    let (b, c) = tri_bounds(&tris);
    let wide = WideBvh::build(&b, &c);
    let mut seen = vec![0u32; b.len()];
    for &p in &wide.prims {
        seen[p as usize] += 1;
    }
    assert!(seen.iter().all(|&s| s == 1));
    fn check(w: &WideBvh, i: usize, outer: Bounds3, b: &[Bounds3]) -> usize {
        let n = &w.nodes[i];
        let inside = |o: &Bounds3| outer.min.cmple(o.min).all() && outer.max.cmpge(o.max).all();
        let mut depth = 0;
        for s in 0..4 {
            if n.count[s] == EMPTY_LANE {
                assert!(s % 2 == 1 && n.count[s - 1] != INTERIOR, "empty lane {s}");
                assert!(n.lane_bounds(s).is_empty());
                continue;
            }
            let lb = n.lane_bounds(s);
            assert!(inside(&lb));
            if n.count[s] == INTERIOR {
                depth = depth.max(check(w, n.child[s] as usize, lb, b));
            } else {
                let first = n.child[s] as usize;
                for k in first..first + n.count[s] as usize {
                    let pb = b[w.prims[k] as usize];
                    assert!(lb.min.cmple(pb.min).all() && lb.max.cmpge(pb.max).all());
                }
            }
        }
        1 + depth
    }
    let depth = check(&wide, 0, wide.root, &b);
    assert!(depth <= 32, "depth {depth}");
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map(|p| p.install(|| WideBvh::build(&b, &c)));
    if let Ok(single) = single {
        assert_eq!(single, wide, "same tree for 1 and N threads");
    }
}

#[test]
fn empty_single_and_small() {
    let e = WideBvh::build(&[], &[]);
    assert!(e.is_empty());
    assert!(e.bounds().is_empty());
    let mut t = f32::INFINITY;
    assert!(!e.traverse(&BoxRay::new(Vec3::ZERO, Vec3::X), &mut t, |_, _, _| true));
    assert!(!e.any_overlapping(&Bounds3::from_point(Vec3::ZERO), |_, _| true));
    let one = [Bounds3 {
        min: Vec3::ZERO,
        max: Vec3::ONE,
    }];
    let w = WideBvh::build(&one, &[]);
    assert_eq!(
        (w.nodes.len(), w.root_leaf, w.prims.clone()),
        (0, 1, vec![0])
    );
    let r = BoxRay::new(Vec3::new(0.5, 0.5, -1.0), Vec3::Z);
    let mut t = f32::INFINITY;
    assert!(w.traverse(&r, &mut t, |first, count, _| (first, count) == (0, 1)));
    assert!(w.any_overlapping(&Bounds3::from_point(Vec3::splat(0.5)), |_, _| true));
    let mut t = f32::INFINITY;
    let away = BoxRay::new(Vec3::new(0.5, 0.5, -1.0), -Vec3::Z);
    assert!(!w.traverse(&away, &mut t, |_, _, _| true));
    // Empty and NaN bounds are left out.
    let bad = [
        Bounds3::EMPTY,
        Bounds3 {
            min: Vec3::NAN,
            max: Vec3::ONE,
        },
        one[0],
    ];
    assert_eq!(WideBvh::build(&bad, &[]).prims, vec![2]);
}

type LeafFn<'a> = dyn FnMut(usize, usize) -> bool + 'a;

/// The overlap query finds exactly the leaves of the binary query.
#[test]
fn overlap_query_matches_the_binary_one() {
    let mut rng = Rng::new(8, 0);
    let tris = soup(4000, 0.5, &mut rng);
    let (b, c) = tri_bounds(&tris);
    let bin = Bvh::build(&b, &c);
    let wide = WideBvh::build(&b, &c);
    for _ in 0..500 {
        let p = rng.vec3() * 10.0;
        let q = Bounds3 {
            min: p - Vec3::splat(rng.f32()),
            max: p + Vec3::splat(rng.f32()),
        };
        let leaves = |f: &dyn Fn(&mut LeafFn)| {
            let mut v = Vec::new();
            f(&mut |first, count| {
                v.push((first, count));
                false
            });
            v.sort_unstable();
            v
        };
        let a = leaves(&|cb| {
            bin.any_overlapping(&q, cb);
        });
        let w = leaves(&|cb| {
            wide.any_overlapping(&q, cb);
        });
        assert_eq!(a, w);
    }
}

/// Lanes give the scalar test's entry distance and hit decision, bit for bit, including
/// for boxes with a face in the plane of the origin and zero direction components.
#[test]
fn lane_test_equals_scalar_test() {
    use super::super::bvh_simd::{rows, WideRay};
    let mut rng = Rng::new(4, 0);
    let pick = |rng: &mut Rng| [0.0f32, -0.0, 1.0, -1.0, 0.5][(rng.f32() * 5.0) as usize];
    for _ in 0..20_000 {
        let mut n = WideNode::default();
        for s in 0..3 {
            let a = Vec3::new(pick(&mut rng), pick(&mut rng), pick(&mut rng));
            let e = Vec3::new(pick(&mut rng), pick(&mut rng), pick(&mut rng)).abs();
            for ax in 0..3 {
                n.b[ax][s] = a[ax];
                n.b[ax + 3][s] = a[ax] + e[ax];
            }
        }
        let o = Vec3::new(pick(&mut rng), pick(&mut rng), pick(&mut rng));
        let d = Vec3::new(pick(&mut rng), pick(&mut rng), pick(&mut rng));
        let t_max = [f32::INFINITY, 0.5, 2.0][(rng.f32() * 3.0) as usize];
        let r = BoxRay::new(o, d);
        let (t, mask) = WideRay::new(&r).test(&rows(&n.b), t_max);
        let t = t.to_array();
        for (s, &ts) in t.iter().enumerate() {
            let lb = n.lane_bounds(s);
            let scalar = hit_bounds(lb.min, lb.max, &r, t_max);
            let hit = mask >> s & 1 == 1;
            assert_eq!(hit, scalar != f32::INFINITY, "lane {s} {o} {d} {lb:?}");
            if hit {
                assert_eq!(ts.to_bits(), scalar.to_bits(), "lane {s} {o} {d} {lb:?}");
            }
        }
    }
}
