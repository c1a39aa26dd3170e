//! Photon map kd-tree (left-balanced heap, one photon per node) against
//! kiddo 6's `ImmutableKdTree` (bucketed leaves, Eytzinger stems) on the same
//! points and queries.
//!
//! * 1M photons uniform in the unit cube (10M with `PHOTON_BENCH_10M=1`);
//! * k-nearest within a fixed max radius (k = 50, 100, 200), unsorted
//!   results and reused scratch on both sides;
//! * radius queries returning ~100 photons, through a visitor on both sides;
//! * queries in random order and in Morton (Z-curve) order;
//! * build time (both parallel on all cores).
//!
//! Run: `cargo bench --bench kdtree -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;
use std::num::NonZeroUsize;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use photonmap::photon::{KdRecord, KnnScratch, Photon, PhotonF32, PhotonKdTree};

const QUERIES: usize = 10_000;

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

fn points(n: usize, seed: u64) -> Vec<[f32; 3]> {
    let mut r = Rng(seed);
    (0..n).map(|_| [r.f32(), r.f32(), r.f32()]).collect()
}

/// 30-bit Morton code of a point in [0, 1)³.
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

/// Queries away from the boundary so that the neighbourhoods are full.
fn queries(seed: u64) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    let mut r = Rng(seed);
    let random: Vec<[f32; 3]> = (0..QUERIES)
        .map(|_| {
            [
                0.05 + 0.9 * r.f32(),
                0.05 + 0.9 * r.f32(),
                0.05 + 0.9 * r.f32(),
            ]
        })
        .collect();
    let mut coherent = random.clone();
    coherent.sort_by_key(morton);
    (random, coherent)
}

fn photons(pts: &[[f32; 3]]) -> Vec<Photon> {
    pts.iter()
        .map(|p| Photon::new(Vec3::from_array(*p), Vec3::splat(1e-6), -Vec3::Z).unwrap())
        .collect()
}

