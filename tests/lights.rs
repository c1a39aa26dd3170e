//! Light sampling: chi-square of every non-delta light's `sample_li` against its `pdf_li`, and
//! each light's power Φ against a Monte Carlo estimate of the flux through an enclosing sphere.

use glam::{Vec2, Vec3};
use photonmap::lights::*;
use photonmap::materials::{texture::Texture, Material};
use photonmap::math::{Spectrum, Transform, PI};
use photonmap::sampling::chi2::{assert_chi2, Chi2Config};
use photonmap::sampling::{warp, Rng};
use photonmap::scene::desc::{ColorInput, MaterialDesc, TextureDesc, WrapMode};

fn emissive_materials() -> Vec<Material> {
    vec![Material::from_desc(&MaterialDesc::Emission {
        name: "glow".into(),
        color: ColorInput::Value([1.0, 0.5, 0.25]),
        strength: 3.0,
    })]
}

fn ctx<'a>(materials: &'a [Material], textures: &'a [Texture]) -> LightCtx<'a> {
    LightCtx {
        materials,
        textures,
        objects: &[],
        scene_center: Vec3::ZERO,
        scene_radius: 10.0,
    }
}

fn sky_texture() -> Texture {
    // A bright spot on a dim sky, to exercise importance sampling.
    let (w, h) = (32u32, 16u32);
    let mut data = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let v = if (i, j) == (5, 4) || (i, j) == (6, 4) {
                50.0
            } else {
                0.2 + (i as f32) / 64.0
            };
            data.extend_from_slice(&[v, v * 0.8, v * 0.6]);
        }
    }
    Texture::from_desc(&TextureDesc {
        name: "sky".into(),
        width: w,
        height: h,
        channels: 3,
        data,
        wrap: WrapMode::Repeat,
        encoding: Default::default(),
    })
}

fn rect_light() -> Light {
    let t = Transform::from_rows(&[
        [1.0, 0.0, 0.0, 0.2],
        [0.0, 0.0, 1.0, 1.0],
        [0.0, -1.0, 0.0, 0.1],
        [0.0, 0.0, 0.0, 1.0],
    ])
    .unwrap();
    Light::Area(AreaLight::new(
        AreaShape::Rect,
        t.point(Vec3::ZERO),
        t.vector(Vec3::X * 0.6),
        t.vector(Vec3::Y * 0.3),
        t.normal(-Vec3::Z),
        10.0,
        Spectrum::ONE,
        false,
        PI,
    ))
}

fn disk_light() -> Light {
    Light::Area(AreaLight::new(
        AreaShape::Disk,
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::X * 0.5,
        Vec3::Z * 0.3,
        -Vec3::Y,
        5.0,
        Spectrum::ONE,
        true,
        PI,
    ))
}

/// A rectangle whose emission is narrowed by Blender's Spread (60 degrees).
fn rect_spread_light() -> Light {
    Light::Area(AreaLight::new(
        AreaShape::Rect,
        Vec3::new(0.1, 1.0, 0.0),
        Vec3::X * 0.4,
        Vec3::Z * 0.25,
        -Vec3::Y,
        10.0,
        Spectrum::ONE,
        false,
        60f32.to_radians(),
    ))
}

/// A sphere light as Blender draws it with Soft Falloff: a disk facing the shading point.
fn soft_sphere_light() -> Light {
    Light::Point(PointLight::new(
        Vec3::new(0.3, 1.2, -0.2),
        20.0,
        Spectrum::ONE,
        0.4,
        None,
        true,
    ))
}

