//! Subsurface scattering (the Principled material's subsurface part, the `subsurface` term):
//! energy conservation in a white furnace, the radius limits, light through a thin plate, the
//! sum rule and determinism, what runs without subsurface materials, and the warnings on bad
//! input. The comparison with Cycles is in the parity corpus (`sss_*`).

use crate::common;
use common::*;
use glam::Vec3;
use photonmap::geometry::shapes;
use photonmap::render::aov::Term;
use photonmap::render::settings::FilterName;
use photonmap::render::{RenderOutput, RenderSettings};
use photonmap::scene::SceneDesc;

/// A sphere of radius 1 at the origin, seen whole by a camera on +z, of a Principled material
/// with `subsurface` (JSON, or null for none), colour `color`, roughness `roughness`; the
/// light is a constant environment of radiance 1 when `furnace`, else a sun from above-left
/// over a grey floor.
fn sphere_scene(
    subsurface: serde_json::Value,
    color: f32,
    roughness: f32,
    furnace: bool,
) -> SceneDesc {
    let s = shapes::sphere(Vec3::ZERO, 1.0, 48, 96);
    let mut principled = serde_json::json!({
        "type": "principled", "name": "wax", "base_color": [color, color, color],
        "roughness": roughness, "ior": 1.4,
    });
    if !subsurface.is_null() {
        principled["subsurface"] = subsurface;
    }
    let mut desc = serde_json::json!({
        "camera": {"transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4.5], [0, 0, 0, 1]],
                   "fov": 0.5},
        "film": {"width": 24, "height": 24},
        "materials": [principled, {"type": "diffuse", "name": "floor", "color": [0.5, 0.5, 0.5]}],
        "meshes": [{
            "name": "sphere", "material": 0,
            "positions": s.positions.iter().map(|p| p.to_array()).collect::<Vec<_>>(),
            "indices": s.indices,
            "normals": s.normals.as_ref().map(|n| n.iter().map(|v| v.to_array()).collect::<Vec<_>>()),
        }],
    });
    if furnace {
        desc["environment"] = serde_json::json!({"color": [1, 1, 1], "strength": 1.0});
    } else {
        desc["meshes"]
            .as_array_mut()
            .unwrap()
            .push(serde_json::json!({
                "name": "floor", "material": 1,
                "positions": [[-10, -1, -10], [10, -1, -10], [10, -1, 10], [-10, -1, 10]],
                "indices": [[0, 2, 1], [0, 3, 2]],
            }));
        desc["lights"] = serde_json::json!([{"type": "distant", "name": "sun",
            "direction": [0.5, -1.0, -0.3], "irradiance": 3.0}]);
    }
    serde_json::from_value(desc).expect("a valid scene")
}

fn settings(spp: u32, seed: u64, threads: usize) -> RenderSettings {
    RenderSettings {
        spp,
        seed,
        threads,
        filter: FilterName::Box,
        photons: 50_000,
        caustic_photons: 20_000,
        ..Default::default()
    }
}

/// Mean of the pixels inside the sphere's disk (centre 0.6 of its radius on the image).
fn disk_mean(out: &RenderOutput, term: Option<Term>) -> Vec3 {
    let img = match term {
        Some(t) => out.film.term(t).clone(),
        None => out.film.combined(),
    };
    let (w, h) = (img.width as f32, img.height as f32);
    let mut sum = Vec3::ZERO;
    let mut n = 0;
    for y in 0..img.height {
        for x in 0..img.width {
            let dx = (x as f32 + 0.5 - w / 2.0) / (w / 2.0);
            let dy = (y as f32 + 0.5 - h / 2.0) / (h / 2.0);
            if dx * dx + dy * dy < 0.35 * 0.35 {
                let p = img.data[y * img.width + x];
                sum += Vec3::new(p[0], p[1], p[2]);
                n += 1;
            }
        }
    }
    sum / n as f32
}

/// Settings of the furnace: no photon maps (nothing in a furnace stores them).
fn furnace_settings(seed: u64) -> RenderSettings {
    let mut st = settings(16, seed, 0);
    st.photons = 0;
    st.caustic_photons = 0;
    st
}

