use super::*;
use crate::geometry::bvh::BoxRay;
use crate::sampling::Rng;

fn boxes(n: usize, rng: &mut Rng) -> Vec<Bounds3> {
    (0..n)
        .map(|_| {
            let c = rng.vec3() * 10.0;
            let h = rng.vec3() * 0.3;
            Bounds3 {
                min: c - h,
                max: c + h,
            }
        })
        .collect()
}

fn centers(b: &[Bounds3]) -> Vec<Vec3> {
    b.iter().map(|b| b.center()).collect()
}

/// Every primitive appears once; every node's bounds contain its children or primitives.
fn check_structure(bvh: &Bvh, b: &[Bounds3]) -> usize {
    let mut seen = vec![0u32; b.len()];
    for &p in &bvh.prims {
        seen[p as usize] += 1;
    }
    assert!(seen.iter().all(|&s| s == 1), "each primitive exactly once");
    fn depth(bvh: &Bvh, i: usize, b: &[Bounds3]) -> usize {
        let n = *bvh.node(i).expect("node");
        let contains = |o: Bounds3| n.min.cmple(o.min).all() && n.max.cmpge(o.max).all();
        if n.count > 0 {
            assert!(n.count as usize <= MAX_LEAF);
            for k in n.offset as usize..(n.offset + n.count as u32) as usize {
                assert!(contains(b[bvh.prims[k] as usize]));
            }
            1
        } else {
            let (l, r) = (2 * n.offset as usize, 2 * n.offset as usize + 1);
            assert!(contains(bvh.node(l).expect("left").bounds()));
            assert!(contains(bvh.node(r).expect("right").bounds()));
            1 + depth(bvh, l, b).max(depth(bvh, r, b))
        }
    }
    depth(bvh, 0, b)
}

#[test]
fn structure_is_valid_and_deterministic() {
    let mut rng = Rng::new(1, 0);
    let b = boxes(50_000, &mut rng);
    let bvh = Bvh::build(&b, &centers(&b));
    let d = check_structure(&bvh, &b);
    assert!(d < 64, "depth {d}");
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map(|p| p.install(|| Bvh::build(&b, &centers(&b))));
    if let Ok(single) = single {
        assert_eq!(single, bvh, "same tree for 1 and N threads");
    }
}

#[test]
fn empty_and_single() {
    let e = Bvh::build(&[], &[]);
    assert!(e.is_empty());
    let mut t = f32::INFINITY;
    assert!(!e.traverse(&BoxRay::new(Vec3::ZERO, Vec3::X), &mut t, |_, _, _| true));
    let one = [Bounds3 {
        min: Vec3::ZERO,
        max: Vec3::ONE,
    }];
    let bvh = Bvh::build(&one, &centers(&one));
    assert_eq!(bvh.pairs.len(), 1);
    assert_eq!(bvh.prims, vec![0]);
    // Empty and NaN bounds are left out.
    let bad = [
        Bounds3::EMPTY,
        Bounds3 {
            min: Vec3::NAN,
            max: Vec3::ONE,
        },
        one[0],
    ];
    let bvh = Bvh::build(&bad, &centers(&bad));
    assert_eq!(bvh.prims, vec![2]);
}

#[test]
fn identical_centroids_terminate_balanced() {
    let n = 1_000_000;
    let b = vec![
        Bounds3 {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0)
        };
        n
    ];
    let bvh = Bvh::build(&b, &centers(&b));
    let d = check_structure(&bvh, &b);
    assert!(d <= 22, "depth {d} for {n} coincident primitives");
}

#[test]
fn traversal_finds_every_box_hit() {
    let mut rng = Rng::new(5, 0);
    let b = boxes(3000, &mut rng);
    let bvh = Bvh::build(&b, &centers(&b));
    for _ in 0..2000 {
        let o = rng.vec3() * 12.0 - 1.0;
        let d = rng.vec3() * 2.0 - 1.0;
        let r = BoxRay::new(o, d);
        let mut found = vec![false; b.len()];
        let mut t = f32::INFINITY;
        bvh.traverse(&r, &mut t, |first, count, _| {
            for k in first..first + count {
                found[bvh.prims[k] as usize] = true;
            }
            false
        });
        for (i, bb) in b.iter().enumerate() {
            // Reference slab test in f64.
            let mut t0 = 0.0f64;
            let mut t1 = f64::INFINITY;
            for a in 0..3 {
                let inv = 1.0 / d[a] as f64;
                let (mut n, mut f) = (
                    (bb.min[a] - o[a]) as f64 * inv,
                    (bb.max[a] - o[a]) as f64 * inv,
                );
                if n > f {
                    std::mem::swap(&mut n, &mut f);
                }
                t0 = t0.max(n);
                t1 = t1.min(f);
            }
            if t0 < t1 * (1.0 - 1e-6) {
                assert!(found[i], "box {i} missed");
            }
        }
    }
}
