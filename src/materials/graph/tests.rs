//! The compiler and the closure sum, on small graphs with known answers.

use super::point::ShadingPoint;
use super::{ShaderGraph, Want};
use crate::error::Error;
use crate::materials::Material;
use crate::scene::graph_desc::GraphDesc;
use glam::{Vec2, Vec3};

fn graph(v: serde_json::Value) -> GraphDesc {
    serde_json::from_value(v).expect("graph IR")
}

fn point() -> ShadingPoint {
    let mut sp = ShadingPoint::at(Vec3::new(0.2, 0.4, 0.0), Vec3::Z, Vec2::new(0.25, 0.75));
    sp.wo = Vec3::new(0.6, 0.0, 0.8);
    sp.dpdu = Vec3::X;
    sp.dpdv = Vec3::Y;
    sp
}

fn err_of(g: &GraphDesc) -> (String, String) {
    match ShaderGraph::new(g, "/materials/0", 1) {
        Err(Error::InvalidScene {
            pointer, message, ..
        }) => (pointer, message),
        other => panic!("expected an invalid-scene error, got {other:?}"),
    }
}

#[test]
fn plastic_mixes_by_the_layer_weight_fresnel() {
    let g = graph(serde_json::json!({
        "name": "plastic",
        "nodes": [
            {"type": "layer_weight", "inputs": {"blend": 0.3}},
            {"type": "diffuse", "inputs": {"color": [0.8, 0.1, 0.1]}},
            {"type": "glossy", "inputs": {"roughness": 0.3}},
            {"type": "mix_shader", "inputs": {
                "fac": {"node": 0, "output": "fresnel"},
                "shader1": {"node": 1}, "shader2": {"node": 2}}}
        ],
        "surface": {"node": 3}
    }));
    let sg = ShaderGraph::new(&g, "/materials/0", 0).unwrap();
    let sp = point();
    let (fres, _) = super::geometry_nodes::layer_weight(&sp, 0.3, None);
    assert!(fres > 0.0 && fres < 1.0);
    let sh = sg.shade(&sp, &[], Want::All);
    let w: Vec<f32> = sh.bsdf.lobes().map(|(w, _)| w).collect();
    assert_eq!(w.len(), 2);
    assert!(
        (w[0] - (1.0 - fres)).abs() < 1e-6 && (w[1] - fres).abs() < 1e-6,
        "{w:?} vs {fres}"
    );
    assert_eq!(sh.emission, Vec3::ZERO);
    assert_eq!(sh.transparency, Vec3::ZERO);
    // Glossy at roughness 0.3 is not near-specular; nothing emits or passes.
    assert!(!sg.has_specular() && !sg.is_emissive() && !sg.can_pass());
}

#[test]
fn a_constant_graph_is_the_plain_material() {
    let g = graph(serde_json::json!({
        "name": "red",
        "nodes": [
            {"type": "value", "params": {"value": 0.25}},
            {"type": "principled", "inputs": {"base_color": [0.8, 0.2, 0.1],
                                               "roughness": {"node": 0, "output": "value"}}}
        ],
        "surface": {"node": 1}
    }));
    match Material::from_graph(&g, "/materials/0", 0) {
        Material::Principled(p) => {
            assert_eq!(p.name, "red");
            assert_eq!(p.roughness, crate::materials::FloatParam::Const(0.25));
        }
        other => panic!("expected a plain Principled, got {other:?}"),
    }
}

#[test]
fn alpha_and_transparent_give_transparency_and_scale_the_rest() {
    let g = graph(serde_json::json!({
        "name": "leaf",
        "nodes": [
            {"type": "principled", "inputs": {"alpha": 0.25, "emission_strength": 2.0,
                                               "emission_color": [1.0, 1.0, 1.0]}}
        ],
        "surface": {"node": 0}
    }));
    let sg = ShaderGraph::new(&g, "/materials/0", 0).unwrap();
    assert!(sg.can_pass() && sg.is_emissive());
    let sh = sg.shade(&point(), &[], Want::All);
    assert!((sh.transparency - Vec3::splat(0.75)).length() < 1e-6);
    assert!((sh.emission - Vec3::splat(0.5)).length() < 1e-6);
    let total: f32 = sh.bsdf.lobes().map(|(w, _)| w).sum();
    // The default Principled is a coat lobe and a diffuse base, each at weight 1 * alpha.
    assert!(
        sh.bsdf.lobes().all(|(w, _)| (w - 0.25).abs() < 1e-6),
        "{total}"
    );
}