fn radius(r: f32) -> serde_json::Value {
    serde_json::json!({"radius": [r, r, r]})
}

/// The mean of the sphere's disk in a furnace of radiance 1, over two seeds.
fn furnace(sub: serde_json::Value, color: f32) -> f32 {
    let desc = sphere_scene(sub, color, 0.0, true);
    (1..=2)
        .map(|seed| disk_mean(&render_settings(&desc, furnace_settings(seed)), None).x)
        .sum::<f32>()
        / 2.0
}

/// A white (albedo 1) subsurface sphere in a white furnace is invisible: what its specular
/// layer reflects and what leaves it after the walk add up to the furnace's radiance, at any
/// mean free path (radius / (4 pi): 0.08 to 1 of the sphere's radius). The shorter the path,
/// the more events a walk needs to leave, and the ones past 256 are lost, as in Cycles: 2% at
/// 0.08, 8% at 0.004 (radius 0.05). An absorbing one is darker.
#[test]
fn white_furnace_conserves_energy_at_any_radius() {
    for (r, tol) in [(0.05f32, 0.1), (1.0, 0.035), (4.0, 0.02), (12.0, 0.02)] {
        let got = furnace(radius(r), 1.0);
        eprintln!("radius {r}: furnace {got:.4}");
        assert!(
            got < 1.005 && got > 1.0 - tol,
            "radius {r}: {got} against 1"
        );
    }
    let grey = furnace(radius(0.2), 0.5);
    eprintln!("colour 0.5, radius 0.2: furnace {grey:.4}");
    assert!(grey < 0.85 && grey > 0.2, "an absorbing sphere: {grey}");
}

/// Radius 0 renders the material as its diffuse base, the very image of the material
/// without subsurface, with a warning naming the material; no walk runs.
#[test]
fn radius_zero_renders_as_the_diffuse_base() {
    let with = sphere_scene(radius(0.0), 0.8, 0.5, false);
    let without = sphere_scene(serde_json::Value::Null, 0.8, 0.5, false);
    let a = render_settings(&with, settings(4, 3, 0));
    let b = render_settings(&without, settings(4, 3, 0));
    assert_eq!(a.film.combined().data, b.film.combined().data);
    assert!(
        a.stats
            .warnings
            .iter()
            .any(|w| w.contains("'wax'") && w.contains("radius 0")),
        "{:?}",
        a.stats.warnings
    );
    assert!(b.stats.warnings.is_empty());
    assert_eq!(a.stats.work.subsurface_walks, 0);
}

/// The radius limits, as Cycles' walk renders them, on a sphere of 1 m under a sun (the mean
/// of the disk the camera sees, against the diffuse base's):
///
/// - radius 1 mm: a walk leaves close to where it entered, with about the colour as its
///   weight (Cycles' fit is close for light colours, darker for dark ones). Cycles 5.0.1
///   (256 spp, the same scene through `bpy`): 0.967 of the diffuse base for colour 0.8, 0.854
///   for 0.3. The volumetric estimate this replaced rendered 0.43.
/// - radius 1000 m: walks cross the sphere without scattering and leave on its far side with
///   the weight 1 / colour times the lobe's colour, whatever the colour; the sphere shows the
///   light of its far side, and of the floor below it, lit through the sphere. Cycles: 0.595
///   (colour 0.8) and 1.517 (colour 0.3). With photons and gather rays that reflect the lobe
///   as the diffuse base instead of walking, the floor below stays dark and the sphere reads
///   0.576 and 1.450 (3.2% and 4.4% low), which this test fails.
///
/// Each ratio is held within 3% of Cycles' (ours: 0.985, 0.844, 0.592, 1.507).
#[test]
fn the_radius_limits_match_cycles() {
    let mean = |desc: &SceneDesc| {
        (1..=2u64)
            .map(|seed| disk_mean(&render_settings(desc, settings(16, seed, 0)), None))
            .sum::<Vec3>()
            / 2.0
    };
    for (r, color, cycles) in [
        (1e-3f32, 0.8f32, 0.967f32),
        (1e-3, 0.3, 0.854),
        (1e3, 0.8, 0.595),
        (1e3, 0.3, 1.517),
    ] {
        let a = mean(&sphere_scene(radius(r), color, 0.5, false));
        let b = mean(&sphere_scene(serde_json::Value::Null, color, 0.5, false));
        let ratio = a.x / b.x;
        eprintln!(
            "radius {r}, colour {color}: {a:?}, diffuse {b:?}, ratio {ratio:.4} (Cycles {cycles})"
        );
        assert!(
            (ratio / cycles - 1.0).abs() < 0.03,
            "radius {r}, colour {color}: {ratio} against {cycles}"
        );
    }
}

