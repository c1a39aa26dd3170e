//! Chi-square tests of every BSDF sampling routine through the shared harness, and the
//! discrete reflection/refraction choice of the smooth dielectric against Fresnel.

use glam::{Vec2, Vec3};
use photonmap::materials::fresnel::{fresnel_dielectric, Fresnel};
use photonmap::materials::{
    dielectric_lobe, reflection_lobe, refraction_lobe, Bsdf, Lobe, Material,
};
use photonmap::math::Frame;
use photonmap::sampling::chi2::{assert_chi2, Chi2Config, Chi2Report};
use photonmap::sampling::Rng;
use photonmap::scene::desc::{ColorInput, FloatInput, MaterialDesc, PrincipledDesc};

/// Tests in this file, for the Šidák correction.
const NUM_TESTS: usize = 74;

fn local() -> Frame {
    Frame {
        s: Vec3::X,
        t: Vec3::Y,
        n: Vec3::Z,
    }
}

/// Direction at `deg` from +z (negative: from -z, inside), at azimuth 0.4 rad.
fn wo_at(deg: f32) -> Vec3 {
    let t = deg.to_radians();
    let phi = 0.4f32;
    let v = Vec3::new(t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos());
    v.normalize()
}

fn cfg(fine_step: f64, normalized: bool) -> Chi2Config {
    Chi2Config {
        samples: 1_000_000,
        num_tests: NUM_TESTS,
        fine_step,
        normalized,
        seed: 17,
        ..Default::default()
    }
}

fn chi2_bsdf(name: &str, bsdf: &Bsdf, wo: Vec3, cfg: &Chi2Config) -> Chi2Report {
    let r = assert_chi2(
        name,
        cfg,
        |u| {
            let s = bsdf.sample(wo, u.x, Vec2::new(u.y, u.z))?;
            if s.is_delta() {
                return None;
            }
            Some((s.wi, s.pdf))
        },
        |wi| bsdf.pdf(wo, wi),
    );
    eprintln!("{name}: {r}");
    r
}

#[test]
fn chi2_lambert() {
    let m = Material::from_desc(&MaterialDesc::Diffuse {
        name: "white".into(),
        color: ColorInput::Value([0.5, 0.7, 0.9]),
    });
    let bsdf = m.bsdf(local(), Vec2::ZERO, &[]);
    for deg in [0.0, 45.0, 85.0] {
        chi2_bsdf(
            &format!("lambert {deg}"),
            &bsdf,
            wo_at(deg),
            &cfg(0.02, true),
        );
        // Two-sided: seen from below it mirrors.
        chi2_bsdf(
            &format!("lambert back {deg}"),
            &bsdf,
            -wo_at(deg),
            &cfg(0.02, true),
        );
    }
}

#[test]
fn chi2_ggx_reflection() {
    let gold = Fresnel::Conductor {
        eta: Vec3::new(0.18, 0.42, 1.37),
        k: Vec3::new(3.42, 2.35, 1.77),
    };
    for roughness in [0.05f32, 0.3, 1.0] {
        let bsdf = Bsdf::new(local()).with(1.0, reflection_lobe(roughness, gold, false));
        for deg in [0.0f32, 30.0, 60.0, 85.0] {
            let wo = wo_at(deg);
            // The reflected lobe is about alpha x cos(theta_o) wide across the plane of
            // incidence; the quadrature panels must be narrower.
            let alpha = (roughness * roughness) as f64;
            let fine = (4.0 * alpha * (wo.z as f64).max(0.08)).clamp(8e-4, 0.02);
            chi2_bsdf(
                &format!("ggx r={roughness} {deg}"),
                &bsdf,
                wo,
                &cfg(fine, false),
            );
        }
    }
}