#[test]
fn unread_nodes_are_not_compiled_and_constants_fold() {
    let g = graph(serde_json::json!({
        "name": "m",
        "nodes": [
            {"type": "tex_coord"},
            {"type": "invert", "inputs": {"fac": 1.0, "color": [0.2, 0.3, 0.4]}},
            {"type": "diffuse", "inputs": {"color": {"node": 1, "output": "color"}}},
            {"type": "geometry"}
        ],
        "surface": {"node": 2}
    }));
    let sg = ShaderGraph::new(&g, "/materials/0", 0).unwrap();
    assert_eq!(sg.instructions(), 0);
    let (_, v) = sg.as_constant().unwrap();
    assert!((v[0] - Vec3::new(0.8, 0.7, 0.6)).length() < 1e-6);
}

#[test]
fn bump_uses_the_height_at_offset_points() {
    // Height = the x of the position: the normal tilts towards -x by atan(distance) (small
    // enough that the mirror direction of `wo` stays above the surface).
    let g = graph(serde_json::json!({
        "name": "bumpy",
        "nodes": [
            {"type": "geometry"},
            {"type": "separate_xyz", "inputs": {"vector": {"node": 0, "output": "position"}}},
            {"type": "bump", "inputs": {"height": {"node": 1, "output": "x"}, "distance": 0.2}},
            {"type": "diffuse", "inputs": {"normal": {"node": 2, "output": "normal"}}}
        ],
        "surface": {"node": 3}
    }));
    let sg = ShaderGraph::new(&g, "/materials/0", 0).unwrap();
    let sh = sg.shade(&point(), &[], Want::All);
    let n = sh.bsdf.frame().n;
    let want = Vec3::new(-0.2, 0.0, 1.0).normalize();
    assert!((n - want).length() < 1e-3, "{n}");
}

/// A diffuse surface displaced by `height` = 0.2 x (world or object space) and `layer`: a
/// Layer Weight read by the closure's colour, which must see the displaced normal.
fn displaced(space: &str) -> GraphDesc {
    graph(serde_json::json!({
        "name": "displaced",
        "nodes": [
            {"type": "geometry"},
            {"type": "separate_xyz", "inputs": {"vector": {"node": 0, "output": "position"}}},
            {"type": "displacement", "params": {"space": space},
             "inputs": {"height": {"node": 1, "output": "x"}, "midlevel": 0.3, "scale": 0.2}},
            {"type": "layer_weight", "inputs": {"blend": 0.5}},
            {"type": "diffuse", "inputs": {"color": {"node": 3, "output": "facing"}}}
        ],
        "surface": {"node": 4},
        "displacement": {"node": 2, "output": "displacement"}
    }))
}

#[test]
fn displacement_bumps_the_normal_every_node_reads() {
    // Height 0.2 x along the normal: the normal tilts as a Bump of distance 0.2 tilts it (the
    // midlevel is a constant shift), and the Layer Weight reads that normal, not the mesh's.
    let sg = ShaderGraph::new(&displaced("WORLD"), "/materials/0", 0).unwrap();
    let sp = point();
    let sh = sg.shade(&sp, &[], Want::All);
    let n = sh.bsdf.frame().n;
    let want = Vec3::new(-0.2, 0.0, 1.0).normalize();
    assert!((n - want).length() < 1e-3, "{n}");
    let moved = ShadingPoint { n: want, ..sp };
    let (_, facing) = super::geometry_nodes::layer_weight(&moved, 0.5, None);
    let (_, flat) = super::geometry_nodes::layer_weight(&sp, 0.5, None);
    let albedo = match sh.bsdf.lobes().next().unwrap().1 {
        crate::materials::lobe::Lobe::Lambert(l) => l.albedo.x,
        other => panic!("{other:?}"),
    };
    assert!(
        (albedo - facing).abs() < 2e-3 && (albedo - flat).abs() > 0.05,
        "{albedo} {facing} {flat}"
    );
    // Object space: an object scaled by 2 displaces twice as far; world space does not.
    let mut big = sp;
    big.object.to_object = glam::Mat4::from_scale(Vec3::splat(0.5));
    let n_obj = ShaderGraph::new(&displaced("OBJECT"), "/materials/0", 0)
        .unwrap()
        .shade(&big, &[], Want::All)
        .bsdf
        .frame()
        .n;
    let want = Vec3::new(-0.4, 0.0, 1.0).normalize();
    assert!((n_obj - want).length() < 1e-3, "{n_obj}");
    assert!((sg.shade(&big, &[], Want::All).bsdf.frame().n - n).length() < 1e-6);
    // A displacement that does not change over the surface compiles to nothing.
    let mut flat_g = displaced("WORLD");
    flat_g.nodes[2].inputs.remove("height");
    let sg = ShaderGraph::new(&flat_g, "/materials/0", 0).unwrap();
    assert_eq!(sg.shade(&sp, &[], Want::All).bsdf.frame().n, sp.n);
}