/// Distance along `d` from `o` to the light's surface, for the chi-square pdf.
fn hit_light(light: &Light, o: Vec3, d: Vec3, ctx: &LightCtx) -> Option<(Vec3, Vec3)> {
    match light {
        Light::Area(a) => a.intersect(o, d, f32::INFINITY).map(|t| (o + d * t, a.n)),
        Light::Point(p) => p
            .intersect(o, d, f32::INFINITY)
            .map(|(t, n)| (o + d * t, n)),
        Light::Triangle(tri) => {
            let _ = ctx;
            let (e1, e2) = (tri.v[1] - tri.v[0], tri.v[2] - tri.v[0]);
            let pv = d.cross(e2);
            let det = e1.dot(pv);
            if det.abs() < 1e-12 {
                return None;
            }
            let tv = o - tri.v[0];
            let u = tv.dot(pv) / det;
            let qv = tv.cross(e1);
            let v = d.dot(qv) / det;
            let t = e2.dot(qv) / det;
            (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then(|| (o + d * t, tri.n))
        }
        _ => Some((Vec3::ZERO, Vec3::ZERO)),
    }
}

fn lights_under_test() -> Vec<(&'static str, Light)> {
    let tex = sky_texture();
    vec![
        (
            "sphere",
            Light::Point(PointLight::new(
                Vec3::new(0.3, 1.2, -0.2),
                20.0,
                Spectrum::ONE,
                0.4,
                None,
                false,
            )),
        ),
        ("sphere_soft_falloff", soft_sphere_light()),
        ("rect", rect_light()),
        ("rect_spread", rect_spread_light()),
        ("disk", disk_light()),
        (
            "distant_with_angle",
            Light::Distant(DistantLight::new(
                Vec3::new(0.2, -1.0, 0.1),
                3.0,
                Spectrum::ONE,
                0.3,
            )),
        ),
        (
            "environment_constant",
            Light::Environment(EnvironmentLight::new(
                Spectrum::ONE,
                None,
                Transform::IDENTITY,
            )),
        ),
        (
            "environment_image",
            Light::Environment(EnvironmentLight::new(
                Spectrum::ONE,
                Some(tex),
                Transform::IDENTITY,
            )),
        ),
        (
            "triangle",
            Light::Triangle(TriangleLight::new(
                [
                    Vec3::new(-0.5, 1.0, -0.5),
                    Vec3::new(0.7, 1.1, -0.4),
                    Vec3::new(0.0, 0.9, 0.6),
                ],
                [Vec2::ZERO, Vec2::X, Vec2::Y],
                0,
                0,
                0,
            )),
        ),
    ]
}

#[test]
fn light_sampling_matches_its_pdf() {
    let materials = emissive_materials();
    let textures: Vec<Texture> = vec![];
    let c = ctx(&materials, &textures);
    let p = Vec3::new(0.05, 0.0, 0.02);
    // Every light from a point in a medium (no reference normal), and the lights at infinity
    // also from a surface facing `up` (a constant world is cosine-weighted about it).
    let up = Vec3::new(0.3, -0.2, 0.9).normalize();
    let all: Vec<(String, Light, Vec3)> = lights_under_test()
        .into_iter()
        .flat_map(|(name, light)| {
            let mut v = vec![(name.to_string(), light.clone(), Vec3::ZERO)];
            if light.is_infinite() {
                v.push((format!("{name}_about_a_normal"), light, up));
            }
            v
        })
        .collect();
    let cfg = Chi2Config {
        samples: 400_000,
        theta_bins: 20,
        phi_bins: 40,
        num_tests: all.len(),
        fine_step: 0.005,
        ..Default::default()
    };
    for (name, light, n) in &all {
        let r = assert_chi2(
            name,
            &cfg,
            |u| {
                let s = light.sample_li(p, *n, Vec2::new(u.x, u.y), &c)?;
                Some((s.wi, s.pdf))
            },
            |d| match hit_light(light, p, d, &c) {
                Some((pl, nl)) => light.pdf_li(p, *n, d, pl, nl),
                None => 0.0,
            },
        );
        eprintln!(
            "{name}: chi2 {:.1} dof {} p {:.3}",
            r.chi2, r.dof, r.p_value
        );
    }
}

/// Φ against the flux through a sphere of radius R around the light: Φ = 4 pi R^2 E[E(x)],
/// with E(x) = L cos / pdf from one light sample at a uniform point x on the sphere.
#[test]
fn light_power_matches_monte_carlo_flux() {
    let materials = emissive_materials();
    let textures: Vec<Texture> = vec![];
    let c = ctx(&materials, &textures);
    let spot = SpotShape::new(Vec3::new(0.0, -1.0, 0.2), 1.2, 0.4);
    let mut lights = lights_under_test();
    lights.retain(|(_, l)| !l.is_infinite());
    lights.push((
        "point",
        Light::Point(PointLight::new(
            Vec3::new(0.1, 0.2, 0.0),
            7.0,
            Spectrum::new(1.0, 0.5, 0.2),
            0.0,
            None,
            false,
        )),
    ));
    lights.push((
        "spot",
        Light::Point(PointLight::new(
            Vec3::ZERO,
            7.0,
            Spectrum::ONE,
            0.0,
            Some(spot),
            false,
        )),
    ));
    for soft in [false, true] {
        lights.push((
            if soft {
                "spot_with_radius_soft_falloff"
            } else {
                "spot_with_radius"
            },
            Light::Point(PointLight::new(
                Vec3::ZERO,
                7.0,
                Spectrum::ONE,
                0.1,
                Some(spot),
                soft,
            )),
        ));
    }
    let radius = 25.0f32;
    let n = 400_000;
    for (name, light) in &lights {
        let mut rng = Rng::new(9, 0);
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let x = warp::square_to_uniform_sphere(rng.vec2()) * radius;
            let e = match light.sample_li(x, Vec3::ZERO, rng.vec2(), &c) {
                Some(s) => {
                    let cos = s.wi.dot(-x.normalize()).max(0.0);
                    photonmap::math::luminance(s.li) as f64 * cos as f64 / s.pdf as f64
                }
                None => 0.0,
            };
            sum += e;
            sum2 += e * e;
        }
        let area = 4.0 * PI as f64 * (radius as f64).powi(2);
        let mean = sum / n as f64;
        let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        let (est, se) = (mean * area, se * area);
        let phi = photonmap::math::luminance(light.power(&c)) as f64;
        eprintln!("{name}: power {phi:.4}, Monte Carlo {est:.4} +- {se:.4}");
        assert!(
            (est - phi).abs() < 4.0 * se + 2e-3 * phi,
            "{name}: power {phi} but flux {est} +- {se}"
        );
    }
}