/// Light crosses a plate thinner than the radius: a plate lit from behind only is bright on
/// the side the camera sees, where the diffuse base is black there.
#[test]
fn light_crosses_a_thin_plate() {
    let plate = |sub: serde_json::Value| {
        let b = shapes::cuboid(Vec3::new(-1.0, -1.0, -0.02), Vec3::new(1.0, 1.0, 0.02));
        let mut m = serde_json::json!({"type": "principled", "name": "plate",
            "base_color": [0.9, 0.9, 0.9], "roughness": 0.5});
        if !sub.is_null() {
            m["subsurface"] = sub;
        }
        let desc = serde_json::json!({
            "camera": {"transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4.5], [0, 0, 0, 1]],
                       "fov": 0.3},
            "film": {"width": 16, "height": 16},
            "materials": [m],
            "meshes": [{"name": "plate", "material": 0,
                "positions": b.positions.iter().map(|p| p.to_array()).collect::<Vec<_>>(),
                "indices": b.indices}],
            "lights": [{"type": "distant", "name": "sun", "direction": [0.0, 0.0, 1.0],
                        "irradiance": 3.0}],
        });
        let desc: SceneDesc = serde_json::from_value(desc).unwrap();
        disk_mean(
            &render_settings(&desc, settings(16, 1, 0)),
            Some(Term::Subsurface),
        )
        .x
    };
    let through = plate(radius(0.1));
    let thick = plate(radius(0.001));
    eprintln!("lit from behind: radius 0.1 {through:.4}, radius 0.001 {thick:.4}");
    assert!(through > 0.05, "{through}");
    assert!(thick < 0.01 * through, "{thick} against {through}");
}

/// The mean of rows `rows` and columns `cols` of `out`'s beauty (red channel; row 0 at the top).
fn region_mean(
    out: &RenderOutput,
    rows: std::ops::Range<usize>,
    cols: std::ops::Range<usize>,
) -> f32 {
    let img = out.film.combined();
    let mut sum = 0.0;
    let mut n = 0;
    for y in rows {
        for x in cols.clone() {
            sum += img.data[y * img.width + x][0];
            n += 1;
        }
    }
    sum / n as f32
}

/// A plate 4 cm thick, 2 m wide, held 0.5 m over a grey floor under a sun from above, seen
/// from beside it at 0.25 m: the floor under the plate is lit by what comes through the plate
/// and by what its underside reflects of the lit floor around. The plate's material is the
/// Principled colour 0.8 with subsurface radius `radius` (none: the diffuse base).
fn plate_over_floor(radius_m: Option<f32>) -> SceneDesc {
    let b = shapes::cuboid(Vec3::new(-1.0, 0.48, -1.0), Vec3::new(1.0, 0.52, 1.0));
    let mut m = serde_json::json!({"type": "principled", "name": "plate",
        "base_color": [0.8, 0.8, 0.8], "roughness": 0.5, "ior": 1.4});
    if let Some(r) = radius_m {
        m["subsurface"] = radius(r);
    }
    let desc = serde_json::json!({
        "camera": {"transform": [[1, 0, 0, 0], [0, 1, 0, 0.25], [0, 0, 1, 2.0], [0, 0, 0, 1]],
                   "fov": 0.5},
        "film": {"width": 48, "height": 48},
        "materials": [m, {"type": "diffuse", "name": "floor", "color": [0.5, 0.5, 0.5]}],
        "meshes": [
            {"name": "plate", "material": 0,
             "positions": b.positions.iter().map(|p| p.to_array()).collect::<Vec<_>>(),
             "indices": b.indices},
            {"name": "floor", "material": 1,
             "positions": [[-2, 0, -2], [2, 0, -2], [2, 0, 2], [-2, 0, 2]],
             "indices": [[0, 2, 1], [0, 3, 2]]}],
        "lights": [{"type": "distant", "name": "sun", "direction": [0.2, -1.0, 0.1],
                    "irradiance": 3.0}],
    });
    serde_json::from_value(desc).unwrap()
}