#[test]
fn light_path_reads_the_kind_of_ray() {
    // Emission for the camera only, a Transparent BSDF for every other ray.
    let g = graph(serde_json::json!({
        "name": "card",
        "nodes": [
            {"type": "light_path"},
            {"type": "transparent"},
            {"type": "emission", "inputs": {"strength": 5.0}},
            {"type": "mix_shader", "inputs": {
                "fac": {"node": 0, "output": "is_camera_ray"},
                "shader1": {"node": 1}, "shader2": {"node": 2}}}
        ],
        "surface": {"node": 3}
    }));
    let sg = ShaderGraph::new(&g, "/materials/0", 0).unwrap();
    let mut sp = point();
    use crate::geometry::{RayPath, Scatter};
    let kinds = [
        (RayPath::CAMERA_RAY, 5.0, 0.0),
        (RayPath::SHADOW_RAY, 0.0, 1.0),
        (
            RayPath::CAMERA_RAY.scattered(Scatter::Diffuse, false),
            0.0,
            1.0,
        ),
        (RayPath::default(), 0.0, 1.0),
    ];
    for (path, emission, transparency) in kinds {
        sp.path = path;
        let sh = sg.shade(&sp, &[], Want::All);
        assert_eq!(
            (sh.emission.x, sh.transparency.x),
            (emission, transparency),
            "{path:?}"
        );
    }
    // Every output, against the path it reads.
    let outs = [
        ("is_glossy_ray", 1.0),
        ("is_singular_ray", 1.0),
        ("is_transmission_ray", 1.0),
        ("is_reflection_ray", 0.0),
        ("is_diffuse_ray", 0.0),
        ("ray_length", 2.5),
        ("ray_depth", 2.0),
        ("diffuse_depth", 1.0),
        ("glossy_depth", 1.0),
        ("transmission_depth", 1.0),
        ("transparent_depth", 1.0),
    ];
    sp.path = RayPath::CAMERA_RAY
        .scattered(Scatter::Diffuse, false)
        .crossed()
        .scattered(Scatter::Singular, true);
    sp.ray_length = 2.5;
    for (name, want) in outs {
        let g = graph(serde_json::json!({
            "name": "probe",
            "nodes": [
                {"type": "light_path"},
                {"type": "emission", "inputs": {"strength": {"node": 0, "output": name}}}
            ],
            "surface": {"node": 1}
        }));
        let sh = ShaderGraph::new(&g, "/materials/0", 0)
            .unwrap()
            .shade(&sp, &[], Want::Light);
        assert_eq!(sh.emission.x, want, "{name}");
    }
}