/// Photon emission: the directions `sample_le` draws follow each light's emission density
/// (uniform for point and sphere lights, the cone for spots, cosine about the normal for area
/// lights, both faces for two-sided emitters), and the mean photon weight is the light's power.
#[test]
fn photon_emission_directions_and_flux() {
    let materials = emissive_materials();
    let textures: Vec<Texture> = vec![];
    let c = ctx(&materials, &textures);
    let spot = SpotShape::new(Vec3::new(0.3, -1.0, 0.2), 1.0, 0.0);
    let rect_n = match rect_light() {
        Light::Area(a) => a.n,
        _ => unreachable!(),
    };
    let tri = lights_under_test()
        .into_iter()
        .find(|(n, _)| *n == "triangle")
        .unwrap()
        .1;
    let tri_n = match &tri {
        Light::Triangle(t) => t.n,
        _ => unreachable!(),
    };
    let cases: Vec<(&str, Light, Box<dyn Fn(Vec3) -> f32 + Sync>)> = vec![
        (
            "point",
            Light::Point(PointLight::new(
                Vec3::ZERO,
                7.0,
                Spectrum::ONE,
                0.0,
                None,
                false,
            )),
            Box::new(|_| 1.0 / (4.0 * PI)),
        ),
        (
            "spot",
            Light::Point(PointLight::new(
                Vec3::ZERO,
                7.0,
                Spectrum::ONE,
                0.0,
                Some(spot),
                false,
            )),
            {
                let s = spot;
                Box::new(move |d: Vec3| {
                    if d.dot(s.axis) > s.cos_half {
                        warp::uniform_cone_pdf(s.cos_half)
                    } else {
                        0.0
                    }
                })
            },
        ),
        (
            "sphere",
            Light::Point(PointLight::new(
                Vec3::ONE,
                3.0,
                Spectrum::ONE,
                0.3,
                None,
                false,
            )),
            Box::new(|_| 1.0 / (4.0 * PI)),
        ),
        (
            "rect",
            rect_light(),
            Box::new(move |d: Vec3| d.dot(rect_n).max(0.0) / PI),
        ),
        (
            "disk_two_sided",
            disk_light(),
            Box::new(|d: Vec3| d.dot(-Vec3::Y).abs() / (2.0 * PI)),
        ),
        (
            "triangle",
            tri,
            Box::new(move |d: Vec3| d.dot(tri_n).abs() / (2.0 * PI)),
        ),
    ];
    let cfg = Chi2Config {
        samples: 300_000,
        theta_bins: 20,
        phi_bins: 40,
        num_tests: cases.len(),
        ..Default::default()
    };
    for (name, light, pdf) in &cases {
        let mut rng = Rng::new(1, 0);
        assert_chi2(
            name,
            &cfg,
            |u| {
                let s = light.sample_le(Vec2::new(u.x, u.y), rng.vec2(), &c)?;
                Some((s.d, f32::NAN))
            },
            |d| pdf(d),
        );
        let n = 200_000;
        let mut sum = 0.0f64;
        let mut rng = Rng::new(6, 0);
        for _ in 0..n {
            if let Some(s) = light.sample_le(rng.vec2(), rng.vec2(), &c) {
                sum += photonmap::math::luminance(s.weight) as f64;
            }
        }
        let est = sum / n as f64;
        let phi = photonmap::math::luminance(light.power(&c)) as f64;
        eprintln!("{name}: power {phi:.4}, mean photon weight {est:.4}");
        assert!((est / phi - 1.0).abs() < 0.01, "{name}: {est} vs {phi}");
    }
}

