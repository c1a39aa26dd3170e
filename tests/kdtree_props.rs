//! Property tests: the photon kd-tree queries agree with brute force on
//! random, clustered and degenerate (coplanar, coincident, collinear,
//! duplicated, lattice) point sets, for both photon record types. Ties make
//! the identity of the k-th neighbour ambiguous, so k-nearest results are
//! compared as multisets of squared distances; radius results are compared
//! as exact sets of (distance, position).

use glam::Vec3;
use photonmap::photon::{KnnScratch, Photon, PhotonF32, PhotonKdTree, PhotonRecord};
use proptest::prelude::*;

fn d2(q: Vec3, p: &[f32; 3]) -> f32 {
    let dx = q.x - p[0];
    let dy = q.y - p[1];
    let dz = q.z - p[2];
    dx * dx + dy * dy + dz * dz
}

fn check<P: PhotonRecord>(photons: Vec<P>, queries: &[Vec3], k: usize, r2: f32) {
    let original = photons.clone();
    let tree = PhotonKdTree::build(photons);
    assert_eq!(tree.len(), original.len());
    let mut scratch = KnnScratch::new();
    for &q in queries {
        let mut want: Vec<f32> = original
            .iter()
            .map(|p| d2(q, p.pos()))
            .filter(|&d| d <= r2)
            .collect();
        want.sort_by(f32::total_cmp);
        let all_within = want.clone();
        want.truncate(k);

        let res = tree.knn(q, k, r2, &mut scratch);
        let mut got: Vec<f32> = res
            .iter()
            .map(|nb| {
                assert_eq!(d2(q, tree.get(nb.index).pos()), nb.dist2);
                nb.dist2
            })
            .collect();
        got.sort_by(f32::total_cmp);
        assert_eq!(got, want, "knn q={q} k={k} r2={r2}");

        let mut got: Vec<(f32, [u32; 3])> = Vec::new();
        tree.for_each_in_radius(q, r2, |p, d| got.push((d, p.pos().map(f32::to_bits))));
        let mut want: Vec<(f32, [u32; 3])> = original
            .iter()
            .map(|p| (d2(q, p.pos()), p.pos().map(f32::to_bits)))
            .filter(|x| x.0 <= r2)
            .collect();
        let key =
            |a: &(f32, [u32; 3]), b: &(f32, [u32; 3])| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
        got.sort_by(key);
        want.sort_by(key);
        assert_eq!(got.len(), all_within.len());
        assert_eq!(got, want, "radius q={q} r2={r2}");
    }
}

fn check_both(points: &[Vec3], queries: &[Vec3], k: usize, r2: f32) {
    let dir = Vec3::new(0.1, -0.7, -0.3);
    let a: Vec<Photon> = points
        .iter()
        .map(|&p| Photon::new(p, Vec3::ONE, dir).unwrap())
        .collect();
    let b: Vec<PhotonF32> = points
        .iter()
        .map(|&p| PhotonF32::new(p, Vec3::ONE, dir).unwrap())
        .collect();
    check(a, queries, k, r2);
    check(b, queries, k, r2);
}

fn vec3(range: std::ops::Range<f32>) -> impl Strategy<Value = Vec3> {
    (range.clone(), range.clone(), range).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// Coordinates drawn from a handful of values: lattices with many exact
/// ties in coordinates and in distances, and many duplicates.
fn lattice() -> impl Strategy<Value = Vec3> {
    (0i32..5, 0i32..5, 0i32..5).prop_map(|(x, y, z)| Vec3::new(x as f32, y as f32, z as f32))
}

fn radius2() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(0.0f32),
        Just(f32::INFINITY),
        Just(1.0f32),
        Just(2.0f32),
        0.0f32..4.0,
    ]
}

fn k() -> impl Strategy<Value = usize> {
    prop_oneof![Just(0usize), Just(1usize), 1usize..40, 100usize..700]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn random_points(points in prop::collection::vec(vec3(-3.0..3.0), 0..600),
                     queries in prop::collection::vec(vec3(-4.0..4.0), 1..6),
                     k in k(), r2 in radius2()) {
        check_both(&points, &queries, k, r2);
    }

    #[test]
    fn lattice_points_with_ties(points in prop::collection::vec(lattice(), 0..600),
                                queries in prop::collection::vec(lattice(), 1..6),
                                half in prop::bool::ANY,
                                k in k(), r2 in radius2()) {
        // Lattice and half-lattice queries: equal distances everywhere.
        let shift = if half { Vec3::splat(0.5) } else { Vec3::ZERO };
        let queries: Vec<Vec3> = queries.iter().map(|&q| q + shift).collect();
        check_both(&points, &queries, k, r2);
    }

    #[test]
    fn clustered_points(centres in prop::collection::vec(vec3(-10.0..10.0), 1..5),
                        offsets in prop::collection::vec((0usize..5, vec3(-0.01..0.01)), 1..600),
                        q in vec3(-10.0..10.0),
                        k in k(), r2 in prop_oneof![Just(1e-4f32), Just(0.01f32), Just(f32::INFINITY)]) {
        let points: Vec<Vec3> = offsets.iter().map(|&(c, o)| centres[c % centres.len()] + o).collect();
        let queries = [q, centres[0], centres[0] + Vec3::splat(0.005)];
        check_both(&points, &queries, k, r2);
    }

    #[test]
    fn coplanar_points(xy in prop::collection::vec((-1.0f32..1.0, -1.0f32..1.0), 1..600),
                       z in -5.0f32..5.0,
                       q in vec3(-1.0..1.0),
                       k in k(), r2 in radius2()) {
        let points: Vec<Vec3> = xy.iter().map(|&(x, y)| Vec3::new(x, y, z)).collect();
        let queries = [q, Vec3::new(q.x, q.y, z)];
        check_both(&points, &queries, k, r2);
    }

    #[test]
    fn coincident_and_collinear(n in 1usize..600,
                                p in vec3(-2.0..2.0),
                                dir in vec3(-1.0..1.0),
                                ts in prop::collection::vec(0u8..20, 1..600),
                                q in vec3(-2.0..2.0),
                                k in k(), r2 in radius2()) {
        let coincident = vec![p; n];
        check_both(&coincident, &[p, q], k, r2);
        let collinear: Vec<Vec3> = ts.iter().map(|&t| p + dir * (t as f32 * 0.1)).collect();
        check_both(&collinear, &[p, q, p + dir * 0.55], k, r2);
    }
}