fn bench_size(c: &mut Criterion, n: usize, label: &str) {
    let pts = points(n, 0x5eed);
    let (random, coherent) = queries(0xbeef);
    let ours = PhotonKdTree::build(photons(&pts));
    let ours_f32 = PhotonKdTree::build(
        photons(&pts)
            .into_iter()
            .map(PhotonF32::from)
            .collect::<Vec<_>>(),
    );
    let kiddo: ImmutableKdTree<f32, 3> = ImmutableKdTree::new_from_slice_parallel(&pts).unwrap();

    // Max radius for knn: ~2.6× the volume holding 200 photons, so every
    // query fills k; radius query: volume holding ~100 photons.
    let density = n as f32;
    let r_knn = (3.0 * 524.0 / (4.0 * std::f32::consts::PI * density)).cbrt();
    let r2_knn = r_knn * r_knn;
    let r_100 = (3.0 * 100.0 / (4.0 * std::f32::consts::PI * density)).cbrt();
    let r2_100 = r_100 * r_100;

    let orders: [(&str, &[[f32; 3]]); 2] = [("random", &random), ("morton", &coherent)];

    // Both trees must return the same neighbourhoods (as distance multisets).
    let mut scratch = KnnScratch::new();
    let mut sum_radius = 0usize;
    for q in &random[..200] {
        let mut a: Vec<f32> = ours
            .knn(Vec3::from_array(*q), 100, r2_knn, &mut scratch)
            .iter()
            .map(|nb| nb.dist2)
            .collect();
        let mut b: Vec<f32> = kiddo
            .query(q)
            .nearest_n::<SquaredEuclidean<f32>>(NonZeroUsize::new(100).unwrap())
            .within(r2_knn)
            .execute()
            .iter()
            .map(|r| r.distance)
            .collect();
        a.sort_by(f32::total_cmp);
        b.sort_by(f32::total_cmp);
        assert_eq!(a.len(), 100);
        assert_eq!(a, b, "knn mismatch against kiddo");
        let mut na = 0;
        ours.for_each_in_radius(Vec3::from_array(*q), r2_100, |_, _| na += 1);
        let mut nb = 0;
        kiddo
            .query(q)
            .within::<SquaredEuclidean<f32>>(r2_100)
            .unsorted()
            .visit(|_| nb += 1);
        assert_eq!(na, nb, "radius mismatch against kiddo");
        sum_radius += na;
    }
    eprintln!(
        "{label}: {n} photons, tree {} bytes ({} B/photon), radius query mean {:.1} photons",
        ours.memory_bytes(),
        ours.memory_bytes() / n,
        sum_radius as f64 / 200.0
    );

    for k in [50usize, 100, 200] {
        let mut g = c.benchmark_group(format!("{label}/knn k={k}"));
        g.sample_size(20);
        g.throughput(Throughput::Elements(QUERIES as u64));
        let nz = NonZeroUsize::new(k).unwrap();
        for (order, qs) in orders {
            let mut scratch = KnnScratch::with_capacity(k);
            g.bench_function(format!("ours/{order}"), |b| {
                b.iter(|| {
                    let mut acc = 0.0f32;
                    for q in qs {
                        let res = ours.knn(Vec3::from_array(*q), k, r2_knn, &mut scratch);
                        acc += res[0].dist2 + res.len() as f32;
                    }
                    black_box(acc)
                })
            });
            if k == 100 {
                g.bench_function(format!("ours-f32/{order}"), |b| {
                    b.iter(|| {
                        let mut acc = 0.0f32;
                        for q in qs {
                            let res = ours_f32.knn(Vec3::from_array(*q), k, r2_knn, &mut scratch);
                            acc += res[0].dist2 + res.len() as f32;
                        }
                        black_box(acc)
                    })
                });
            }
            let mut ks = kiddo.create_scratch::<SquaredEuclidean<f32>>();
            g.bench_function(format!("kiddo/{order}"), |b| {
                b.iter(|| {
                    let mut acc = 0.0f32;
                    for q in qs {
                        let res = kiddo
                            .query(q)
                            .nearest_n::<SquaredEuclidean<f32>>(nz)
                            .within(r2_knn)
                            .unsorted()
                            .with_scratch(&mut ks)
                            .execute();
                        acc += res[0].distance + res.len() as f32;
                    }
                    black_box(acc)
                })
            });
        }
        g.finish();
    }

    {
        let mut g = c.benchmark_group(format!("{label}/radius ~100"));
        g.sample_size(20);
        g.throughput(Throughput::Elements(QUERIES as u64));
        for (order, qs) in orders {
            g.bench_function(format!("ours/{order}"), |b| {
                b.iter(|| {
                    let mut acc = 0.0f32;
                    let mut cnt = 0usize;
                    for q in qs {
                        ours.for_each_in_radius(Vec3::from_array(*q), r2_100, |p, d2| {
                            acc += d2 + p.pos()[0];
                            cnt += 1;
                        });
                    }
                    black_box((acc, cnt))
                })
            });
            g.bench_function(format!("kiddo/{order}"), |b| {
                b.iter(|| {
                    let mut acc = 0.0f32;
                    let mut cnt = 0usize;
                    for q in qs {
                        kiddo
                            .query(q)
                            .within::<SquaredEuclidean<f32>>(r2_100)
                            .unsorted()
                            .visit(|r| {
                                acc += r.distance + r.item as f32;
                                cnt += 1;
                            });
                    }
                    black_box((acc, cnt))
                })
            });
        }
        g.finish();
    }

    {
        let mut g = c.benchmark_group(format!("{label}/build"));
        g.sample_size(10);
        g.throughput(Throughput::Elements(n as u64));
        let input = photons(&pts);
        g.bench_function("ours", |b| {
            b.iter_batched(
                || input.clone(),
                |v| black_box(PhotonKdTree::build(v)),
                BatchSize::LargeInput,
            )
        });
        g.bench_function("kiddo", |b| {
            b.iter(|| black_box(ImmutableKdTree::<f32, 3>::new_from_slice_parallel(&pts).unwrap()))
        });
        g.finish();
    }
}

fn kdtree_1m(c: &mut Criterion) {
    bench_size(c, 1_000_000, "1M");
}

fn kdtree_10m(c: &mut Criterion) {
    if std::env::var_os("PHOTON_BENCH_10M").is_some() {
        bench_size(c, 10_000_000, "10M");
    }
}

criterion_group!(benches, kdtree_1m, kdtree_10m);
criterion_main!(benches);
