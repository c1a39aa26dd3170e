//! Interleaved A/B timing of the photon kd-tree against kiddo 6, measured in
//! per-thread CPU time (`/proc/thread-self/schedstat`, Linux only) and
//! reported as the best of several rounds, so that other processes on a
//! shared machine perturb the comparison less than wall-clock timing does.
//! Same points and queries as `benches/kdtree.rs`.
//!
//! Run: `cargo run --release --example kdtree_cputime [n_photons]`

use std::hint::black_box;
use std::num::NonZeroUsize;

use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use photonmap::photon::{KnnScratch, Photon, PhotonKdTree};

struct Rng(u64);
impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// CPU time of this thread in ns.
fn cpu_ns() -> u64 {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").unwrap();
    s.split_whitespace().next().unwrap().parse().unwrap()
}

fn morton(p: &[f32; 3]) -> u32 {
    fn spread(v: u32) -> u32 {
        let mut x = v & 0x3ff;
        x = (x | (x << 16)) & 0x0300_00ff;
        x = (x | (x << 8)) & 0x0300_f00f;
        x = (x | (x << 4)) & 0x030c_30c3;
        x = (x | (x << 2)) & 0x0924_9249;
        x
    }
    let q = p.map(|c| (c.clamp(0.0, 0.999_999) * 1024.0) as u32);
    spread(q[0]) | (spread(q[1]) << 1) | (spread(q[2]) << 2)
}

/// Query sets timed together: the thread's CPU time advances in scheduler ticks (4 ms
/// here), so each timing spans several sets to keep the tick a few percent of it.
const REPEAT: usize = 4;

/// Best-of-`rounds` ns per query for `a` and `b`, interleaved.
fn ab(rounds: usize, nq: usize, mut a: impl FnMut(), mut b: impl FnMut()) -> (f64, f64) {
    let (mut ta, mut tb) = (u64::MAX, u64::MAX);
    for _ in 0..rounds {
        let t = cpu_ns();
        for _ in 0..REPEAT {
            a();
        }
        ta = ta.min(cpu_ns() - t);
        let t = cpu_ns();
        for _ in 0..REPEAT {
            b();
        }
        tb = tb.min(cpu_ns() - t);
    }
    let per = (nq * REPEAT) as f64;
    (ta as f64 / per, tb as f64 / per)
}

/// Asserts that both trees give the same results on every query before anything is timed:
/// the same multiset of neighbour distances for each k, the same for each radius query.
fn check_exact(
    tree: &PhotonKdTree<Photon>,
    kiddo: &ImmutableKdTree<f32, 3>,
    qs: &[[f32; 3]],
    r2_knn: f32,
    r2_100: f32,
) {
    let sorted = |mut v: Vec<f32>| {
        v.sort_by(f32::total_cmp);
        v
    };
    let mut s = KnnScratch::new();
    let mut total = 0usize;
    for q in qs {
        for k in [50usize, 100, 200] {
            let ours = sorted(
                tree.knn(Vec3::from_array(*q), k, r2_knn, &mut s)
                    .iter()
                    .map(|nb| nb.dist2)
                    .collect(),
            );
            let theirs = sorted(
                kiddo
                    .query(q)
                    .nearest_n::<SquaredEuclidean<f32>>(NonZeroUsize::new(k).unwrap())
                    .within(r2_knn)
                    .execute()
                    .iter()
                    .map(|nb| nb.distance)
                    .collect(),
            );
            assert_eq!(ours, theirs, "knn k={k} differs from kiddo at {q:?}");
        }
        let mut ours = Vec::new();
        tree.for_each_in_radius(Vec3::from_array(*q), r2_100, |_, d2| ours.push(d2));
        let mut theirs = Vec::new();
        kiddo
            .query(q)
            .within::<SquaredEuclidean<f32>>(r2_100)
            .unsorted()
            .visit(|nb| theirs.push(nb.distance));
        total += ours.len();
        assert_eq!(
            sorted(ours),
            sorted(theirs),
            "radius query differs from kiddo at {q:?}"
        );
    }
    println!(
        "exact: knn (k = 50, 100, 200) and radius results equal kiddo's on all {} queries \
         ({:.1} photons per radius query)",
        qs.len(),
        total as f64 / qs.len() as f64
    );
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .map_or(1_000_000, |s| s.parse().unwrap());
    let mut r = Rng(0x5eed);
    let pts: Vec<[f32; 3]> = (0..n).map(|_| [r.f32(), r.f32(), r.f32()]).collect();
    let photons: Vec<Photon> = pts
        .iter()
        .map(|p| Photon::new(Vec3::from_array(*p), Vec3::splat(1e-6), -Vec3::Z).unwrap())
        .collect();
    let tree = PhotonKdTree::build(photons.clone());
    let kiddo: ImmutableKdTree<f32, 3> = ImmutableKdTree::new_from_slice_parallel(&pts).unwrap();
    let mut r = Rng(0xbeef);
    let random: Vec<[f32; 3]> = (0..10_000)
        .map(|_| {
            [
                0.05 + 0.9 * r.f32(),
                0.05 + 0.9 * r.f32(),
                0.05 + 0.9 * r.f32(),
            ]
        })
        .collect();
    let mut morton_q = random.clone();
    morton_q.sort_by_key(morton);
    let r2_knn = (3.0 * 524.0 / (4.0 * std::f32::consts::PI * n as f32))
        .cbrt()
        .powi(2);
    let r2_100 = (3.0 * 100.0 / (4.0 * std::f32::consts::PI * n as f32))
        .cbrt()
        .powi(2);
    check_exact(&tree, &kiddo, &random, r2_knn, r2_100);
    println!("n = {n}; ns/query (best of 7, thread CPU time); ratio = kiddo time / ours");
    for (order, qs) in [("random", &random), ("morton", &morton_q)] {
        for k in [50usize, 100, 200] {
            let mut s = KnnScratch::with_capacity(k);
            let mut ks = kiddo.create_scratch::<SquaredEuclidean<f32>>();
            let nz = NonZeroUsize::new(k).unwrap();
            let (a, b) = ab(
                7,
                qs.len(),
                || {
                    for q in qs.iter() {
                        black_box(tree.knn(Vec3::from_array(*q), k, r2_knn, &mut s)[0]);
                    }
                },
                || {
                    for q in qs.iter() {
                        let res = kiddo
                            .query(q)
                            .nearest_n::<SquaredEuclidean<f32>>(nz)
                            .within(r2_knn)
                            .unsorted()
                            .with_scratch(&mut ks)
                            .execute();
                        black_box(res[0].distance);
                    }
                },
            );
            println!(
                "knn k={k:3} {order}: ours {a:7.0}  kiddo {b:7.0}  ratio {:.2}",
                b / a
            );
        }
        let (a, b) = ab(
            7,
            qs.len(),
            || {
                for q in qs.iter() {
                    let mut c = 0usize;
                    tree.for_each_in_radius(Vec3::from_array(*q), r2_100, |_, _| c += 1);
                    black_box(c);
                }
            },
            || {
                for q in qs.iter() {
                    let mut c = 0usize;
                    kiddo
                        .query(q)
                        .within::<SquaredEuclidean<f32>>(r2_100)
                        .unsorted()
                        .visit(|_| c += 1);
                    black_box(c);
                }
            },
        );
        println!(
            "radius~100 {order}: ours {a:7.0}  kiddo {b:7.0}  ratio {:.2}",
            b / a
        );
    }
}
