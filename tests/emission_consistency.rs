//! Photons are emitted with the distribution the eye side sees: for every finite light kind,
//! the irradiance that photons deliver to the cells of a receiving plane (photon flux landing
//! in a cell over its area) equals the irradiance the light-sampling estimator (`sample_li`,
//! as the `direct` term uses it) gives over the same cell, cell by cell, within the two
//! estimates' combined noise.
//!
//! The plane is close to each light (about 2.5 radii for the lights with a radius), where a
//! sphere and Blender's soft-falloff disk differ, and spots are aimed so that the cone edge
//! crosses the plane. Run: `cargo test --release --test emission_consistency -- --nocapture`.

use glam::{Vec2, Vec3};
use photonmap::lights::*;
use photonmap::materials::{texture::Texture, Material};
use photonmap::math::{luminance, Spectrum, PI};
use photonmap::sampling::Rng;
use photonmap::scene::desc::{ColorInput, MaterialDesc};

/// Receiver: the square [-H, H]^2 of the plane z = 0, facing +z, in N x N cells.
const H: f32 = 1.2;
const N: usize = 8;

fn cell_area() -> f32 {
    (2.0 * H / N as f32).powi(2)
}

fn cell_of(p: Vec3) -> Option<usize> {
    let fx = (p.x + H) / (2.0 * H) * N as f32;
    let fy = (p.y + H) / (2.0 * H) * N as f32;
    (fx >= 0.0 && fy >= 0.0 && fx < N as f32 && fy < N as f32)
        .then(|| fy as usize * N + fx as usize)
}

/// Mean and standard error per cell.
struct Estimate {
    mean: Vec<f64>,
    se: Vec<f64>,
}

/// Photon side: the flux of photons whose straight flight first meets the plane (from above)
/// inside a cell, at a distance past their `min_travel`, over (photons emitted x cell area).
fn photon_irradiance(light: &Light, ctx: &LightCtx, photons: usize, seed: u64) -> Estimate {
    let mut sum = vec![0.0f64; N * N];
    let mut sum2 = vec![0.0f64; N * N];
    let mut rng = Rng::new(seed, 0);
    for _ in 0..photons {
        let Some(s) = light.sample_le(rng.vec2(), rng.vec2(), ctx) else {
            continue;
        };
        if !(s.d.z < 0.0 && s.o.z > 0.0) {
            continue;
        }
        let t = -s.o.z / s.d.z;
        if t < s.min_travel {
            continue;
        }
        if let Some(c) = cell_of(s.o + s.d * t) {
            let w = luminance(s.weight) as f64;
            sum[c] += w;
            sum2[c] += w * w;
        }
    }
    let n = photons as f64;
    let a = cell_area() as f64;
    Estimate {
        mean: sum.iter().map(|s| s / n / a).collect(),
        se: sum
            .iter()
            .zip(&sum2)
            .map(|(s, s2)| ((s2 / n - (s / n).powi(2)).max(0.0) / n).sqrt() / a)
            .collect(),
    }
}

