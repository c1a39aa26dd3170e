//! Closest-hit throughput of `geometry::Accel` against the `bvh` crate (0.13) on the same
//! ~1M-triangle scene and the same rays, single-threaded.
//!
//! Scene: a finely tessellated displaced sphere above a terrain grid.
//! Rays: (a) random origins in the scene bounds with uniform directions; (b) diffuse
//! bounces: origins on the surfaces (spawned from the first hits of (a)) with cosine
//! directions about the normal.
//!
//! The `bvh` crate is used as its documentation shows: shapes implementing `Bounded` and
//! `BHShape`, `Bvh::build_par`, and `nearest_traverse_iterator` (nearest-first, with an
//! early exit once a box starts beyond the closest hit). Both sides use the same
//! watertight triangle test, so they return the same hits.
//!
//! With the `embree-bench` feature (needs `libembree3`, Debian's `libembree-dev`), Embree 3
//! is measured beside us on the same meshes and rays: the hit counts are asserted equal, then
//! ours and Embree's passes alternate (A B A B A B) and the best of each is compared.
//!
//! Run: `cargo bench --bench bvh` (prints a summary line per ray set in Mrays/s);
//! `cargo bench --features embree-bench --bench bvh -- --test` prints the lines alone,
//! Embree's among them.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::Vec3;
use photonmap::geometry::{intersect_triangle, shapes, Accel, Instance, MeshGeom, Ray, TriRay};
use photonmap::math::{Frame, Transform};
use photonmap::sampling::{warp, Rng};
use std::time::Instant;

use bvh::aabb::{Aabb, Bounded};
use bvh::bounding_hierarchy::{BHShape, BoundingHierarchy};

#[cfg(feature = "embree-bench")]
mod embree_ffi;

const RAYS: usize = 100_000;

fn scene() -> Vec<MeshGeom> {
    let sphere = shapes::sphere_displaced(Vec3::new(0.0, 0.0, 1.3), 1.0, 450, 900, |d| {
        0.04 * (9.0 * d.x).sin() * (7.0 * d.y).cos() + 0.02 * (23.0 * d.z).sin()
    });
    let terrain = shapes::terrain(-4.0, -4.0, 8.0, 320, |x, y| {
        0.15 * (1.3 * x).sin() * (0.9 * y).cos() + 0.03 * (5.0 * x + 3.0 * y).sin()
    });
    vec![sphere, terrain]
}

struct Tri {
    p: [Vec3; 3],
    node: usize,
}

impl Bounded<f32, 3> for Tri {
    fn aabb(&self) -> Aabb<f32, 3> {
        let lo = self.p[0].min(self.p[1]).min(self.p[2]);
        let hi = self.p[0].max(self.p[1]).max(self.p[2]);
        Aabb::with_bounds(lo.to_array().into(), hi.to_array().into())
    }
}

impl BHShape<f32, 3> for Tri {
    fn set_bh_node_index(&mut self, index: usize) {
        self.node = index;
    }
    fn bh_node_index(&self) -> usize {
        self.node
    }
}

struct Peer {
    bvh: bvh::bvh::Bvh<f32, 3>,
    tris: Vec<Tri>,
}

impl Peer {
    fn closest(&self, r: &Ray) -> Option<f32> {
        let d = r.d.normalize();
        let ray = bvh::ray::Ray::new(r.o.to_array().into(), d.to_array().into());
        let tr = TriRay::new(r.o, d);
        let mut best = f32::INFINITY;
        for tri in self.bvh.nearest_traverse_iterator(&ray, &self.tris) {
            if let Some((t_in, _)) = ray.intersection_slice_for_aabb(&tri.aabb()) {
                if t_in > best {
                    break;
                }
            }
            if let Some(h) = intersect_triangle(&tr, best, tri.p[0], tri.p[1], tri.p[2]) {
                best = h.t;
            }
        }
        best.is_finite().then_some(best)
    }
}

fn rays(acc: &Accel) -> (Vec<Ray>, Vec<Ray>) {
    let b = acc.bounds();
    let mut rng = Rng::new(1, 0);
    let mut random = Vec::with_capacity(RAYS);
    let mut bounce = Vec::with_capacity(RAYS);
    while random.len() < RAYS || bounce.len() < RAYS {
        let o = b.min + (b.max - b.min) * rng.vec3();
        let ray = Ray::new(o, warp::square_to_uniform_sphere(rng.vec2()));
        if random.len() < RAYS {
            random.push(ray);
        }
        if bounce.len() < RAYS {
            if let Some(h) = acc.intersect(&ray) {
                let si = acc.interaction(&ray, &h);
                let n = if si.ng.dot(si.wo) < 0.0 {
                    -si.ng
                } else {
                    si.ng
                };
                let d =
                    Frame::from_normal(n).to_world(warp::square_to_cosine_hemisphere(rng.vec2()));
                bounce.push(si.spawn_ray(d));
            }
        }
    }
    (random, bounce)
}

