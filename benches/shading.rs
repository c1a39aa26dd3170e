//! Shading cost per shading point: a 20-node graph (procedural textures, Bump, Layer Weight,
//! a Mix Shader of two Principled BSDFs) against the constant Principled BSDF it would be
//! without nodes, each building the BSDF at the same 4,096 points.
//!
//! Run: `cargo bench --bench shading -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::{Vec2, Vec3};
use photonmap::materials::graph::point::ShadingPoint;
use photonmap::materials::graph::{ShaderGraph, Want};
use photonmap::materials::Material;
use photonmap::math::Frame;
use photonmap::scene::graph_desc::GraphDesc;

const POINTS: usize = 4096;

fn points() -> Vec<ShadingPoint> {
    let mut s = 0x9e37_79b9_7f4a_7c15u64;
    let mut f = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..POINTS)
        .map(|_| {
            let mut sp = ShadingPoint::at(
                Vec3::new(4.0 * f() - 2.0, 4.0 * f() - 2.0, f()),
                Vec3::Z,
                Vec2::new(f(), f()),
            );
            sp.wo = Vec3::new(f() - 0.5, f() - 0.5, 1.0).normalize();
            sp.dpdu = Vec3::X;
            sp.dpdv = Vec3::Y;
            sp
        })
        .collect()
}

fn graph_20() -> GraphDesc {
    serde_json::from_value(serde_json::json!({
        "name": "twenty",
        "nodes": [
            {"type": "tex_coord"},
            {"type": "mapping", "inputs": {"vector": {"node": 0, "output": "object"},
                                           "scale": [1.0, 6.0, 1.0]}},
            {"type": "noise_texture", "inputs": {"vector": {"node": 1, "output": "vector"},
                                                 "scale": 3.0, "detail": 4.0}},
            {"type": "voronoi_texture", "inputs": {"vector": {"node": 0, "output": "object"}}},
            {"type": "checker_texture", "inputs": {"vector": {"node": 0, "output": "uv"}}},
            {"type": "invert", "inputs": {"color": {"node": 3, "output": "color"}}},
            {"type": "separate_xyz", "inputs": {"vector": {"node": 2, "output": "color"}}},
            {"type": "combine_xyz", "inputs": {"x": {"node": 6, "output": "y"},
                                               "y": {"node": 6, "output": "x"},
                                               "z": {"node": 4, "output": "fac"}}},
            {"type": "wave_texture", "inputs": {"vector": {"node": 7, "output": "vector"}}},
            {"type": "gradient_texture", "inputs": {"vector": {"node": 0, "output": "generated"}}},
            {"type": "magic_texture", "inputs": {"vector": {"node": 0, "output": "generated"}}},
            {"type": "layer_weight", "inputs": {"blend": 0.3}},
            {"type": "noise_texture", "inputs": {"scale": 8.0}},
            {"type": "bump", "inputs": {"height": {"node": 12, "output": "fac"},
                                        "distance": 0.05}},
            {"type": "value", "params": {"value": 0.4}},
            {"type": "rgb", "params": {"color": [0.9, 0.5, 0.2]}},
            {"type": "principled", "inputs": {"base_color": {"node": 8, "output": "color"},
                                               "roughness": {"node": 9, "output": "fac"},
                                               "normal": {"node": 13, "output": "normal"}}},
            {"type": "principled", "inputs": {"base_color": {"node": 5, "output": "color"},
                                               "metallic": {"node": 14, "output": "value"},
                                               "coat_tint": {"node": 15, "output": "color"},
                                               "normal": {"node": 13, "output": "normal"}}},
            {"type": "mix_shader", "inputs": {"fac": {"node": 11, "output": "fresnel"},
                                              "shader1": {"node": 16}, "shader2": {"node": 17}}},
            {"type": "geometry"}
        ],
        "surface": {"node": 18}
    }))
    .expect("the bench graph")
}

fn bench(c: &mut Criterion) {
    let pts = points();
    let graph = ShaderGraph::new(&graph_20(), "/materials/0", 0).expect("compiles");
    let constant = Material::from_desc(
        &serde_json::from_value(serde_json::json!({
        "type": "principled", "base_color": [0.8, 0.5, 0.2], "roughness": 0.4}))
        .unwrap(),
    );
    let mut g = c.benchmark_group("shading");
    g.throughput(Throughput::Elements(POINTS as u64));
    g.bench_function("constant principled", |b| {
        b.iter(|| {
            for sp in &pts {
                black_box(constant.bsdf(Frame::from_normal_tangent(sp.n, sp.dpdu), sp.uv, &[]));
            }
        })
    });
    g.bench_function(
        format!("20-node graph ({} instructions)", graph.instructions()),
        |b| {
            b.iter(|| {
                for sp in &pts {
                    black_box(graph.shade(sp, &[], Want::All));
                }
            })
        },
    );
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