/// Light through a plate onto the floor under it, against Cycles 5.0.1 on the same scene
/// (512 spp through `bpy`, box filter): the mean of the floor under the plate (rows 36-45)
/// and of the plate's underside (rows 3-10), columns 14-33. Ours: 4 seeds of 16 spp with
/// 200,000 global photons (the seeds spread by about 2%).
///
/// | plate | floor: ours / Cycles | underside: ours / Cycles |
/// |---|---|---|
/// | diffuse base | 0.0409 / 0.0380 | 0.1199 / 0.1131 |
/// | radius 1 mm | 0.0383 / 0.0374 | 0.1233 / 0.1152 |
/// | radius 10 cm | 0.1032 / 0.1109 | 0.2803 / 0.2764 |
///
/// At 10 cm light comes through the plate: Cycles' floor is 2.9 times what it is under the
/// diffuse base. It does only if photons walk through the plate and the final-gathering rays
/// from the floor read the light leaving its underside; with either reflecting the diffuse
/// base the floor reads 0.002 (1 mm) or 0.054 (10 cm). Without subsurface the floor reads 7.6%
/// bright: it and the underside are lit only by light bounced in the gap between them, where
/// the global map's estimates are biased (the parity corpus sees the same in concave
/// corners). Every figure is held within 10% of Cycles'.
#[test]
fn light_through_a_plate_reaches_the_floor_as_in_cycles() {
    let mean = |desc: &SceneDesc, rows: std::ops::Range<usize>| {
        let each: Vec<f32> = (1..=4u64)
            .map(|seed| {
                let mut s = settings(16, seed, 0);
                s.photons = 200_000;
                region_mean(&render_settings(desc, s), rows.clone(), 14..34)
            })
            .collect();
        each.iter().sum::<f32>() / each.len() as f32
    };
    for (r, floor_cycles, under_cycles, tol) in [
        (None, 0.0380f32, 0.1131f32, 0.10f32),
        (Some(1e-3f32), 0.0374, 0.1152, 0.10),
        (Some(0.1), 0.1109, 0.2764, 0.10),
    ] {
        let d = plate_over_floor(r);
        let (floor, under) = (mean(&d, 36..46), mean(&d, 3..11));
        eprintln!(
            "radius {r:?}: floor {floor:.4} (Cycles {floor_cycles}), underside {under:.4} \
             (Cycles {under_cycles})"
        );
        assert!(
            (floor / floor_cycles - 1.0).abs() < tol,
            "the floor under the plate, radius {r:?}: {floor} against {floor_cycles}"
        );
        assert!(
            (under / under_cycles - 1.0).abs() < tol,
            "the plate's underside, radius {r:?}: {under} against {under_cycles}"
        );
    }
}

/// The same seed gives the same bits for 1 and 2 threads, every term included; the
/// subsurface term holds light and the terms sum to the beauty.
#[test]
fn subsurface_renders_are_deterministic_and_sum_to_the_beauty() {
    let desc = sphere_scene(radius(0.2), 0.8, 0.5, false);
    let s1 = settings(4, 7, 1);
    let mut s2 = s1.clone();
    s2.threads = 2;
    let a = render_settings(&desc, s1);
    let b = render_settings(&desc, s2);
    for t in Term::ALL {
        assert_eq!(a.film.term(t).data, b.film.term(t).data, "{}", t.name());
    }
    let sub = disk_mean(&a, Some(Term::Subsurface));
    assert!(sub.min_element() > 0.01, "subsurface light {sub:?}");
    let sum = sum_terms(&a, &Term::ALL);
    assert_eq!(sum.data, a.film.combined().data);
}