/// A spot with a radius seen by a ray (a camera ray, or a BSDF sample of next-event
/// estimation, which MIS weighs against the light sample) shows the radiance that its light
/// sample sends to the ray's origin from the same point: the cone is taken along the light's
/// travel, from the emitter to the origin. Receivers inside the cone see the emitter lit,
/// receivers behind the spot (its back, or a ceiling it pierces) dark.
#[test]
fn spot_emitter_seen_by_a_ray_matches_its_light_sample() {
    let spot = SpotShape::new(Vec3::new(0.0, -1.0, 0.3).normalize(), 0.7, 0.05);
    let mut rng = Rng::new(3, 0);
    for soft in [false, true] {
        let light = PointLight::new(Vec3::ZERO, 50.0, Spectrum::ONE, 0.2, Some(spot), soft);
        let (mut lit, mut dark) = (0, 0);
        for _ in 0..4000 {
            // Receivers from 0.25 to 2 from the centre, all around it.
            let p = warp::square_to_uniform_sphere(rng.vec2()) * (0.25 + 1.75 * rng.f32());
            let Some(ls) = light.sample_li(p, rng.vec2()) else {
                continue;
            };
            let Some((t, _)) = light.intersect(p, ls.wi, f32::INFINITY) else {
                continue;
            };
            let seen = light.le(ls.wi);
            let want = ls.li;
            assert!(
                (seen - want).abs().max_element() <= 1e-3 * want.max_element().max(1.0),
                "soft {soft}: receiver {p}, towards {} at t {t}: a ray sees {seen:?}, the light \
                 sample sends {want:?}",
                ls.wi
            );
            if want.max_element() > 0.0 {
                lit += 1;
            } else {
                dark += 1;
            }
        }
        assert!(
            lit > 100 && dark > 1000,
            "soft {soft}: {lit} lit, {dark} dark"
        );
    }
}