#[test]
fn errors_name_the_node_and_the_field() {
    let bad_type = graph(
        serde_json::json!({"name": "m", "nodes": [{"type": "warp_drive"}],
                                            "surface": {"node": 0}}),
    );
    let (ptr, msg) = err_of(&bad_type);
    assert_eq!(ptr, "/materials/0/nodes/0/type");
    assert!(msg.contains("warp_drive"), "{msg}");

    let bad_output = graph(serde_json::json!({"name": "m", "nodes": [
        {"type": "tex_coord", "name": "Texture Coordinate"},
        {"type": "diffuse", "inputs": {"color": {"node": 0, "output": "colour"}}}],
        "surface": {"node": 1}}));
    let (ptr, msg) = err_of(&bad_output);
    assert_eq!(ptr, "/materials/0/nodes/1/inputs/color");
    assert!(
        msg.contains("Texture Coordinate") && msg.contains("colour"),
        "{msg}"
    );

    let bad_input = graph(serde_json::json!({"name": "m", "nodes": [
        {"type": "diffuse", "inputs": {"colr": [1.0, 0.0, 0.0]}}], "surface": {"node": 0}}));
    assert_eq!(err_of(&bad_input).0, "/materials/0/nodes/0/inputs/colr");

    let cycle = graph(serde_json::json!({"name": "m", "nodes": [
        {"type": "invert", "inputs": {"color": {"node": 1, "output": "color"}}},
        {"type": "invert", "inputs": {"color": {"node": 0, "output": "color"}}},
        {"type": "diffuse", "inputs": {"color": {"node": 1, "output": "color"}}}],
        "surface": {"node": 2}}));
    assert!(err_of(&cycle).1.contains("cycle"));

    let dangling = graph(serde_json::json!({"name": "m", "nodes": [
        {"type": "diffuse", "inputs": {"color": {"node": 9}}}], "surface": {"node": 0}}));
    assert!(err_of(&dangling).1.contains("node 9"));

    let value_as_shader = graph(
        serde_json::json!({"name": "m", "nodes": [{"type": "value"}],
                                                   "surface": {"node": 0}}),
    );
    assert!(err_of(&value_as_shader).1.contains("not a shader"));

    let bad_image = graph(serde_json::json!({"name": "m", "nodes": [
        {"type": "image_texture", "params": {"texture": 3}},
        {"type": "diffuse", "inputs": {"color": {"node": 0, "output": "color"}}}],
        "surface": {"node": 1}}));
    assert_eq!(err_of(&bad_image).0, "/materials/0/nodes/0/params/texture");

    // Unknown modes of the image's interpolation and projection, and of a Displacement's
    // space, name the field and the value.
    for (kind, field, value) in [
        ("image_texture", "interpolation", "Nearest"),
        ("image_texture", "projection", "CYLINDER"),
        ("displacement", "space", "TANGENT"),
    ] {
        let g = graph(serde_json::json!({"name": "m", "nodes": [
            {"type": kind, "params": {"texture": 0, field: value}},
            {"type": "diffuse", "inputs": {"normal": {"node": 0, "output": if kind == "displacement" { "displacement" } else { "color" }}}}],
            "surface": {"node": 1}}));
        let (ptr, msg) = err_of(&g);
        assert_eq!(ptr, format!("/materials/0/nodes/0/params/{field}"));
        assert!(msg.contains(value), "{msg}");
    }
}

#[test]
fn node_specs_list_every_type_with_its_sockets() {
    let s = super::compile::node_specs();
    let p = &s["principled"];
    assert_eq!(p["inputs"][0], serde_json::json!(["base_color", "color"]));
    assert_eq!(p["outputs"][0], serde_json::json!(["bsdf", "closure"]));
    assert_eq!(
        s["image_texture"]["outputs"][1],
        serde_json::json!(["alpha", "float"])
    );
    assert!(s["mix_shader"]["inputs"].as_array().unwrap().len() == 3);
    // Every type the compiler knows is listed (those needing properties too).
    let all = super::compile::BUILTIN.len()
        + super::closure::LeafKind::TYPES.len()
        + super::nodes::NodeOp::TYPES.len();
    assert_eq!(s.as_object().unwrap().len(), all);
    assert_eq!(
        s["color_ramp"]["outputs"][1],
        serde_json::json!(["alpha", "float"])
    );
    assert_eq!(
        s["rgb_curves"]["inputs"][1],
        serde_json::json!(["color", "color"])
    );
}

/// A floor under a card at z = 1 whose Alpha is a linear gradient along x in object space:
/// a hole for x < 0, half covered at x = 0.5, solid for x >= 1.
fn card_scene() -> crate::scene::Scene {
    crate::render::terms::testing::scene(serde_json::json!({
        "materials": [
            {"type": "diffuse", "name": "floor"},
            {"type": "graph", "name": "card", "nodes": [
                {"type": "tex_coord"},
                {"type": "gradient_texture", "inputs": {"vector": {"node": 0, "output": "object"}}},
                {"type": "principled", "inputs": {"alpha": {"node": 1, "output": "fac"}}}
            ], "surface": {"node": 2}}
        ],
        "meshes": [
            crate::render::terms::testing::floor(0),
            {"name": "card", "material": 1,
             "positions": [[-10, -10, 1], [10, -10, 1], [10, 10, 1], [-10, 10, 1]],
             "indices": [[0, 1, 2], [0, 2, 3]]}
        ],
    }))
}