/// Without a subsurface material no walk runs and the term is skipped, with its reason;
/// with one, the stats count the walks and their events. No photon map is built for it.
#[test]
fn nothing_subsurface_runs_without_subsurface_materials() {
    let plain = render_settings(
        &sphere_scene(serde_json::Value::Null, 0.8, 0.5, false),
        settings(2, 1, 0),
    );
    assert_eq!(plain.stats.work.subsurface_walks, 0);
    assert_eq!(plain.stats.work.subsurface_events, 0);
    assert!(plain
        .stats
        .skipped
        .iter()
        .any(|t| t.term == "subsurface" && t.reason == "the scene has no subsurface materials"));

    let wax = render_settings(
        &sphere_scene(radius(0.2), 0.8, 0.5, false),
        settings(2, 1, 0),
    );
    let w = &wax.stats.work;
    assert!(
        w.subsurface_walks > 0 && w.subsurface_events > w.subsurface_walks,
        "{w:?}"
    );
    assert!(!wax.stats.skipped.iter().any(|t| t.term == "subsurface"));
    let maps: Vec<String> = wax
        .stats
        .photon_maps
        .iter()
        .map(|m| m.map.to_string())
        .collect();
    assert!(!maps.iter().any(|m| m == "subsurface"), "{maps:?}");
    assert_eq!(w.march_steps, 0);
}

/// Bad input is warned about, naming the mesh or material, and renders finite images: an
/// inside-out mesh, an open mesh, negative and NaN radii.
#[test]
fn bad_subsurface_input_is_warned_about() {
    let warnings = |desc: &SceneDesc| {
        let scene = photonmap::scene::Scene::build(desc).expect("builds");
        scene.warnings.clone()
    };
    // Inside out: every triangle's winding reversed.
    let mut inside_out = sphere_scene(radius(0.2), 0.8, 0.5, false);
    for t in inside_out.meshes[0].indices.iter_mut() {
        t.swap(1, 2);
    }
    let w = warnings(&inside_out);
    assert!(
        w.iter()
            .any(|w| w.contains("'sphere'") && w.contains("inwards")),
        "{w:?}"
    );
    // Open: a cap of triangles removed.
    let mut open = sphere_scene(radius(0.2), 0.8, 0.5, false);
    let n = open.meshes[0].indices.len();
    open.meshes[0].indices.truncate(n - 10);
    let w = warnings(&open);
    assert!(
        w.iter()
            .any(|w| w.contains("'sphere'") && w.contains("closed")),
        "{w:?}"
    );
    // A closed, outward sphere: no warning.
    assert!(warnings(&sphere_scene(radius(0.2), 0.8, 0.5, false)).is_empty());
    // Negative and NaN radii.
    for bad in [
        [-0.1f32, 0.2, 0.2],
        [f32::NAN, 0.2, 0.2],
        [-1.0, -1.0, -1.0],
    ] {
        let mut desc = sphere_scene(radius(0.2), 0.8, 0.5, false);
        if let photonmap::scene::desc::MaterialDesc::Principled(p) = &mut desc.materials[0] {
            p.subsurface.as_mut().unwrap().radius = bad;
        }
        let w = warnings(&desc);
        assert!(
            w.iter()
                .any(|w| w.contains("'wax'") && w.contains("radius")),
            "{bad:?}: {w:?}"
        );
        let out = render_settings(&desc, settings(2, 1, 0));
        assert_eq!(out.stats.non_finite_samples, 0, "{bad:?}");
        assert!(out
            .film
            .combined()
            .data
            .iter()
            .all(|p| p.iter().all(|c| c.is_finite())));
    }
}

// -- the walk against Chandrasekhar's half-space ---------------------------------------------

/// Chandrasekhar's H-function of isotropic scattering with single-scattering albedo `w` at
/// `mu`, from its form 1/H(mu) = sqrt(1 - w) + (w/2) int_0^1 mu' H(mu') / (mu + mu') dmu'
/// (Chandrasekhar 1960, "Radiative Transfer", ch. V), iterated on a midpoint grid.
fn chandrasekhar_h(w: f64, mu: f64) -> f64 {
    const N: usize = 2000;
    let grid: Vec<f64> = (0..N).map(|i| (i as f64 + 0.5) / N as f64).collect();
    let mut h = vec![1.0f64; N];
    let inv = |h: &[f64], m: f64| {
        (1.0 - w).sqrt()
            + 0.5
                * w
                * grid
                    .iter()
                    .zip(h)
                    .map(|(&x, &hx)| x * hx / (m + x))
                    .sum::<f64>()
                / N as f64
    };
    for _ in 0..400 {
        h = grid.iter().map(|&m| 1.0 / inv(&h, m)).collect();
    }
    1.0 / inv(&h, mu)
}