#[test]
fn chi2_rough_dielectric() {
    for (ior, multiscatter) in [(1.5f32, false), (2.4, true)] {
        for roughness in [0.3f32, 0.7] {
            let bsdf = Bsdf::new(local()).with(
                1.0,
                dielectric_lobe(ior, roughness, Vec3::new(1.0, 0.8, 0.6), multiscatter),
            );
            assert!(matches!(
                bsdf.lobes().next(),
                Some((_, Lobe::RoughDielectric(_)))
            ));
            for deg in [10.0f32, 60.0, 85.0, 180.0 - 20.0, 180.0 - 70.0] {
                let fine = if roughness < 0.5 { 0.006 } else { 0.02 };
                chi2_bsdf(
                    &format!("rough dielectric ior={ior} r={roughness} {deg}"),
                    &bsdf,
                    wo_at(deg),
                    &cfg(fine, false),
                );
            }
        }
    }
}

#[test]
fn nearly_index_matched_dielectric_is_a_clean_pass_through() {
    // IOR 1.0001: a rough interface refracts into a lobe ~ alpha |eta - 1| wide, so the
    // material treats it as smooth: a delta straight through, reflection ~ 1e-9.
    for roughness in [0.0f32, 0.3, 1.0] {
        let bsdf =
            Bsdf::new(local()).with(1.0, dielectric_lobe(1.0001, roughness, Vec3::ONE, true));
        let mut rng = Rng::new(3, 0);
        for deg in [0.0f32, 40.0, 85.0, 130.0] {
            let wo = wo_at(deg);
            let (r, ..) = fresnel_dielectric(wo.z, 1.0001);
            assert!(r < 1e-4, "{r}");
            for _ in 0..1000 {
                let s = bsdf.sample(wo, rng.f32(), rng.vec2()).expect("a sample");
                assert!(s.is_delta());
                if s.wi.z * wo.z < 0.0 {
                    // Snell bends it by at most ~ |eta - 1| / cos(theta) (1e-3 at 85 degrees).
                    assert!((s.wi + wo).length() < 3e-3, "straight through: {:?}", s.wi);
                    assert!((s.weight - Vec3::ONE).abs().max_element() < 1e-4);
                }
            }
            assert_eq!(bsdf.pdf(wo, -wo), 0.0);
            assert_eq!(bsdf.eval(wo, -wo), Vec3::ZERO);
        }
    }
}

