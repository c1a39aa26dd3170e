//! Participating media: the phase function's sampling, a closed-form single-scattering value,
//! the extremes of the extinction coefficient, and media-free scenes never marching.

use crate::common;
use common::*;
use glam::{Vec2, Vec3};
use photonmap::geometry::shapes;
use photonmap::media::HenyeyGreenstein;
use photonmap::render::aov::Term;
use photonmap::render::settings::FilterName;
use photonmap::render::RenderSettings;
use photonmap::sampling::chi2::{assert_chi2, Chi2Config};
use photonmap::scene::desc::*;
use photonmap::scene::SceneDesc;

#[test]
fn henyey_greenstein_sampling_matches_its_density() {
    let gs = [-0.9f32, 0.0, 0.3, 0.9];
    let cfg = Chi2Config {
        samples: 500_000,
        theta_bins: 20,
        phi_bins: 40,
        num_tests: gs.len(),
        normalized: true,
        fine_step: 0.005,
        ..Default::default()
    };
    for g in gs {
        let hg = HenyeyGreenstein::new(g);
        let wo = Vec3::new(0.3, -0.5, 0.81).normalize();
        let r = assert_chi2(
            &format!("hg g={g}"),
            &cfg,
            |u| Some(hg.sample(wo, Vec2::new(u.x, u.y))),
            |wi| hg.eval(wo, wi),
        );
        eprintln!(
            "g {g}: chi2 {:.1} dof {} p {:.3}, pdf integral {:.5}",
            r.chi2, r.dof, r.p_value, r.pdf_integral
        );
        // The mean cosine between the travel directions before (-wi) and after (wo)
        // scattering is g.
        let n = 200_000;
        let mut rng = photonmap::sampling::Rng::new(1, 0);
        let mean_cos: f64 = (0..n)
            .map(|_| (-hg.sample(wo, rng.vec2()).0).dot(wo) as f64)
            .sum::<f64>()
            / n as f64;
        assert!(
            (mean_cos - g as f64).abs() < 0.01,
            "g {g}: mean cosine {mean_cos}"
        );
    }
}