/// A walk entering a half-space (a box 100 mean free paths deep) along direction cosine mu0,
/// with isotropic scattering of single-scattering albedo `alpha`, leaves it with the weight
/// alpha^n after n events, and its expectation is the half-space's total reflectance,
/// exactly R(mu0) = 1 - H(mu0) sqrt(1 - alpha) (Chandrasekhar). 200,000 walks per case, within
/// four standard errors; an albedo 2% off fails.
#[test]
fn the_walk_returns_chandrasekhars_half_space_reflectance() {
    use photonmap::geometry::Ray;
    use photonmap::materials::subsurface::Subsurface;
    use photonmap::math::Spectrum;
    use photonmap::render::terms::subsurface;
    use photonmap::sampling::Rng;
    let b = shapes::cuboid(
        Vec3::new(-100.0, -100.0, -100.0),
        Vec3::new(100.0, 0.0, 100.0),
    );
    let desc: SceneDesc = serde_json::from_value(serde_json::json!({
        "camera": {"transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4.5], [0, 0, 0, 1]],
                   "fov": 0.5},
        "film": {"width": 4, "height": 4},
        "materials": [{"type": "principled", "name": "slab", "base_color": [1, 1, 1],
                       "subsurface": {"radius": [1, 1, 1]}}],
        "meshes": [{"name": "half_space", "material": 0,
            "positions": b.positions.iter().map(|p| p.to_array()).collect::<Vec<_>>(),
            "indices": b.indices}],
    }))
    .unwrap();
    let scene = photonmap::scene::Scene::build(&desc).unwrap();
    let walked = |alpha: f32, view_deg: f32, seed: u64| -> (f64, f64, f64) {
        let ior = 1.01f32;
        let (s, c) = view_deg.to_radians().sin_cos();
        let wo = Vec3::new(s, c, 0.0);
        let photonmap::scene::SceneHit::Surface(si) = scene.intersect(&Ray::new(wo * 10.0, -wo))
        else {
            panic!("the ray misses the half-space");
        };
        let ss = Subsurface {
            weight: 1.0,
            color: Spectrum::ONE,
            walks: Spectrum::ONE,
            ior,
            g: 0.0,
            skin: false,
            sigma_t: Spectrum::ONE,
            alpha: Spectrum::splat(alpha),
            start: Spectrum::ONE,
        };
        let n = 200_000;
        let mut rng = Rng::new(seed, 0);
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            // Roughness 0: the entry refracts (GGX at its smallest alpha).
            let w = subsurface::walk(&scene, &si, &ss, 0.0, &mut rng)
                .map_or(0.0, |e| e.weight.x as f64);
            sum += w;
            sum2 += w * w;
        }
        let mean = sum / n as f64;
        let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        // The direction cosine inside, after refraction.
        let mu0 = (1.0 - (s / ior).powi(2)).sqrt() as f64;
        (mean, se, mu0)
    };
    for (alpha, view) in [(0.5f32, 0.0f32), (0.9, 0.0), (0.9, 60.0), (0.95, 30.0)] {
        let (mean, se, mu0) = walked(alpha, view, 11);
        let exact = 1.0 - chandrasekhar_h(alpha as f64, mu0) * (1.0 - alpha as f64).sqrt();
        eprintln!(
            "albedo {alpha}, view {view} deg (mu0 {mu0:.4}): walk {mean:.5} +- {se:.5}, \
             Chandrasekhar {exact:.5}"
        );
        assert!(
            (mean - exact).abs() < 4.0 * se,
            "albedo {alpha}, view {view}: {mean} against {exact}"
        );
        // The test sees an albedo 2% off.
        let off =
            1.0 - chandrasekhar_h(alpha as f64 * 0.98, mu0) * (1.0 - alpha as f64 * 0.98).sqrt();
        assert!(
            (mean - off).abs() > 4.0 * se,
            "albedo {alpha}: 2% off not seen"
        );
    }
}