/// Eye side: irradiance at uniform points of each cell from one light sample each,
/// L cos / pdf (the light is not occluded: the plane is all there is).
fn eye_irradiance(light: &Light, ctx: &LightCtx, per_cell: usize, seed: u64) -> Estimate {
    let mut rng = Rng::new(seed, 1);
    let side = 2.0 * H / N as f32;
    let mut mean = vec![0.0f64; N * N];
    let mut se = vec![0.0f64; N * N];
    for c in 0..N * N {
        let (cx, cy) = ((c % N) as f32, (c / N) as f32);
        let (mut s1, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..per_cell {
            let u = rng.vec2();
            let p = Vec3::new(-H + (cx + u.x) * side, -H + (cy + u.y) * side, 0.0);
            let e = match light.sample_li(p, Vec3::ZERO, rng.vec2(), ctx) {
                Some(ls) if ls.wi.z > 0.0 => (luminance(ls.li) * ls.wi.z / ls.pdf) as f64,
                _ => 0.0,
            };
            s1 += e;
            s2 += e * e;
        }
        let n = per_cell as f64;
        mean[c] = s1 / n;
        se[c] = ((s2 / n - mean[c].powi(2)).max(0.0) / n).sqrt();
    }
    Estimate { mean, se }
}

/// The largest |difference| in combined standard errors over the cells that receive light.
fn worst_z(a: &Estimate, b: &Estimate) -> (f64, usize, f64) {
    let peak = a.mean.iter().cloned().fold(0.0, f64::max);
    let mut worst = (0.0, 0, 0.0);
    for c in 0..N * N {
        let se = (a.se[c].powi(2) + b.se[c].powi(2)).sqrt();
        let d = a.mean[c] - b.mean[c];
        // Cells with (almost) nothing on either side are compared on the peak's scale.
        let z = d.abs() / se.max(1e-4 * peak);
        if z > worst.0 {
            worst = (z, c, d / a.mean[c].max(1e-12));
        }
    }
    worst
}

fn lights() -> Vec<(&'static str, Light)> {
    let at = Vec3::new(0.1, -0.05, 0.5);
    let aim = Vec3::new(0.35, 0.1, -1.0).normalize();
    let spot = SpotShape::new(aim, 50f32.to_radians(), 0.3);
    let point = |radius: f32, spot: Option<SpotShape>, soft: bool| {
        Light::Point(PointLight::new(at, 10.0, Spectrum::ONE, radius, spot, soft))
    };
    let area = |shape, ex: Vec3, ey: Vec3, two_sided, spread: f32| {
        Light::Area(AreaLight::new(
            shape,
            Vec3::new(0.05, 0.1, 0.6),
            ex,
            ey,
            -Vec3::Z,
            10.0,
            Spectrum::ONE,
            two_sided,
            spread,
        ))
    };
    let tilted_x = Vec3::new(0.3, 0.0, 0.1);
    let tilted_y = Vec3::new(0.0, 0.2, 0.0);
    vec![
        ("point", point(0.0, None, false)),
        ("sphere", point(0.2, None, false)),
        ("sphere_soft_falloff", point(0.2, None, true)),
        ("spot", point(0.0, Some(spot), false)),
        ("spot_radius", point(0.2, Some(spot), false)),
        ("spot_radius_soft_falloff", point(0.2, Some(spot), true)),
        ("rect", area(AreaShape::Rect, tilted_x, tilted_y, false, PI)),
        (
            "rect_spread_60",
            area(
                AreaShape::Rect,
                tilted_x,
                tilted_y,
                false,
                60f32.to_radians(),
            ),
        ),
        (
            "ellipse_two_sided_spread_120",
            area(
                AreaShape::Disk,
                Vec3::X * 0.35,
                Vec3::Y * 0.15,
                true,
                120f32.to_radians(),
            ),
        ),
        (
            "triangle",
            Light::Triangle(TriangleLight::new(
                [
                    Vec3::new(-0.3, -0.2, 0.55),
                    Vec3::new(0.4, -0.1, 0.45),
                    Vec3::new(0.0, 0.35, 0.6),
                ],
                [Vec2::ZERO, Vec2::X, Vec2::Y],
                0,
                0,
                0,
            )),
        ),
    ]
}

fn emissive() -> Vec<Material> {
    vec![Material::from_desc(&MaterialDesc::Emission {
        name: "glow".into(),
        color: ColorInput::Value([1.0, 1.0, 1.0]),
        strength: 3.0,
    })]
}

/// Cells compared per light, times lights: about 640 comparisons, so 5 sigma.
const Z_MAX: f64 = 5.0;

#[test]
fn photons_deliver_what_light_sampling_sees() {
    let materials = emissive();
    let textures: Vec<Texture> = vec![];
    let ctx = LightCtx {
        materials: &materials,
        objects: &[],
        textures: &textures,
        scene_center: Vec3::ZERO,
        scene_radius: 3.0,
    };
    for (name, light) in lights() {
        let ph = photon_irradiance(&light, &ctx, 2_000_000, 3);
        let eye = eye_irradiance(&light, &ctx, 4096, 4);
        let (z, cell, rel) = worst_z(&eye, &ph);
        let total_eye: f64 = eye.mean.iter().sum();
        let total_ph: f64 = ph.mean.iter().sum();
        eprintln!(
            "{name}: worst cell {cell} at {z:.2} sigma ({:+.2}%), totals eye {total_eye:.6} photons {total_ph:.6}",
            -100.0 * rel
        );
        assert!(
            z < Z_MAX,
            "{name}: cell {cell} differs by {z:.1} sigma ({:+.2}%)",
            -100.0 * rel
        );
    }
}

/// The comparison bites: photons of a spot whose attenuation is taken at the sampled point of
/// its sphere (the centre-outwards direction) instead of along the photon's direction, or of
/// a sphere read as the soft-falloff disk, fail it.
#[test]
fn the_emission_comparison_catches_a_wrong_emitter() {
    let materials = emissive();
    let textures: Vec<Texture> = vec![];
    let ctx = LightCtx {
        materials: &materials,
        objects: &[],
        textures: &textures,
        scene_center: Vec3::ZERO,
        scene_radius: 3.0,
    };
    let all = lights();
    let get = |n: &str| all.iter().find(|(k, _)| *k == n).unwrap().1.clone();
    // Eye side of the sphere against photons of the soft-falloff disk.
    let eye = eye_irradiance(&get("sphere"), &ctx, 4096, 4);
    let ph = photon_irradiance(&get("sphere_soft_falloff"), &ctx, 2_000_000, 3);
    let (z, _, rel) = worst_z(&eye, &ph);
    eprintln!(
        "sphere vs soft-falloff photons: {z:.1} sigma ({:+.2}%)",
        -100.0 * rel
    );
    assert!(
        z > 2.0 * Z_MAX,
        "sphere and soft falloff not told apart: {z}"
    );
    // A spot 5 degrees off its axis.
    let Light::Point(mut p) = get("spot_radius") else {
        unreachable!()
    };
    let eye = eye_irradiance(&Light::Point(p.clone()), &ctx, 4096, 4);
    let s = p.spot.unwrap();
    let axis = glam::Quat::from_rotation_y(5f32.to_radians()) * s.axis;
    p.spot = Some(SpotShape { axis, ..s });
    let ph = photon_irradiance(&Light::Point(p), &ctx, 2_000_000, 3);
    let (z, _, rel) = worst_z(&eye, &ph);
    eprintln!(
        "spot rotated 5 degrees: {z:.1} sigma ({:+.2}%)",
        -100.0 * rel
    );
    assert!(
        z > 2.0 * Z_MAX,
        "a 5 degree spot rotation was not caught: {z}"
    );
}

/// A spot with a radius keeps its cone (Cycles takes the attenuation along the direction from
/// the point on the emitter to the receiver): receivers whose every view of the emitter lies
/// outside the cone get exactly nothing, and receivers that see the whole emitter inside the
/// cone's flat top get a point light's irradiance (a uniform sphere wholly above the
/// horizon gives exactly I cos / d^2), for the sphere and, to O(r^2/d^2), the soft disk.
#[test]
fn spot_with_radius_keeps_its_cone() {
    let materials = emissive();
    let textures: Vec<Texture> = vec![];
    let ctx = LightCtx {
        materials: &materials,
        objects: &[],
        textures: &textures,
        scene_center: Vec3::ZERO,
        scene_radius: 3.0,
    };
    let at = Vec3::new(0.0, 0.0, 2.0);
    let spot = SpotShape::new(-Vec3::Z, 40f32.to_radians(), 0.2);
    let r = 0.1f32;
    for soft in [false, true] {
        let l = Light::Point(PointLight::new(
            at,
            10.0,
            Spectrum::ONE,
            r,
            Some(spot),
            soft,
        ));
        let point = Light::Point(PointLight::new(
            at,
            10.0,
            Spectrum::ONE,
            0.0,
            Some(spot),
            false,
        ));
        let mut rng = Rng::new(11, 0);
        let half = 20f32.to_radians();
        let inner = (spot.cos_half + spot.smooth).acos();
        for (x, expect_dark) in [(0.0, false), (0.3, false), (1.2, true), (2.0, true)] {
            let p = Vec3::new(x, 0.0, 0.0);
            let d = (at - p).length();
            let ang = (x / 2.0f32).atan();
            let margin = (r / d).asin() * 1.05;
            if expect_dark {
                assert!(ang - margin > half, "receiver {x} is not outside the cone");
            } else {
                assert!(ang + margin < inner, "receiver {x} is not in the flat top");
            }
            let n = 20_000;
            let (mut s1, mut s2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let e = l
                    .sample_li(p, Vec3::ZERO, rng.vec2(), &ctx)
                    .filter(|ls| ls.wi.z > 0.0)
                    .map_or(0.0, |ls| (luminance(ls.li) * ls.wi.z / ls.pdf) as f64);
                s1 += e;
                s2 += e * e;
            }
            let mean = s1 / n as f64;
            let se = ((s2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
            let exact = point
                .sample_li(p, Vec3::ZERO, Vec2::ZERO, &ctx)
                .map_or(0.0, |ls| (luminance(ls.li) * ls.wi.z) as f64);
            eprintln!(
                "soft {soft} receiver x={x}: E {mean:.6} +- {se:.2e}, point light {exact:.6}"
            );
            if expect_dark {
                assert_eq!(mean, 0.0, "soft {soft}: light outside the cone at x={x}");
            } else {
                // The soft disk delivers d^2/(d^2 + r^2) of the sphere's irradiance on axis.
                let tol = if soft {
                    1.5 * (r * r / (d * d)) as f64
                } else {
                    0.0
                };
                assert!(
                    (mean - exact).abs() <= 4.0 * se + tol * exact + 1e-4 * exact,
                    "soft {soft} x={x}: {mean} vs {exact}"
                );
            }
        }
    }
}