#[test]
fn alpha_cut_outs_pass_shadow_rays_and_paths_where_transparent() {
    use crate::geometry::Ray;
    use crate::scene::shading::Crossing;
    use crate::scene::SceneHit;
    let sc = card_scene();
    assert!(sc.transparent);
    let stack = sc.camera_stack;
    let shadow = |x: f32| {
        let o = Vec3::new(x, 0.0, 0.001);
        sc.transmittance(&Ray::with_t_max(o, Vec3::new(0.0, 0.0, 2.0), 1.0), &stack)
    };
    assert_eq!(shadow(-5.0), Vec3::ONE);
    assert_eq!(shadow(5.0), Vec3::ZERO);
    assert!(
        (shadow(0.5) - Vec3::splat(0.5)).length() < 1e-5,
        "{}",
        shadow(0.5)
    );
    let card_at = |x: f32| {
        let ray = Ray::new(Vec3::new(x, 0.0, 2.0), Vec3::new(0.0, 0.0, -1.0));
        let SceneHit::Surface(si) = sc.intersect(&ray) else {
            panic!("the card is below")
        };
        si
    };
    let card = &sc.materials[1];
    assert_eq!(
        sc.crossing(card, &card_at(-5.0), || 0.99),
        Crossing::Pass(Vec3::ONE)
    );
    assert_eq!(
        sc.crossing(card, &card_at(5.0), || 0.0),
        Crossing::Stop(1.0)
    );
    // Half covered: pass with probability 1/2 at weight 1, or stop at weight 2.
    match sc.crossing(card, &card_at(0.5), || 0.2) {
        Crossing::Pass(w) => assert!((w - Vec3::ONE).length() < 1e-5),
        c => panic!("{c:?}"),
    }
    match sc.crossing(card, &card_at(0.5), || 0.7) {
        Crossing::Stop(w) => assert!((w - 2.0).abs() < 1e-4),
        c => panic!("{c:?}"),
    }
    // The floor is plain: nothing passes, no random number is drawn.
    let floor = &sc.materials[0];
    assert_eq!(
        sc.crossing(floor, &card_at(-5.0), || panic!("drawn")),
        Crossing::Stop(1.0)
    );
}

#[test]
fn scene_counters_show_what_graphs_compiled_to() {
    use super::GraphStats;
    let plain = crate::render::terms::testing::scene(serde_json::json!({
        "materials": [{"type": "diffuse"}],
        "meshes": [crate::render::terms::testing::floor(0)],
    }));
    assert_eq!(plain.graph_stats, GraphStats::default());
    assert!(plain.objects.is_empty() && !plain.transparent);
    let card = card_scene();
    assert_eq!(card.graph_stats.graphs, 1);
    assert_eq!(card.graph_stats.folded, 0);
    assert_eq!(card.graph_stats.leaves, 1);
    // tex_coord and the gradient run per point (the Principled's constants are folded).
    assert_eq!(card.graph_stats.instructions, 2);
    assert_eq!(card.objects.len(), 2);
    let folded = crate::render::terms::testing::scene(serde_json::json!({
        "materials": [{"type": "graph", "name": "g", "nodes": [{"type": "diffuse"}],
                       "surface": {"node": 0}}],
        "meshes": [crate::render::terms::testing::floor(0)],
    }));
    assert_eq!(
        folded.graph_stats,
        GraphStats {
            graphs: 1,
            folded: 1,
            instructions: 0,
            leaves: 0,
            tangent_meshes: 0,
        }
    );
    assert!(folded.objects.is_empty());
}

#[test]
fn tangents_are_built_only_for_meshes_a_tangent_normal_map_reads() {
    let mut uv_floor = crate::render::terms::testing::floor(1);
    uv_floor["uvs"] = serde_json::json!([[0, 0], [1, 0], [1, 1], [0, 1]]);
    let mapped = |space: &str| {
        serde_json::json!({"type": "graph", "name": space, "nodes": [
            {"type": "normal_map", "params": {"space": space},
             "inputs": {"color": [0.7, 0.5, 0.9]}},
            {"type": "diffuse", "inputs": {"normal": {"node": 0, "output": "normal"}}}],
            "surface": {"node": 1}})
    };
    let count = |material: serde_json::Value, meshes: serde_json::Value| {
        crate::render::terms::testing::scene(serde_json::json!({
            "materials": [{"type": "diffuse"}, material],
            "meshes": meshes,
        }))
        .graph_stats
        .tangent_meshes
    };
    // The floor with UVs under a tangent-space map; not the one with the plain material,
    // nor an object-space map, nor a floor without UVs.
    let tangent = mapped("TANGENT");
    let plain = crate::render::terms::testing::floor(0);
    let both = serde_json::json!([uv_floor.clone(), plain.clone()]);
    assert_eq!(count(tangent.clone(), both.clone()), 1);
    assert_eq!(count(mapped("OBJECT"), both), 0);
    assert_eq!(
        count(
            tangent,
            serde_json::json!([crate::render::terms::testing::floor(1)])
        ),
        0
    );
}