#[test]
fn smooth_dielectric_choice_follows_fresnel_and_tir() {
    let n = 200_000;
    for ior in [1.0001f32, 1.5, 2.4] {
        let bsdf = Bsdf::new(local()).with(1.0, dielectric_lobe(ior, 0.0, Vec3::ONE, true));
        for deg in [0.0f32, 30.0, 60.0, 80.0, 89.0, 150.0, 120.0, 100.0] {
            let wo = wo_at(deg);
            let (r, cos_t, _, _) = fresnel_dielectric(wo.z, ior);
            let mut rng = Rng::new(5, deg as u64);
            let mut reflected = 0usize;
            for _ in 0..n {
                let s = bsdf.sample(wo, rng.f32(), rng.vec2()).expect("a sample");
                assert!(s.is_delta());
                if s.wi.z * wo.z > 0.0 {
                    reflected += 1;
                    assert!(
                        (s.pdf - r).abs() < 1e-6,
                        "pdf is the discrete probability R"
                    );
                    assert!((s.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-5);
                    assert_eq!(s.eta, 1.0);
                } else {
                    assert!((s.pdf - (1.0 - r)).abs() < 1e-6);
                    assert!((s.wi.z - cos_t).abs() < 1e-4, "Snell");
                    // Snell's law: eta_i sin_i = eta_t sin_t.
                    let sin_i = (1.0 - wo.z * wo.z).sqrt();
                    let sin_t = (1.0 - s.wi.z * s.wi.z).max(0.0).sqrt();
                    assert!((sin_i - s.eta * sin_t).abs() < 1e-4);
                    // The camera's weight is the tint (no 1/eta^2, as in Cycles); the
                    // photon's, its adjoint, is scaled by 1/eta^2.
                    assert!((s.weight - Vec3::ONE).abs().max_element() < 1e-5);
                    let w = s.importance_weight() * s.eta * s.eta;
                    assert!((w - Vec3::ONE).abs().max_element() < 1e-5);
                }
            }
            let frac = reflected as f64 / n as f64;
            let sigma = (r as f64 * (1.0 - r as f64) / n as f64).sqrt();
            assert!(
                (frac - r as f64).abs() <= 5.0 * sigma + 1e-9,
                "ior {ior}, {deg} deg: reflected {frac} vs Fresnel {r}"
            );
            let critical = (1.0 / ior).asin().to_degrees();
            if wo.z < 0.0 && 180.0 - deg > critical {
                assert_eq!(r, 1.0, "total internal reflection");
                assert_eq!(reflected, n);
            }
        }
    }
}

fn principled(f: impl FnOnce(&mut PrincipledDesc)) -> Material {
    let mut d = PrincipledDesc {
        base_color: ColorInput::Value([0.9, 0.6, 0.3]),
        ..Default::default()
    };
    f(&mut d);
    Material::from_desc(&MaterialDesc::Principled(Box::new(d)))
}

#[test]
fn chi2_principled_mixture() {
    let sets: Vec<(&str, Material, f64)> = vec![
        ("plastic r=0.5", principled(|_| {}), 0.02),
        (
            "plastic r=0.2",
            principled(|d| d.roughness = FloatInput::Value(0.2)),
            0.006,
        ),
        (
            "half metal r=0.3",
            principled(|d| {
                d.metallic = FloatInput::Value(0.5);
                d.roughness = FloatInput::Value(0.3);
            }),
            0.008,
        ),
        (
            "frosted glass r=0.4 t=0.7",
            principled(|d| {
                d.transmission = 0.7;
                d.roughness = FloatInput::Value(0.4);
            }),
            0.01,
        ),
        (
            "everything r=0.5",
            principled(|d| {
                d.metallic = FloatInput::Value(0.3);
                d.transmission = 0.5;
                d.specular = 2.0;
                d.ior = 1.45;
            }),
            0.02,
        ),
        (
            "smooth plastic (delta coat)",
            principled(|d| d.roughness = FloatInput::Value(0.0)),
            0.02,
        ),
    ];
    for (name, m, fine) in &sets {
        let bsdf = m.bsdf(local(), Vec2::ZERO, &[]);
        for deg in [5.0f32, 50.0, 80.0] {
            chi2_bsdf(
                &format!("principled {name} {deg}"),
                &bsdf,
                wo_at(deg),
                &cfg(*fine, false),
            );
        }
    }
}

/// Lobes in two frames (a specular normal bent away from the diffuse one, as under a normal
/// map): the mixture still samples its own pdf, and a sample's weight is f |cos| / pdf.
#[test]
fn chi2_split_normals() {
    let bent = Vec3::new(0.35, -0.2, 1.0).normalize();
    let sets: Vec<(&str, Bsdf, f64)> = vec![
        (
            "plastic r=0.3",
            principled(|d| d.roughness = FloatInput::Value(0.3)).bsdf(local(), Vec2::ZERO, &[]),
            0.008,
        ),
        (
            "lambert + rough glass r=0.4",
            Bsdf::new(local())
                .with(0.5, dielectric_lobe(1.5, 0.4, Vec3::ONE, false))
                .with(
                    0.5,
                    Lobe::Lambert(photonmap::materials::diffuse::Lambert {
                        albedo: Vec3::splat(0.8),
                    }),
                ),
            0.01,
        ),
    ];
    for (name, mut bsdf, fine) in sets {
        bsdf.set_specular_normal(bent, Vec3::X);
        for deg in [5.0f32, 50.0, 80.0] {
            let wo = wo_at(deg);
            chi2_bsdf(&format!("split {name} {deg}"), &bsdf, wo, &cfg(fine, false));
            let mut rng = Rng::new(5, deg as u64);
            let mut n = 0;
            for _ in 0..2000 {
                let u = rng.vec3();
                let Some(s) = bsdf.sample(wo, u.x, Vec2::new(u.y, u.z)) else {
                    continue;
                };
                if s.is_delta() {
                    continue;
                }
                let want = bsdf.eval(wo, s.wi) * (s.wi.z.abs() / s.pdf);
                assert!(
                    (s.weight - want).abs().max_element() <= 1e-4 * (1.0 + want.max_element()),
                    "{name} {deg}: weight {} against f cos / pdf {}",
                    s.weight,
                    want
                );
                assert!((bsdf.pdf(wo, s.wi) - s.pdf).abs() <= 1e-4 * s.pdf.max(1.0));
                n += 1;
            }
            assert!(n > 1000, "{name} {deg}: {n} samples");
        }
    }
}

/// The Translucent BSDF (diffuse transmission), alone and mixed with Lambertian reflection,
/// from both sides: it samples its pdf and transmits its albedo.
#[test]
fn chi2_translucent() {
    use photonmap::materials::diffuse::Lambert;
    use photonmap::materials::translucent::Translucent;
    let t = Lobe::Translucent(Translucent {
        albedo: Vec3::new(0.3, 0.6, 0.9),
    });
    let alone = Bsdf::new(local()).with(1.0, t);
    let mixed = Bsdf::new(local()).with(0.5, t).with(
        0.5,
        Lobe::Lambert(Lambert {
            albedo: Vec3::splat(0.8),
        }),
    );
    for (name, bsdf) in [("translucent", &alone), ("translucent + lambert", &mixed)] {
        for wo in [wo_at(30.0), wo_at(150.0)] {
            chi2_bsdf(&format!("{name} {}", wo.z), bsdf, wo, &cfg(0.02, true));
        }
    }
    // Every sample crosses the surface and carries the albedo.
    let mut rng = Rng::new(9, 0);
    for _ in 0..1000 {
        let wo = wo_at(40.0);
        let s = alone.sample(wo, rng.f32(), rng.vec2()).expect("a sample");
        assert!(s.wi.z < 0.0);
        assert!((s.weight - Vec3::new(0.3, 0.6, 0.9)).abs().max_element() < 1e-5);
    }
    assert_eq!(alone.eval(wo_at(40.0), wo_at(20.0)), Vec3::ZERO);
}

/// Cycles' Refraction BSDF: refraction alone, not scaled by the Fresnel transmittance. The
/// rough lobe samples its pdf; every sample crosses the surface; the smooth one carries the
/// tint whole (none under total internal reflection).
#[test]
fn chi2_refraction_only() {
    let tint = Vec3::new(0.9, 0.8, 0.7);
    let rough = Bsdf::new(local()).with(1.0, refraction_lobe(1.45, 0.3, tint));
    for deg in [20.0f32, 70.0, 160.0, 120.0] {
        let wo = wo_at(deg);
        chi2_bsdf(
            &format!("refraction r=0.3 {deg}"),
            &rough,
            wo,
            &cfg(0.01, false),
        );
        let mut rng = Rng::new(11, deg as u64);
        for _ in 0..500 {
            if let Some(s) = rough.sample(wo, rng.f32(), rng.vec2()) {
                assert!(s.wi.z * wo.z < 0.0, "{deg}: a reflection");
            }
        }
    }
    let smooth = Bsdf::new(local()).with(1.0, refraction_lobe(1.45, 0.0, tint));
    let s = smooth
        .sample(wo_at(50.0), 0.01, Vec2::ZERO)
        .expect("a refraction");
    assert!(s.wi.z < 0.0 && (s.weight - tint).abs().max_element() < 1e-6);
    // From inside beyond the critical angle (43.6 degrees at 1.45): nothing.
    assert!(smooth
        .sample(wo_at(180.0 - 60.0), 0.5, Vec2::ZERO)
        .is_none());
}