fn mrays(f: impl Fn(&Ray) -> Option<f32>, rays: &[Ray]) -> (f64, usize) {
    let start = Instant::now();
    let mut hits = 0;
    for r in rays {
        hits += f(r).is_some() as usize;
    }
    (
        rays.len() as f64 / start.elapsed().as_secs_f64() / 1e6,
        hits,
    )
}

/// Ours against Embree on one ray set: the same hits (asserted), then three alternating
/// timed passes each; prints the best of each and their ratio (ours / Embree's throughput).
#[cfg(feature = "embree-bench")]
fn against_embree(name: &str, set: &[Ray], acc: &Accel, embree: &embree_ffi::EmbreeScene) {
    let ours_t: Vec<Option<f32>> = set.iter().map(|r| acc.intersect(r).map(|h| h.t)).collect();
    let theirs_t: Vec<Option<f32>> = set.iter().map(|r| embree.closest(r)).collect();
    let hits = |v: &[Option<f32>]| v.iter().filter(|t| t.is_some()).count();
    let (h0, h1) = (hits(&ours_t), hits(&theirs_t));
    assert_eq!(h0, h1, "{name}: ours and Embree's hit counts differ");
    let far = ours_t
        .iter()
        .zip(&theirs_t)
        .filter(|(a, b)| match (a, b) {
            (Some(a), Some(b)) => (a - b).abs() > 1e-4 * a.max(*b).max(1.0),
            _ => a.is_some() != b.is_some(),
        })
        .count();
    let (mut ours, mut theirs) = (0f64, 0f64);
    for _ in 0..3 {
        ours = ours.max(mrays(|r| acc.intersect(r).map(|h| h.t), set).0);
        theirs = theirs.max(mrays(|r| embree.closest(r), set).0);
    }
    eprintln!(
        "{name}: ours {ours:.3} Mrays/s, Embree 3 {theirs:.3} Mrays/s, ratio {:.2} \
         (best of 3 alternating passes; hits {h0} = {h1}, {far} rays with another distance)",
        ours / theirs
    );
}

fn bench(c: &mut Criterion) {
    let meshes = scene();
    let n_tris: usize = meshes.iter().map(|m| m.indices.len()).sum();
    let mut peer_tris: Vec<Tri> = meshes
        .iter()
        .flat_map(|m| {
            (0..m.indices.len() as u32).map(move |t| Tri {
                p: m.triangle(t),
                node: 0,
            })
        })
        .collect();
    let instances: Vec<Instance> = (0..meshes.len() as u32)
        .map(|mesh| Instance {
            mesh,
            transform: Transform::IDENTITY,
        })
        .collect();

    let t0 = Instant::now();
    let acc = Accel::build(meshes, instances);
    let ours_build = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let peer_bvh = bvh::bvh::Bvh::build_par(&mut peer_tris);
    let peer_build = t0.elapsed().as_secs_f64();
    let peer = Peer {
        bvh: peer_bvh,
        tris: peer_tris,
    };
    eprintln!(
        "scene: {n_tris} triangles; build (2 threads): ours {ours_build:.3} s, bvh 0.13 {peer_build:.3} s"
    );

    #[cfg(feature = "embree-bench")]
    let embree = {
        let t0 = Instant::now();
        let e = embree_ffi::EmbreeScene::new(&scene(), "threads=2");
        eprintln!(
            "Embree 3 build (2 threads, default quality): {:.3} s; ours / Embree build time {:.2}",
            t0.elapsed().as_secs_f64(),
            ours_build / t0.elapsed().as_secs_f64()
        );
        e
    };

    let (random, bounce) = rays(&acc);
    for (name, set) in [("random", &random), ("diffuse_bounce", &bounce)] {
        #[cfg(feature = "embree-bench")]
        against_embree(name, set, &acc, &embree);
        let (ours, h0) = mrays(|r| acc.intersect(r).map(|h| h.t * r.d.length()), set);
        let (theirs, h1) = mrays(|r| peer.closest(r), set);
        eprintln!(
            "{name}: ours {ours:.3} Mrays/s, bvh 0.13 {theirs:.3} Mrays/s, ratio {:.2}x (hits {h0} vs {h1})",
            ours / theirs
        );
        let mut g = c.benchmark_group(format!("closest_hit_{name}"));
        g.throughput(Throughput::Elements(set.len() as u64));
        g.sample_size(10);
        g.bench_function("photonmap", |b| {
            b.iter(|| set.iter().filter(|r| acc.intersect(r).is_some()).count())
        });
        g.bench_function("bvh_0.13", |b| {
            b.iter(|| set.iter().filter(|r| peer.closest(r).is_some()).count())
        });
        #[cfg(feature = "embree-bench")]
        g.bench_function("embree_3", |b| {
            b.iter(|| set.iter().filter(|r| embree.closest(r).is_some()).count())
        });
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