#[test]
fn converters_compile_and_run_as_their_nodes() {
    // Noise -> Map Range -> Math (x 2) -> ColorRamp -> Mix (multiply with a colour) on an
    // emission: the emission at a point is the chain's value there.
    let g = graph(serde_json::json!({
        "name": "chain",
        "nodes": [
            {"type": "noise_texture", "inputs": {"scale": 3.0}},
            {"type": "map_range", "inputs": {"value": {"node": 0, "output": "fac"},
                                             "from_min": 0.3, "from_max": 0.7}},
            {"type": "math", "params": {"operation": "MULTIPLY", "use_clamp": true},
             "inputs": {"value": {"node": 1, "output": "result"}, "value_001": 2.0}},
            {"type": "color_ramp", "params": {"interpolation": "LINEAR",
                                              "stops": [[0.0, 0.0, 0.0, 0.0, 1.0],
                                                        [1.0, 1.0, 0.5, 0.25, 1.0]]},
             "inputs": {"fac": {"node": 2, "output": "value"}}},
            {"type": "mix", "params": {"data_type": "RGBA", "blend_type": "MULTIPLY"},
             "inputs": {"factor": 1.0, "a": {"node": 3, "output": "color"},
                        "b": [0.5, 1.0, 1.0]}},
            {"type": "emission", "inputs": {"color": {"node": 4, "output": "result"}}}
        ],
        "surface": {"node": 5}
    }));
    let sg = ShaderGraph::new(&g, "/materials/0", 0).unwrap();
    assert_eq!(
        sg.instructions(),
        6,
        "the implicit coordinates, then five nodes"
    );
    let sp = point();
    let gen = sp.object.generated(sp.p);
    let noise = super::tex::NoiseTexture {
        dimensions: super::tex::Dimensions::D3,
        noise_type: super::tex::NoiseType::Fbm,
        normalize: true,
    }
    .eval_fac(&super::tex::NoiseInputs {
        vector: gen,
        scale: 3.0,
        ..Default::default()
    });
    let t = (((noise - 0.3) / 0.4).clamp(0.0, 1.0) * 2.0).clamp(0.0, 1.0);
    let want = Vec3::new(1.0, 0.5, 0.25) * t * Vec3::new(0.5, 1.0, 1.0);
    let got = sg.shade(&sp, &[], Want::Light).emission;
    // The ramp is baked into 257 entries as Cycles does: linear ramps are exact up to float
    // rounding.
    assert!(
        (got - want).length() < 1e-4,
        "{got} vs {want} (noise {noise})"
    );
}

#[test]
fn the_graphs_normal_is_the_hits_shading_normal() {
    // A floor whose Normal Map tilts the normal towards +x: the hit's shading normal (which
    // every estimate's cosine reads) is the tilted one, from above and from below.
    let sc = crate::render::terms::testing::scene(serde_json::json!({
        "materials": [{"type": "graph", "name": "tilted", "nodes": [
            {"type": "normal_map", "inputs": {"color": [0.8, 0.5, 0.9]}},
            {"type": "diffuse", "inputs": {"normal": {"node": 0, "output": "normal"}}}
        ], "surface": {"node": 1}}],
        "meshes": [{"name": "floor", "material": 0,
                    "positions": [[-10, -10, 0], [10, -10, 0], [10, 10, 0], [-10, 10, 0]],
                    "uvs": [[0, 0], [1, 0], [1, 1], [0, 1]],
                    "indices": [[0, 1, 2], [0, 2, 3]]}],
    }));
    let (si, bsdf) = crate::render::terms::testing::hit_below(&sc, 0.3);
    let c = Vec3::new(0.6, 0.0, 0.8);
    let want = c.normalize();
    assert!((si.ns - want).length() < 1e-3, "{}", si.ns);
    assert!((bsdf.frame().n - want).length() < 1e-3);
}