fn slab_scene(sigma_a: f32, sigma_s: f32) -> SceneDesc {
    // A wide box of fog, 2 units along the camera ray (x) and 2 units deep below its top face
    // (y = 1), lit from straight above by a sun; the camera looks along +x through y = 0.
    let b = shapes::cuboid(Vec3::new(-1.0, -1.0, -20.0), Vec3::new(1.0, 1.0, 20.0));
    let mesh = MeshDesc {
        name: "fog".into(),
        positions: b.positions.iter().map(|p| p.to_array()).collect(),
        indices: b.indices.clone(),
        material: 0,
        interior_medium: Some(0),
        ..Default::default()
    };
    // Camera at x = -3 looking along +x: camera -Z maps to world +x.
    let cam = [
        [0.0, 0.0, -1.0, -3.0],
        [0.0, 1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    SceneDesc {
        camera: CameraDesc {
            transform: cam,
            fov: Some(0.02),
            ..Default::default()
        },
        film: FilmDesc {
            width: 8,
            height: 8,
            transparent: false,
        },
        materials: vec![MaterialDesc::Null {
            name: "boundary".into(),
        }],
        meshes: vec![mesh],
        lights: vec![LightDesc::Distant {
            name: "sun".into(),
            direction: [0.0, -1.0, 0.0],
            irradiance: 3.0,
            color: [1.0; 3],
            angle: 0.0,
        }],
        media: vec![MediumDesc {
            name: "fog".into(),
            sigma_a: [sigma_a; 3],
            sigma_s: [sigma_s; 3],
            g: 0.0,
            density: None,
        }],
        ..Default::default()
    }
}

fn render_single_scattering(desc: &SceneDesc, spp: u32) -> photonmap::render::RenderOutput {
    // No volume photons: the volume term is single scattering only.
    let photons = RenderSettings {
        volume_photons: 0,
        ..Default::default()
    };
    render_settings(
        desc,
        RenderSettings {
            spp,
            seed: 3,
            filter: FilterName::Box,
            ..photons
        },
    )
}

/// Single scattering along a ray crossing a slab of width W at depth h below the lit face:
/// L = sigma_s / (4 pi) E exp(-sigma_t h) (1 - exp(-sigma_t W)) / sigma_t (isotropic phase).
#[test]
fn single_scattering_matches_the_closed_form() {
    for (sa, ss) in [(0.1f32, 0.5f32), (0.0, 3.0), (1e-3, 1e-3)] {
        let out = render_single_scattering(&slab_scene(sa, ss), 64);
        let st = (sa + ss) as f64;
        let expected = ss as f64 / (4.0 * std::f64::consts::PI)
            * 3.0
            * (-st * 1.0).exp()
            * (1.0 - (-st * 2.0).exp())
            / st;
        let got = out.film.term(Term::Volume).mean();
        eprintln!("sigma_a {sa} sigma_s {ss}: volume {got:?}, closed form {expected:.6}");
        for c in 0..3 {
            assert!(
                (got[c] as f64 / expected - 1.0).abs() < 0.01,
                "channel {c}: {} vs {expected}",
                got[c]
            );
        }
        // Nothing else in the scene: every other term is zero, and the sum rule holds.
        assert_eq!(out.film.term(Term::Direct).mean(), Vec3::ZERO);
    }
}

#[test]
fn extinction_extremes_stay_finite_thin_is_vacuum_dense_is_dark() {
    for st in [1e-6f32, 1e-2, 1.0, 1e2, 1e4] {
        let mut desc = load_scene("cornell_diffuse");
        desc.film = FilmDesc {
            width: 24,
            height: 24,
            transparent: false,
        };
        desc.media = vec![MediumDesc {
            name: "fog".into(),
            sigma_a: [0.2 * st; 3],
            sigma_s: [0.8 * st; 3],
            g: 0.5,
            density: None,
        }];
        desc.world_medium = Some(0);
        let t0 = std::time::Instant::now();
        let out = render(&desc, 2, 1, 0);
        let secs = t0.elapsed().as_secs_f64();
        for t in Term::ALL {
            assert!(
                out.film
                    .term(t)
                    .data
                    .iter()
                    .all(|p| p.iter().all(|c| c.is_finite() && *c >= 0.0)),
                "sigma_t {st}: {} not finite",
                t.name()
            );
        }
        assert_eq!(out.stats.non_finite_samples, 0);
        let beauty = out.film.combined().mean();
        eprintln!("sigma_t {st}: beauty {beauty:?} in {secs:.2} s");
        if st >= 1e4 {
            assert!(
                beauty.max_element() < 1e-3,
                "a dense medium hides the scene: {beauty:?}"
            );
        }
    }
    // Thin: the same as vacuum within noise.
    let mut desc = load_scene("cornell_diffuse");
    desc.film = FilmDesc {
        width: 24,
        height: 24,
        transparent: false,
    };
    let vacuum = render(&desc, 64, 1, 0).film.term(Term::Direct).mean();
    desc.media = vec![MediumDesc {
        name: "fog".into(),
        sigma_a: [2e-7; 3],
        sigma_s: [8e-7; 3],
        g: 0.0,
        density: None,
    }];
    desc.world_medium = Some(0);
    let thin = render(&desc, 64, 1, 0);
    let d = thin.film.term(Term::Direct).mean();
    // The march draws random numbers too, so the two renders differ by noise (about 0.3% on
    // this mean at 64 spp), not by the medium's 1e-6 attenuation.
    for c in 0..3 {
        assert!(
            (d[c] / vacuum[c] - 1.0).abs() < 0.01,
            "thin medium changes direct light: {d:?} vs {vacuum:?}"
        );
    }
    assert!(thin.film.term(Term::Volume).mean().max_element() < 1e-4);
}

#[test]
fn media_free_scenes_build_no_volume_map() {
    let mut desc = load_scene("cornell_diffuse");
    desc.film = FilmDesc {
        width: 8,
        height: 8,
        transparent: false,
    };
    let out = render(&desc, 1, 0, 0);
    let v = out
        .stats
        .photon_maps
        .iter()
        .find(|m| m.map == "volume")
        .expect("volume map reported");
    assert!(
        !v.built && v.skipped_because.as_deref() == Some("the scene has no participating media"),
        "{v:?}"
    );
    assert!(out.stats.skipped.iter().any(|s| s.term == "volume"));
}

/// A density grid of constant density 1 is the homogeneous medium: the single-scattering
/// slab renders the same (transmittance by the midpoint rule is exact for constant density),
/// and a grid with density 2 matches the homogeneous medium with doubled coefficients.
#[test]
fn density_grid_matches_the_homogeneous_medium() {
    for (rho, scale) in [(1.0f32, 1.0f32), (2.0, 2.0)] {
        let homogeneous = slab_scene(0.1 * scale, 0.5 * scale);
        let mut grid = slab_scene(0.1, 0.5);
        // The grid covers the fog box [-1,1] x [-1,1] x [-20,20].
        let res = [4u32, 4, 8];
        grid.media[0].density = Some(DensityGridDesc {
            resolution: res,
            data: vec![rho; (res[0] * res[1] * res[2]) as usize],
            transform: [
                [2.0, 0.0, 0.0, -1.0],
                [0.0, 2.0, 0.0, -1.0],
                [0.0, 0.0, 40.0, -20.0],
                [0.0, 0.0, 0.0, 1.0],
            ],
        });
        let a = render_single_scattering(&homogeneous, 16)
            .film
            .term(Term::Volume)
            .mean();
        let b = render_single_scattering(&grid, 16)
            .film
            .term(Term::Volume)
            .mean();
        eprintln!("density {rho}: homogeneous {a:?}, grid {b:?}");
        assert!((b.x / a.x - 1.0).abs() < 0.005, "{a:?} vs {b:?}");
    }
}

#[test]
fn density_grid_validation_names_the_field() {
    let mut desc = slab_scene(0.1, 0.5);
    desc.media[0].density = Some(DensityGridDesc {
        resolution: [2, 2, 2],
        data: vec![1.0; 7],
        transform: photonmap::scene::desc::IDENTITY,
    });
    let e = photonmap::scene::validate(&desc).unwrap_err().to_string();
    assert!(
        e.contains("/media/0/density/data") && e.contains("expected 2x2x2 = 8"),
        "{e}"
    );
    desc.media[0].density = Some(DensityGridDesc {
        resolution: [2, 2, 2],
        data: vec![1.0, -1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0],
        transform: photonmap::scene::desc::IDENTITY,
    });
    let e = photonmap::scene::validate(&desc).unwrap_err().to_string();
    assert!(e.contains("/media/0/density/data/1"), "{e}");
    desc.media[0].density = Some(DensityGridDesc {
        resolution: [1, 1, 1],
        data: vec![1.0],
        transform: photonmap::scene::desc::IDENTITY,
    });
    desc.media[0].sigma_a = [0.1, 0.2, 0.1];
    let e = photonmap::scene::validate(&desc).unwrap_err().to_string();
    assert!(e.contains("grey extinction"), "{e}");
}

/// Photons fly through a grid by delta tracking: a fog of constant-density grid lights the
/// scene like the homogeneous fog (full render, all terms, means within 3%).
#[test]
fn density_grid_photons_match_homogeneous_photons() {
    let mut a = load_scene("fog_spot");
    a.film = FilmDesc {
        width: 32,
        height: 32,
        transparent: false,
    };
    let mut b = a.clone();
    // The fog box of fog_spot spans its first mesh with an interior medium; cover all of space
    // that box can occupy with a constant grid (density 1 inside the scene bounds).
    b.media[0].density = Some(DensityGridDesc {
        resolution: [2, 2, 2],
        data: vec![1.0; 8],
        transform: [
            [20.0, 0.0, 0.0, -10.0],
            [0.0, 20.0, 0.0, -10.0],
            [0.0, 0.0, 20.0, -10.0],
            [0.0, 0.0, 0.0, 1.0],
        ],
    });
    let ma = render(&a, 8, 4, 0).film.combined().mean();
    let mb = render(&b, 8, 4, 0).film.combined().mean();
    eprintln!("fog_spot homogeneous {ma:?}, constant grid {mb:?}");
    assert!((mb.x / ma.x - 1.0).abs() < 0.03, "{ma:?} vs {mb:?}");
}

/// The part of a volume estimate's sphere that photons reach, against the closed form of a
/// sphere of radius r cut by a plane at distance d from its centre: 1 - h^2 (3r - h) / (4 r^3)
/// with h = r - d; exactly 1 where the sphere misses every surface.
#[test]
fn reachable_fraction_matches_the_cut_sphere() {
    use photonmap::render::terms::volume::reachable_fraction;
    use photonmap::sampling::Rng;
    let scene = photonmap::scene::Scene::build(&slab_scene(0.1, 0.5)).unwrap();
    let r = 0.5f32;
    let mut rng = Rng::new(7, 0);
    // Below the top face (y = 1), far from the other faces.
    for d in [0.01f32, 0.1, 0.25, 0.4] {
        let x = Vec3::new(0.0, 1.0 - d, 0.0);
        let n = 40_000;
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let f = reachable_fraction(&scene, x, r, &mut rng) as f64;
            sum += f;
            sum2 += f * f;
        }
        let mean = sum / n as f64;
        let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        let h = (r - d) as f64;
        let exact = 1.0 - h * h * (3.0 * r as f64 - h) / (4.0 * (r as f64).powi(3));
        eprintln!("d {d}: fraction {mean:.4} +- {se:.4}, exact {exact:.4}");
        assert!(
            (mean - exact).abs() < 4.0 * se + 1e-3,
            "d {d}: {mean} vs {exact}"
        );
    }
    let deep = Vec3::new(0.0, 0.0, 0.0);
    for _ in 0..100 {
        assert_eq!(reachable_fraction(&scene, deep, r, &mut rng), 1.0);
    }
}

/// The volume map's precomputed points (isotropic media) against the k-nearest estimate at
/// every march step, on fog_glass made isotropic (its volume caustic under the glass sphere
/// is where a blurred estimate would show): the volume term of the two, from six seeds each,
/// agrees in every 8x8 block by a Welch t-test (the noise of each from the spread of its
/// seeds, photon maps included; 64 blocks at a family-wise false-alarm rate of 10^-3), and
/// in mean within 1.5%. A volume term 5% brighter fails the same comparison. The work
/// counters show which estimate ran: every read but a few from points with g = 0, none with
/// fog_glass's g = 0.3 or with the points switched off.
#[test]
fn volume_points_match_the_k_nearest_march() {
    use common::compare::{block_t_tests, Blocks, BLOCK_FWER};
    let mut desc = load_scene("fog_glass");
    desc.film.width = 64;
    desc.film.height = 64;
    for m in desc.media.iter_mut() {
        m.g = 0.0;
    }
    let run = |desc: &SceneDesc, points: bool, seed: u64| {
        render_settings(
            desc,
            RenderSettings {
                spp: 8,
                seed,
                filter: FilterName::Box,
                adaptive_sampling: false,
                photons: 50_000,
                caustic_photons: 50_000,
                volume_photons: 100_000,
                volume_points: points,
                ..Default::default()
            },
        )
    };
    let volume = |out: &photonmap::render::RenderOutput, k: f32| {
        let mut img = out.film.term(Term::Volume).clone();
        for p in img.data.iter_mut() {
            for c in p.iter_mut() {
                *c *= k;
            }
        }
        img
    };
    let knn: Vec<_> = (1..=6).map(|seed| run(&desc, false, seed)).collect();
    let pts: Vec<_> = (11..=16).map(|seed| run(&desc, true, seed)).collect();
    for out in &knn {
        assert_eq!(out.stats.work.volume_point_reads, 0);
    }
    for out in &pts {
        let w = out.stats.work;
        assert!(
            w.volume_point_reads as f64 > 0.95 * w.volume_lookups as f64,
            "{w:?}"
        );
    }
    let knn_blocks = Blocks::of_seeds(&knn.iter().map(|o| volume(o, 1.0)).collect::<Vec<_>>(), 8);
    let judge = |k: f32| {
        let b = Blocks::of_seeds(&pts.iter().map(|o| volume(o, k)).collect::<Vec<_>>(), 8);
        let tests = block_t_tests(&b, &knn_blocks, BLOCK_FWER);
        let over = tests.iter().filter(|t| t.2.abs() > t.4).count();
        let ratio = b.mean.iter().sum::<f64>() / knn_blocks.mean.iter().sum::<f64>();
        (over, ratio, tests[0])
    };
    let (over, ratio, worst) = judge(1.0);
    eprintln!(
        "volume points vs k-nearest: {over} of 64 blocks off, mean ratio {ratio:.4}; farthest \
         (bx, by, t, points/knn, critical |t|) {worst:?}"
    );
    assert!(over == 0, "{over} blocks off, the farthest {worst:?}");
    assert!((ratio - 1.0).abs() < 0.015, "mean ratio {ratio}");
    let (over5, ratio5, worst5) = judge(1.05);
    eprintln!("with the points' volume term x 1.05: {over5} blocks off, mean ratio {ratio5:.4}, farthest {worst5:?}");
    assert!(
        over5 > 0 || (ratio5 - 1.0).abs() >= 0.015,
        "a volume term 5% brighter passes: {over5} blocks off, mean ratio {ratio5:.4}"
    );
    // Anisotropic fog reads no points.
    let aniso = run(&load_scene("fog_glass"), true, 5);
    assert_eq!(aniso.stats.work.volume_point_reads, 0);
}