#[test]
fn bump_shadowing_dims_diffuse_light_as_cycles() {
    // A Diffuse BSDF normal-mapped to (0, 0.6, 0.8) under light from (0.766, 0, 0.643): Cycles
    // 5.0 renders 0.781 of the flat plane's brightness where the cosine alone gives 0.800
    // (measured on a plane lit by a sun, 16 spp: 0.3289 against 0.4211); the bump shadowing
    // term of the bumped normal's tilt gives that 0.976.
    let g = graph(serde_json::json!({
        "name": "tilted",
        "nodes": [
            {"type": "normal_map", "inputs": {"color": [0.5, 0.8, 0.9]}},
            {"type": "diffuse", "inputs": {"color": [1.0, 1.0, 1.0],
                                           "normal": {"node": 0, "output": "normal"}}}
        ],
        "surface": {"node": 1}
    }));
    let sg = ShaderGraph::new(&g, "/materials/0", 0).unwrap();
    let mut sp = point();
    sp.wo = Vec3::Z;
    let bsdf = sg.shade(&sp, &[], Want::All).bsdf;
    let n = bsdf.frame().n;
    let wi = Vec3::new(0.766, 0.0, 0.643).normalize();
    let flat = wi.z;
    let ratio = bsdf.eval(sp.wo, wi).x * std::f32::consts::PI * wi.dot(n) / flat;
    assert!((ratio - 0.781).abs() < 0.004, "{ratio}");
    // Light below the smooth surface but above the bumped one is blocked.
    let under = Vec3::new(0.0, 0.9, -0.1).normalize();
    assert!(under.dot(n) > 0.0);
    assert_eq!(bsdf.eval(sp.wo, under), Vec3::ZERO);
}

#[test]
fn the_attribute_node_reads_the_mesh_attribute_of_its_name() {
    let g = graph(serde_json::json!({
        "name": "painted",
        "nodes": [
            {"type": "attribute", "params": {"name": "Paint"}},
            {"type": "emission", "inputs": {"color": {"node": 0, "output": "color"},
                                            "strength": {"node": 0, "output": "alpha"}}},
            {"type": "emission", "inputs": {"color": [1.0, 1.0, 1.0],
                                            "strength": {"node": 0, "output": "fac"}}},
            {"type": "add_shader", "inputs": {"shader1": {"node": 1}, "shader2": {"node": 2}}}
        ],
        "surface": {"node": 3}
    }));
    let sg = ShaderGraph::new(&g, "/materials/0", 0).unwrap();
    let mut sp = point();
    // Without the attribute: zero, as in Cycles.
    assert_eq!(sg.shade(&sp, &[], Want::Light).emission, Vec3::ZERO);
    let a = &mut sp.attributes;
    a.len = 2;
    a.keys[0] = crate::geometry::attribute_key("Other");
    a.values[0] = glam::Vec4::splat(9.0);
    a.keys[1] = crate::geometry::attribute_key("Paint");
    a.values[1] = glam::Vec4::new(0.2, 0.4, 0.9, 0.5);
    let e = sg.shade(&sp, &[], Want::Light).emission;
    // colour x alpha + white x mean(colour).
    let want = Vec3::new(0.2, 0.4, 0.9) * 0.5 + Vec3::splat(0.5);
    assert!((e - want).abs().max_element() < 1e-6, "{e} vs {want}");
}

#[test]
fn a_named_uv_map_reads_its_attribute_and_moves_with_a_bump() {
    // Emission = the UV map "Decal" (u, v, 0); a second graph bumps by its u.
    let uv = graph(serde_json::json!({
        "name": "decal",
        "nodes": [
            {"type": "uv_map", "params": {"uv_map": "Decal"}},
            {"type": "emission", "inputs": {"color": {"node": 0, "output": "uv"}}}
        ],
        "surface": {"node": 1}
    }));
    let sg = ShaderGraph::new(&uv, "/materials/0", 0).unwrap();
    let mut sp = point();
    // A mesh without the map reads zero, as in Cycles.
    assert_eq!(sg.shade(&sp, &[], Want::Light).emission, Vec3::ZERO);
    // The triangle's edges are x and y; the map's u grows by 2 along x, v by 3 along y.
    let a = &mut sp.attributes;
    a.len = 1;
    a.keys[0] = crate::geometry::attribute_key("Decal");
    a.values[0] = glam::Vec4::new(0.25, 0.5, 0.0, 1.0);
    a.d1[0] = glam::Vec4::new(2.0, 0.0, 0.0, 0.0);
    a.d2[0] = glam::Vec4::new(0.0, 3.0, 0.0, 0.0);
    (a.e1, a.e2) = (Vec3::X, Vec3::Y);
    let e = sg.shade(&sp, &[], Want::Light).emission;
    assert!(
        (e - Vec3::new(0.25, 0.5, 0.0)).abs().max_element() < 1e-6,
        "{e}"
    );
    let moved = sp.attributes.get_moved(
        crate::geometry::attribute_key("Decal"),
        Vec3::new(0.1, 0.2, 0.0),
    );
    assert!(
        (moved.unwrap() - glam::Vec4::new(0.45, 1.1, 0.0, 1.0))
            .abs()
            .max_element()
            < 1e-6
    );
    // A Bump whose height is the map's u tilts the normal against +x (the height grows
    // along x), as it would for the same height over the position.
    let bumped = graph(serde_json::json!({
        "name": "bumped",
        "nodes": [
            {"type": "uv_map", "params": {"uv_map": "Decal"}},
            {"type": "separate_xyz", "inputs": {"vector": {"node": 0, "output": "uv"}}},
            {"type": "bump", "inputs": {"height": {"node": 1, "output": "x"}, "distance": 0.1}},
            {"type": "vector_math", "params": {"operation": "MULTIPLY_ADD"},
             "inputs": {"vector": {"node": 2, "output": "normal"},
                        "vector_001": [0.5, 0.5, 0.5], "vector_002": [0.5, 0.5, 0.5]}},
            {"type": "emission", "inputs": {"color": {"node": 3, "output": "vector"}}}
        ],
        "surface": {"node": 4}
    }));
    let sg = ShaderGraph::new(&bumped, "/materials/0", 0).unwrap();
    let n = 2.0 * sg.shade(&sp, &[], Want::Light).emission - Vec3::ONE;
    assert!(n.x < -0.1 && n.y.abs() < 1e-3, "{n}");
}

#[test]
fn a_bad_attribute_fallback_names_the_field() {
    let g = graph(serde_json::json!({
        "name": "painted",
        "nodes": [
            {"type": "attribute", "params": {"name": "Paint", "fallback": [1.0, 0.0]}},
            {"type": "emission", "inputs": {"color": {"node": 0, "output": "color"}}}
        ],
        "surface": {"node": 1}
    }));
    let (pointer, message) = err_of(&g);
    assert!(pointer.contains("fallback"), "{pointer}");
    assert!(message.contains("4 numbers"), "{message}");
}

#[test]
fn the_coat_reflects_about_its_own_normal() {
    // A black Principled (rough specular layer) under a sharp coat; the Normal or the Coat
    // Normal tilted by a world-space normal map. The coat's highlight lies at the mirror
    // direction about the coat's normal: the surface's own when Coat Normal is unlinked.
    let tilted = Vec3::new(0.3, 0.0, 1.0).normalize();
    let coated = |socket: &str| {
        graph(serde_json::json!({
            "name": socket,
            "nodes": [
                {"type": "normal_map", "params": {"space": "WORLD"},
                 "inputs": {"color": [0.65, 0.5, 1.0]}},
                {"type": "principled", "inputs": {
                    "base_color": [0.0, 0.0, 0.0], "roughness": 1.0, "coat_weight": 1.0,
                    "coat_roughness": 0.05, socket: {"node": 0, "output": "normal"}}}
            ],
            "surface": {"node": 1}
        }))
    };
    let sp = point();
    let mirror = |n: Vec3| 2.0 * n.dot(sp.wo) * n - sp.wo;
    let peak = |g: &GraphDesc| {
        let sh = ShaderGraph::new(g, "/materials/0", 0)
            .unwrap()
            .shade(&sp, &[], Want::All);
        let f = |wi: Vec3| sh.bsdf.eval(sp.wo, wi.normalize()).x;
        (f(mirror(Vec3::Z)), f(mirror(tilted)))
    };
    let (smooth, bent) = peak(&coated("normal"));
    assert!(
        smooth > 10.0 * bent,
        "Normal tilted: {smooth} at the smooth mirror, {bent}"
    );
    let (smooth, bent) = peak(&coated("coat_normal"));
    assert!(
        bent > 10.0 * smooth,
        "Coat Normal tilted: {smooth}, {bent} at its mirror"
    );
}
