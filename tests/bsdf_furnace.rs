//! White-furnace, reciprocity and Russian-roulette tests for every material.

use glam::{Vec2, Vec3};
use photonmap::materials::{Bsdf, Component, LobeFlags, Material};
use photonmap::math::Frame;
use photonmap::sampling::warp::{square_to_uniform_sphere, UNIFORM_SPHERE_PDF};
use photonmap::sampling::Rng;
use photonmap::scene::desc::{ColorInput, FloatInput, MaterialDesc, PrincipledDesc};

fn local() -> Frame {
    Frame {
        s: Vec3::X,
        t: Vec3::Y,
        n: Vec3::Z,
    }
}

fn wo_at(deg: f32) -> Vec3 {
    let t = deg.to_radians();
    Vec3::new(t.sin() * 0.3f32.cos(), t.sin() * 0.3f32.sin(), t.cos()).normalize()
}

fn principled(f: impl FnOnce(&mut PrincipledDesc)) -> MaterialDesc {
    let mut d = PrincipledDesc {
        base_color: ColorInput::Value([1.0; 3]),
        ..Default::default()
    };
    f(&mut d);
    MaterialDesc::Principled(Box::new(d))
}

/// Every material type with white colours, and the principled BSDF with several settings.
fn white_materials() -> Vec<(String, MaterialDesc)> {
    let mut v: Vec<(String, MaterialDesc)> = vec![
        (
            "diffuse".into(),
            MaterialDesc::Diffuse {
                name: String::new(),
                color: ColorInput::Value([1.0; 3]),
            },
        ),
        (
            "mirror".into(),
            MaterialDesc::Mirror {
                name: String::new(),
                color: [1.0; 3],
            },
        ),
        (
            "emission".into(),
            MaterialDesc::Emission {
                name: String::new(),
                color: ColorInput::Value([1.0; 3]),
                strength: 3.0,
            },
        ),
    ];
    for r in [0.0f32, 0.1, 0.4, 1.0] {
        v.push((
            format!("conductor r={r}"),
            MaterialDesc::Conductor {
                name: String::new(),
                eta: [0.05; 3],
                k: [20.0; 3],
                roughness: r,
            },
        ));
        for multiscatter in [true, false] {
            v.push((
                format!("glossy multiscatter={multiscatter} r={r}"),
                MaterialDesc::Glossy {
                    name: String::new(),
                    color: [1.0; 3],
                    roughness: r,
                    multiscatter,
                },
            ));
        }
        for ior in [1.0001f32, 1.5, 2.4] {
            for multiscatter in [true, false] {
                v.push((
                    format!("dielectric ior={ior} multiscatter={multiscatter} r={r}"),
                    MaterialDesc::Dielectric {
                        name: String::new(),
                        ior,
                        roughness: r,
                        color: [1.0; 3],
                        multiscatter,
                    },
                ));
            }
        }
        v.push((
            format!("principled plastic r={r}"),
            principled(|d| d.roughness = FloatInput::Value(r)),
        ));
        v.push((
            format!("principled metal r={r}"),
            principled(|d| {
                d.roughness = FloatInput::Value(r);
                d.metallic = FloatInput::Value(1.0);
            }),
        ));
        v.push((
            format!("principled glass r={r}"),
            principled(|d| {
                d.roughness = FloatInput::Value(r);
                d.transmission = 1.0;
                d.ior = 1.33;
            }),
        ));
        v.push((
            format!("principled mix r={r}"),
            principled(|d| {
                d.roughness = FloatInput::Value(r);
                d.metallic = FloatInput::Value(0.3);
                d.transmission = 0.4;
                d.ior = 2.0;
            }),
        ));
        v.push((
            format!("principled specular 0.5 ior 3 r={r}"),
            principled(|d| {
                d.roughness = FloatInput::Value(r);
                d.specular = 0.5;
                d.ior = 3.0;
            }),
        ));
    }
    v
}

const ANGLES: [f32; 9] = [0.0, 20.0, 40.0, 60.0, 75.0, 85.0, 89.0, 120.0, 170.0];

/// Mean and standard error of the sampled weight per channel (max over channels): the
/// energy a camera path keeps (refraction as Cycles weights it, without 1/eta^2).
fn albedo_by_sampling(bsdf: &Bsdf, wo: Vec3, n: usize, seed: u64) -> (f64, f64) {
    let mut rng = Rng::new(seed, 1);
    let (mut s, mut s2) = (Vec3::ZERO.as_dvec3(), Vec3::ZERO.as_dvec3());
    for _ in 0..n {
        if let Some(x) = bsdf.sample(wo, rng.f32(), rng.vec2()) {
            let w = x.weight.as_dvec3();
            assert!(w.is_finite() && w.min_element() >= 0.0, "{x:?}");
            s += w;
            s2 += w * w;
        }
    }
    let mean = s / n as f64;
    let var = (s2 / n as f64 - mean * mean).max(glam::DVec3::ZERO);
    let i = if mean.x >= mean.y && mean.x >= mean.z {
        0
    } else if mean.y >= mean.z {
        1
    } else {
        2
    };
    (mean[i], (var[i] / n as f64).sqrt())
}

/// The albedo photons see: the mean flux weight with the reflection lobes evaluated with the
/// directions swapped, f(wi, wo) |cos wi| / pdf (the adjoint of a lobe that depends on the
/// view direction only), refraction and delta lobes as sampled. Red channel.
fn adjoint_albedo_by_sampling(bsdf: &Bsdf, wo: Vec3, n: usize, seed: u64) -> (f64, f64) {
    let mut rng = Rng::new(seed, 3);
    let (mut s, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        if let Some(x) = bsdf.sample(wo, rng.f32(), rng.vec2()) {
            let w = if !x.is_delta() && x.wi.z * wo.z > 0.0 {
                bsdf.eval(x.wi, wo).x * x.wi.z.abs() / x.pdf
            } else {
                x.importance_weight().x
            } as f64;
            s += w;
            s2 += w * w;
        }
    }
    let mean = s / n as f64;
    (
        mean,
        ((s2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt(),
    )
}

/// Photons leave a surface with the adjoint of the BSDF: for every material, the weight of a
/// reflection the photon pass samples (`Bsdf::sample_component`) is f(wi, wo) |cos wi| / pdf,
/// the BSDF with the photon's directions swapped, which for the reciprocal lobes is the BSDF
/// itself and for the view-dependent ones (Cycles' layering and multiple-scattering
/// compensation) is what light leaving along wi carries.
#[test]
fn photon_scattering_uses_the_adjoint() {
    let mut rng = Rng::new(8, 0);
    for (name, desc) in white_materials() {
        let m = Material::from_desc(&desc);
        let bsdf = m.bsdf(local(), Vec2::ZERO, &[]);
        for deg in [10.0f32, 50.0, 80.0] {
            let wo = wo_at(deg);
            for c in [Component::Diffuse, Component::Specular] {
                for _ in 0..200 {
                    let Some(x) = bsdf.sample_component(wo, c, rng.f32(), rng.vec2()) else {
                        continue;
                    };
                    if x.is_delta() {
                        continue;
                    }
                    let f = bsdf.eval_component(x.wi, wo, c);
                    let pdf = bsdf.pdf_component(wo, x.wi, c);
                    let expect = f * (x.wi.z.abs() / pdf);
                    let scale = expect.max_element().max(1e-6);
                    assert!(
                        (x.weight - expect).abs().max_element() <= 1e-4 * scale,
                        "{name} {c:?} at {deg}: weight {:?}, f(wi, wo) |cos| / pdf {expect:?}",
                        x.weight
                    );
                }
            }
        }
    }
}

/// Albedo of the non-delta part by uniform sphere sampling of eval (refraction is evaluated
/// as Cycles evaluates it, without 1/eta^2: the integral is the energy kept).
fn albedo_by_eval(bsdf: &Bsdf, wo: Vec3, n: usize, seed: u64) -> (f64, f64) {
    let mut rng = Rng::new(seed, 2);
    let (mut s, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let wi = square_to_uniform_sphere(rng.vec2());
        let f = bsdf.eval(wo, wi) * wi.z.abs() / UNIFORM_SPHERE_PDF;
        let v = f.max_element() as f64;
        s += v;
        s2 += v * v;
    }
    let mean = s / n as f64;
    (
        mean,
        ((s2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt(),
    )
}

fn ior_of(d: &MaterialDesc) -> f32 {
    match d {
        MaterialDesc::Dielectric { ior, .. } => *ior,
        MaterialDesc::Principled(p) => p.ior,
        _ => 1.0,
    }
}

/// Fresnel reflectance of a conductor of complex IOR eta + i k at incidence cosine `c`
/// (Born & Wolf; the parallel and perpendicular amplitudes, averaged), in f64.
fn conductor_fresnel(c: f64, eta: f64, k: f64) -> f64 {
    // (eta + i k)^2 - sin^2 = a + i b; t0 = sqrt(a^2 + b^2); a2b2 = t0.
    let s2 = 1.0 - c * c;
    let (a, b) = (eta * eta - k * k - s2, 2.0 * eta * k);
    let t0 = (a * a + b * b).sqrt();
    let re = (0.5 * (t0 + a)).max(0.0).sqrt();
    let t1 = t0 + c * c;
    let t2 = 2.0 * c * re;
    let rs = (t1 - t2) / (t1 + t2);
    let t3 = c * c * t0 + s2 * s2;
    let t4 = t2 * s2;
    let rp = rs * (t3 - t4) / (t3 + t4);
    0.5 * (rs + rp)
}

/// Fresnel reflectance of a smooth dielectric interface, relative IOR `eta` (transmitted
/// over incident side), at incidence cosine `c` > 0; 1 under total internal reflection.
fn dielectric_fresnel(c: f64, eta: f64) -> f64 {
    let s2t = (1.0 - c * c) / (eta * eta);
    if s2t >= 1.0 {
        return 1.0;
    }
    let ct = (1.0 - s2t).sqrt();
    let rs = (c - eta * ct) / (c + eta * ct);
    let rp = (eta * c - ct) / (eta * c + ct);
    0.5 * (rs * rs + rp * rp)
}

/// What a microfacet surface does at each facet, for [`single_scattering_albedo`].
#[derive(Clone, Copy, Debug)]
enum Facet {
    /// Reflects everything (a white glossy surface).
    White,
    /// Reflects the conductor Fresnel of eta + i k.
    Conductor(f64, f64),
    /// Reflects the dielectric Fresnel and transmits the rest, relative IOR eta.
    Dielectric(f64),
}

/// The flux albedo of single scattering off a GGX microfacet surface of width `alpha` (no
/// multiple-scattering compensation), for `wo` above the surface, by quadrature over the
/// microfacet normals m: the visible facets' share D(m) (wo.m) / cos_o dm, each reflecting F
/// and transmitting 1 - F of the flux (energy is conserved at a smooth facet), the scattered
/// direction then escaping with probability G2 / G1 of height-correlated Smith masking
/// (Heitz 2014). Written here from the formulas, apart from the renderer's lobes.
fn single_scattering_albedo(wo: glam::DVec3, alpha: f64, facet: Facet) -> f64 {
    let a2 = alpha * alpha;
    let lambda = |w: glam::DVec3| {
        let c2 = w.z * w.z;
        let t2 = (1.0 - c2).max(0.0) / c2;
        0.5 * (-1.0 + (1.0 + a2 * t2).sqrt())
    };
    // Doubling both counts changes no expected albedo of the test by more than 4e-5.
    let (ns, nphi) = (3000usize, 512usize);
    let mut sum = 0.0f64;
    for i in 0..ns {
        // tan(theta_m) = alpha tan(pi s / 2): the samples follow the distribution's width.
        let sv = (i as f64 + 0.5) / ns as f64;
        let u = 0.5 * std::f64::consts::PI * sv;
        let tan_t = alpha * u.tan();
        let theta = tan_t.atan();
        let dtheta = 0.5 * std::f64::consts::PI * alpha
            / (u.cos().powi(2) * (1.0 + tan_t * tan_t))
            / ns as f64;
        let (st, ct) = theta.sin_cos();
        let d = a2 / (std::f64::consts::PI * ct.powi(4) * (a2 + tan_t * tan_t).powi(2));
        for j in 0..nphi {
            let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / nphi as f64;
            let m = glam::DVec3::new(st * phi.cos(), st * phi.sin(), ct);
            let om = wo.dot(m);
            if om <= 0.0 {
                continue;
            }
            let dm = st * dtheta * 2.0 * std::f64::consts::PI / nphi as f64;
            let visible = d * om / wo.z * dm;
            let escape = |wi: glam::DVec3| {
                if wi.z * wi.dot(m) <= 0.0 || wi.z == 0.0 {
                    0.0
                } else {
                    // G2 / G1(wo) of the height-correlated form, G1(wo) = 1 / (1 + L(wo)).
                    (1.0 + lambda(wo)) / (1.0 + lambda(wo) + lambda(wi))
                }
            };
            let wr = 2.0 * om * m - wo;
            let (f, wt) = match facet {
                Facet::White => (1.0, None),
                Facet::Conductor(eta, k) => (conductor_fresnel(om, eta, k), None),
                Facet::Dielectric(eta) => {
                    let f = dielectric_fresnel(om, eta);
                    let s2t = (1.0 - om * om) / (eta * eta);
                    let wt = (s2t < 1.0).then(|| -wo / eta + (om / eta - (1.0 - s2t).sqrt()) * m);
                    (f, wt)
                }
            };
            let mut e = f * escape(wr);
            if let Some(wt) = wt {
                e += (1.0 - f) * escape(wt.normalize());
            }
            sum += visible * e;
        }
    }
    // D(m) (wo.m) / cos_o integrates to 1 + Lambda(wo) over the facets facing wo: times
    // G1(wo) = 1 / (1 + Lambda(wo)) it is the visible facets' distribution.
    sum / (1.0 + lambda(wo))
}

/// The directional albedo `desc` must have (white colours), for `wo` in the local frame:
/// 1 where the material conserves energy (Lambert, mirror, smooth dielectrics, the
/// multiple-scattering-compensated lobes, the principled BSDF's layering of them, an
/// index-matched interface, which is skipped), 0 for an emitter, the conductor Fresnel for a
/// smooth conductor, and [`single_scattering_albedo`] for the uncompensated rough lobes. A
/// reflecting lobe is the same seen from either side; a dielectric seen from inside has the
/// inverse relative IOR.
fn expected_albedo(desc: &MaterialDesc, wo: Vec3) -> f64 {
    let wo = wo.as_dvec3();
    let up = glam::DVec3::new(wo.x, wo.y, wo.z.abs());
    match desc {
        MaterialDesc::Diffuse { .. } | MaterialDesc::Mirror { .. } => 1.0,
        MaterialDesc::Emission { .. } => 0.0,
        MaterialDesc::Principled(_) => 1.0,
        MaterialDesc::Glossy {
            multiscatter,
            roughness,
            ..
        } => {
            if *multiscatter || *roughness == 0.0 {
                1.0
            } else {
                single_scattering_albedo(up, (*roughness as f64).powi(2), Facet::White)
            }
        }
        MaterialDesc::Conductor {
            eta, k, roughness, ..
        } => {
            let (eta, k) = (eta[0] as f64, k[0] as f64);
            if *roughness == 0.0 {
                conductor_fresnel(up.z, eta, k)
            } else {
                single_scattering_albedo(up, (*roughness as f64).powi(2), Facet::Conductor(eta, k))
            }
        }
        MaterialDesc::Dielectric {
            ior,
            roughness,
            multiscatter,
            ..
        } => {
            if *multiscatter || *roughness == 0.0 || (*ior - 1.0).abs() < 1e-3 {
                1.0
            } else {
                let eta = if wo.z >= 0.0 {
                    *ior as f64
                } else {
                    1.0 / *ior as f64
                };
                single_scattering_albedo(up, (*roughness as f64).powi(2), Facet::Dielectric(eta))
            }
        }
        _ => panic!("no expected albedo for {desc:?}"),
    }
}

/// How far [`single_scattering_albedo`] and the renderer's f32 arithmetic may differ from the
/// exact albedo.
const QUADRATURE: f64 = 1e-4;

/// White furnace: every material's directional albedo, estimated by sampling (100,000 samples,
/// flux weights) at nine angles, equals the albedo it must have (`expected_albedo`) within
/// 4.5 standard errors of the estimate (the largest over the 2,000-odd cases of a Gaussian
/// estimate passes at a false-alarm rate of about 1%), plus `slack`: the albedo tables of the
/// multiple-scattering compensation are read bilinearly, within about 0.3% of the truth
/// between their rows; and `QUADRATURE`. Both bounds, not only energy conservation. The estimate by uniform
/// sampling of `eval` must agree with the sampled one where it is not too noisy to tell.
#[test]
fn white_furnace_every_material() {
    let n = 100_000;
    let mut table = String::new();
    let mut worst = (0.0f64, String::new());
    for (name, desc) in white_materials() {
        let m = Material::from_desc(&desc);
        let bsdf = m.bsdf(local(), Vec2::new(0.5, 0.5), &[]);
        let slack = if reciprocal(&desc) { 1e-5 } else { 3e-3 };
        let mut line = format!("{name:38}");
        for (k, deg) in ANGLES.iter().enumerate() {
            let wo = wo_at(*deg);
            let expected = expected_albedo(&desc, wo);
            let (a, sa) = albedo_by_sampling(&bsdf, wo, n, k as u64);
            let off = (a - expected).abs();
            let tol = 4.5 * sa + slack + QUADRATURE;
            if off / tol > worst.0 {
                worst = (
                    off / tol,
                    format!("{name} at {deg}: {a:.5} +- {sa:.5}, expected {expected:.5}"),
                );
            }
            assert!(
                off <= tol,
                "{name} at {deg} deg: sampled albedo {a:.5} +- {sa:.5}, expected {expected:.5} \
                 (tolerance {tol:.5})"
            );
            let (b, sb) = albedo_by_eval(&bsdf, wo, n, k as u64);
            assert!(
                b <= 1.0 + 3.0 * sb + slack,
                "{name} at {deg} deg: uniform-eval albedo {b} +- {sb} exceeds 1"
            );
            // Without delta lobes both estimators agree (where uniform sampling of a narrow
            // lobe is not too noisy to tell).
            if bsdf.flags() & LobeFlags::SPECULAR == 0 && !bsdf.is_black() && sb < 5e-3 {
                assert!(
                    (a - b).abs() <= 4.0 * (sa * sa + sb * sb).sqrt() + 2e-3,
                    "{name} at {deg} deg: sampled {a} +- {sa} vs eval {b} +- {sb}"
                );
            }
            line += &format!(" {a:.5}/{expected:.5}");
        }
        table += &line;
        table.push('\n');
    }
    eprintln!("directional albedo (sampled/expected) at {ANGLES:?} degrees:\n{table}");
    eprintln!(
        "largest |sampled - expected| / tolerance: {:.3} ({})",
        worst.0, worst.1
    );
}

#[test]
fn lambert_albedo_one_is_exact() {
    let m = Material::from_desc(&MaterialDesc::Diffuse {
        name: String::new(),
        color: ColorInput::Value([1.0; 3]),
    });
    let bsdf = m.bsdf(local(), Vec2::ZERO, &[]);
    let mut rng = Rng::new(1, 0);
    for deg in ANGLES {
        let wo = wo_at(deg);
        for _ in 0..10_000 {
            let s = bsdf
                .sample(wo, rng.f32(), rng.vec2())
                .expect("lambert samples");
            assert!((s.weight - Vec3::ONE).abs().max_element() < 1e-6, "{s:?}");
            assert!(s.wi.z * wo.z > 0.0);
        }
        let (d, s, t) = bsdf.rr_reflectivities(wo);
        assert_eq!((d, s, t), (Vec3::ONE, Vec3::ZERO, Vec3::ZERO));
    }
}

#[test]
fn smooth_dielectric_r_plus_t_is_one() {
    for ior in [1.0001f32, 1.33, 1.5, 2.4] {
        let m = Material::from_desc(&MaterialDesc::Dielectric {
            name: String::new(),
            ior,
            roughness: 0.0,
            color: [1.0; 3],
            multiscatter: true,
        });
        let bsdf = m.bsdf(local(), Vec2::ZERO, &[]);
        let mut rng = Rng::new(2, 0);
        for deg in ANGLES {
            let wo = wo_at(deg);
            for _ in 0..10_000 {
                let s = bsdf
                    .sample(wo, rng.f32(), rng.vec2())
                    .expect("always a sample");
                // Every event carries weight R/R or T/T: the energy is kept exactly; a
                // photon's refraction carries 1/eta^2 besides.
                assert!((s.weight - Vec3::ONE).abs().max_element() < 1e-5, "{s:?}");
                assert!(
                    (s.importance_weight() * s.eta * s.eta - Vec3::ONE)
                        .abs()
                        .max_element()
                        < 1e-5,
                    "{s:?}"
                );
            }
            let (d, s, t) = bsdf.rr_reflectivities(wo);
            assert_eq!(d, Vec3::ZERO);
            assert!(((s + t) - Vec3::ONE).abs().max_element() < 1e-6);
        }
    }
}

fn random_dir(rng: &mut Rng) -> Vec3 {
    square_to_uniform_sphere(rng.vec2())
}

/// Whether a material's lobes are all reciprocal: the Principled BSDF's base is layered under
/// its specular layer as Cycles layers it, and Multiscatter GGX is compensated as Cycles
/// compensates it, both by the view direction alone (see
/// `photon_scattering_uses_the_adjoint`).
fn reciprocal(desc: &MaterialDesc) -> bool {
    match desc {
        MaterialDesc::Principled(_) => false,
        MaterialDesc::Glossy { multiscatter, .. } => !multiscatter,
        MaterialDesc::Dielectric {
            multiscatter,
            roughness,
            ..
        } => !multiscatter || *roughness == 0.0,
        _ => true,
    }
}

#[test]
fn reciprocity() {
    let mut rng = Rng::new(4, 0);
    for (name, desc) in white_materials() {
        let ior = ior_of(&desc);
        let m = Material::from_desc(&desc);
        let bsdf = m.bsdf(local(), Vec2::ZERO, &[]);
        for _ in 0..2000 {
            let (a, b) = (random_dir(&mut rng), random_dir(&mut rng));
            if !reciprocal(&desc) {
                continue;
            }
            let fab = bsdf.eval(a, b);
            let fba = bsdf.eval(b, a);
            // Veach 1997 eq. 5.14 holds for the radiance BSDF f_s: f_s(wi -> wo) / eta_o^2 =
            // f_s(wo -> wi) / eta_i^2. Refraction here is evaluated as Cycles evaluates it,
            // eval(a, b) = f_s(b -> a) eta_b^2 / eta_a^2 (no 1/eta^2 radiance scaling), so
            // f(a, b) / eta_b^2 = f(b, a) / eta_a^2 with eta_x the index on x's side.
            // Reflection is the special case eta_a = eta_b.
            let eta_a = if a.z > 0.0 { 1.0 } else { ior };
            let eta_b = if b.z > 0.0 { 1.0 } else { ior };
            let lhs = fab * (eta_a * eta_a);
            let rhs = fba * (eta_b * eta_b);
            let scale = lhs.max_element().max(rhs.max_element()).max(1e-6);
            assert!(
                (lhs - rhs).abs().max_element() <= 1e-2 * scale + 2e-5,
                "{name}: f({a:?}, {b:?}) = {fab:?}, reversed {fba:?}"
            );
        }
    }
}

#[test]
fn russian_roulette_components_are_unbiased() {
    // Jensen 2001 §6.3: pick diffuse, specular or transmission with probabilities P_d, P_s,
    // P_t (means of the reflectivities), absorb otherwise, and scale the photon by
    // weight / P. The expected scaled weight must be the BSDF's albedo.
    let n = 200_000;
    for (name, desc) in white_materials() {
        let m = Material::from_desc(&desc);
        let bsdf = m.bsdf(local(), Vec2::ZERO, &[]);
        for deg in [10.0f32, 60.0, 85.0, 150.0] {
            let wo = wo_at(deg);
            let (d, s, t) = bsdf.rr_reflectivities(wo);
            let p = [d, s, t].map(|c| ((c.x + c.y + c.z) / 3.0) as f64);
            assert!(p.iter().all(|v| *v >= 0.0));
            assert!(p.iter().sum::<f64>() <= 1.0 + 1e-6, "{name}: {p:?}");
            let mut rng = Rng::new(6, deg as u64);
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let u = rng.f32() as f64;
                let (c, pc) = if u < p[0] {
                    (Component::Diffuse, p[0])
                } else if u < p[0] + p[1] {
                    (Component::Specular, p[1])
                } else if u < p[0] + p[1] + p[2] {
                    (Component::Transmission, p[2])
                } else {
                    continue;
                };
                if let Some(x) = bsdf.sample_component(wo, c, rng.f32(), rng.vec2()) {
                    let w = x.importance_weight().x as f64 / pc;
                    sum += w;
                    sum2 += w * w;
                }
            }
            let rr = sum / n as f64;
            let srr = ((sum2 / n as f64 - rr * rr).max(0.0) / n as f64).sqrt();
            let (full, sfull) = adjoint_albedo_by_sampling(&bsdf, wo, n, 99);
            assert!(
                (rr - full).abs() <= 4.5 * (srr * srr + sfull * sfull).sqrt() + 1e-4,
                "{name} at {deg}: roulette {rr} +- {srr} vs full {full} +- {sfull}"
            );
        }
    }
}

#[test]
fn material_queries() {
    let all = white_materials();
    for (name, desc) in &all {
        let m = Material::from_desc(desc);
        let bsdf = m.bsdf(local(), Vec2::ZERO, &[]);
        let delta_or_t = bsdf.flags() & (LobeFlags::SPECULAR | LobeFlags::TRANSMISSION) != 0;
        if delta_or_t {
            assert!(m.has_specular(), "{name} has a delta or transmissive lobe");
        }
        assert_eq!(m.is_emissive(), name == "emission", "{name}");
        assert_eq!(
            bsdf.has_non_delta(),
            bsdf.lobes()
                .any(|(_, l)| l.flags() & LobeFlags::SPECULAR == 0)
        );
    }
    let e = Material::from_desc(&MaterialDesc::Emission {
        name: "lamp".into(),
        color: ColorInput::Value([1.0, 0.5, 0.25]),
        strength: 4.0,
    });
    assert_eq!(e.emission(Vec2::ZERO, &[]), Vec3::new(4.0, 2.0, 1.0));
    assert!(e.bsdf(local(), Vec2::ZERO, &[]).is_black());
    assert_eq!(e.name(), "lamp");
    let p = Material::from_desc(&principled(|d| {
        d.emission_color = ColorInput::Value([0.0, 1.0, 0.0]);
        d.emission_strength = 2.0;
    }));
    assert!(p.is_emissive());
    assert_eq!(p.emission(Vec2::ZERO, &[]), Vec3::new(0.0, 2.0, 0.0));
    // Rough opaque principled with no transmission needs no caustic map.
    assert!(!Material::from_desc(&principled(|_| {})).has_specular());
    let d = Material::from_desc(&MaterialDesc::Diffuse {
        name: String::new(),
        color: ColorInput::Value([0.5; 3]),
    });
    assert!(!d.has_specular() && !d.is_emissive());
    assert_eq!(d.emission(Vec2::ZERO, &[]), Vec3::ZERO);
}

#[test]
fn world_frame_round_trip() {
    // The same BSDF in a rotated frame gives the same values for rotated directions.
    let desc = principled(|d| {
        d.metallic = FloatInput::Value(0.4);
        d.roughness = FloatInput::Value(0.35);
    });
    let m = Material::from_desc(&desc);
    let n = Vec3::new(0.3, -0.5, 0.8).normalize();
    let frame = Frame::from_normal(n);
    let a = m.bsdf(local(), Vec2::ZERO, &[]);
    let b = m.bsdf(frame, Vec2::ZERO, &[]);
    let mut rng = Rng::new(8, 0);
    for _ in 0..1000 {
        let (wo, wi) = (random_dir(&mut rng), random_dir(&mut rng));
        let fa = a.eval(wo, wi);
        let fb = b.eval(frame.to_world(wo), frame.to_world(wi));
        assert!((fa - fb).abs().max_element() <= 1e-3 * fa.max_element().max(1e-3));
        let (u0, u) = (rng.f32(), rng.vec2());
        if let (Some(sa), Some(sb)) = (a.sample(wo, u0, u), b.sample(frame.to_world(wo), u0, u)) {
            assert!((frame.to_world(sa.wi) - sb.wi).length() < 1e-3);
            assert!((sa.pdf - sb.pdf).abs() <= 1e-2 * sa.pdf.max(1e-3));
        }
    }
}

/// Cycles' Multiscatter GGX reflects all light off a white reflector at every roughness and
/// angle: the compensation f_ss (1 + F_ms (1 - E1) / E1) with F_ss = 1 (so F_ms = 1) has
/// albedo E1 + 1 - E1 = 1, where plain GGX loses the single-scattering energy 1 - E1
/// (tabulated in `SchlickAlbedoTable`). Checked by sampling, to the table's interpolation.
#[test]
fn multiscatter_ggx_white_furnace_is_one() {
    use photonmap::materials::layer::SchlickAlbedoTable;
    let n = 200_000;
    for r in [0.2f32, 0.5, 0.8, 1.0] {
        for multiscatter in [true, false] {
            let m = Material::from_desc(&MaterialDesc::Glossy {
                name: String::new(),
                color: [1.0; 3],
                roughness: r,
                multiscatter,
            });
            let bsdf = m.bsdf(local(), Vec2::ZERO, &[]);
            for (k, deg) in [0.0f32, 30.0, 60.0, 80.0].iter().enumerate() {
                let wo = wo_at(*deg);
                let (a, sa) = albedo_by_sampling(&bsdf, wo, n, 10 + k as u64);
                let expect = if multiscatter {
                    1.0
                } else {
                    SchlickAlbedoTable::get().e1(wo.z, r) as f64
                };
                eprintln!(
                    "r {r} ms {multiscatter} {deg} deg: {a:.4} +- {sa:.4}, expected {expect:.4}"
                );
                assert!(
                    (a - expect).abs() < 4.0 * sa + 4e-3,
                    "r {r} multiscatter {multiscatter} at {deg} deg: {a} +- {sa}, expected {expect}"
                );
            }
        }
    }
}

/// Rough glass: with Cycles' Multiscatter GGX compensation it reflects and refracts all the
/// energy arriving from either side; without it, the single-scattering albedo of its table,
/// which the sampled lobe must reproduce (a table or a factor that is off fails).
#[test]
fn multiscatter_glass_white_furnace_is_one() {
    use photonmap::materials::glass_albedo;
    let n = 200_000;
    for (r, ior) in [(0.3f32, 1.5f32), (0.6, 1.33), (0.9, 2.4)] {
        for multiscatter in [true, false] {
            let m = Material::from_desc(&MaterialDesc::Dielectric {
                name: String::new(),
                ior,
                roughness: r,
                color: [1.0; 3],
                multiscatter,
            });
            let bsdf = m.bsdf(local(), Vec2::ZERO, &[]);
            for (k, deg) in [0.0f32, 45.0, 80.0, 120.0, 170.0].iter().enumerate() {
                let wo = wo_at(*deg);
                let (a, sa) = albedo_by_sampling(&bsdf, wo, n, 20 + k as u64);
                let eta = if wo.z > 0.0 { ior } else { 1.0 / ior };
                let expect = if multiscatter {
                    1.0
                } else {
                    glass_albedo::albedo(wo.z.abs(), r, eta) as f64
                };
                assert!(
                    (a - expect).abs() < 4.0 * sa + 4e-3,
                    "r {r} ior {ior} multiscatter {multiscatter} at {deg} deg: {a} +- {sa}, \
                     expected {expect}"
                );
                if !multiscatter && *deg >= 80.0 {
                    assert!(
                        expect < 0.999,
                        "r {r} ior {ior} at {deg} deg loses energy: {expect}"
                    );
                }
            }
        }
    }
}

/// Known albedos of the layered and metallic lobes, by sampling:
/// - the Principled BSDF with a white base: its specular layer reflects E_spec(wo) and the
///   base, weighted by 1 - E_spec(wo), the rest, so it reflects everything, at every
///   roughness (to the tables' interpolation);
/// - a white Principled metal (Schlick F0 = 1, Multiscatter GGX): everything;
/// - the white plastic under a clear coat: the coat reflects E_coat(wo), what it lets
///   through is reflected entirely below, so everything again;
/// - a Principled base of albedo 0.5: 1/2 + E_spec(wo)/2, with E_spec from the coat table, so
///   a coat that reflects the wrong amount fails.
#[test]
fn layered_and_metal_albedos_are_known() {
    use photonmap::materials::layer::CoatAlbedoTable;
    use photonmap::materials::Principled;
    let n = 200_000;
    for r in [0.0f32, 0.3, 0.6, 1.0] {
        for deg in [0.0f32, 45.0, 75.0] {
            let wo = wo_at(deg);
            for (name, desc, expect) in [
                (
                    "white plastic",
                    principled(|d| d.roughness = FloatInput::Value(r)),
                    None,
                ),
                (
                    "white metal",
                    principled(|d| {
                        d.roughness = FloatInput::Value(r);
                        d.metallic = FloatInput::Value(1.0);
                    }),
                    None,
                ),
                (
                    "grey plastic",
                    principled(|d| {
                        d.roughness = FloatInput::Value(r);
                        d.base_color = ColorInput::Value([0.5; 3]);
                    }),
                    Some(()),
                ),
            ] {
                let m = Material::from_desc(&desc);
                let bsdf = m.bsdf(local(), Vec2::ZERO, &[]);
                let expected = match expect {
                    None => 1.0,
                    Some(()) => {
                        let MaterialDesc::Principled(p) = &desc else {
                            unreachable!()
                        };
                        let f0 = Principled::from_desc(p).coat_f0();
                        let e = CoatAlbedoTable::for_f0(f0).albedo_ms(wo.z, r, true) as f64;
                        0.5 + 0.5 * e
                    }
                };
                let (a, sa) = albedo_by_sampling(&bsdf, wo, n, 40 + deg as u64);
                eprintln!("{name} r {r} {deg} deg: {a:.4} +- {sa:.4}, expected {expected:.4}");
                assert!(
                    (a - expected).abs() < 4.0 * sa + 4e-3,
                    "{name} r {r} at {deg} deg: {a} +- {sa}, expected {expected}"
                );
            }
        }
    }
}

/// The near-specular lobes (`LobeFlags::NEAR_SPECULAR`: GGX alpha <= 0.04) are a partition of
/// the BSDF: the estimate's part (`without_near_specular`) plus the near-specular component
/// is the whole, direction by direction; the two reflection parts the photon pass splits
/// `Specular` into sum to it; and the flag is set where the roughness says so.
#[test]
fn near_specular_lobes_partition_the_bsdf() {
    let mut cases = white_materials();
    cases.push((
        "principled coat".into(),
        principled(|d| d.coat_weight = 1.0),
    ));
    let mut rng = Rng::new(12, 0);
    let mut flagged = Vec::new();
    for (name, desc) in &cases {
        let m = Material::from_desc(desc);
        let bsdf = m.bsdf(local(), Vec2::ZERO, &[]);
        if bsdf.flags() & LobeFlags::NEAR_SPECULAR != 0 {
            flagged.push(name.clone());
        }
        let rest = bsdf.without_near_specular();
        for _ in 0..200 {
            let (wo, wi) = (random_dir(&mut rng), random_dir(&mut rng));
            let whole = bsdf.eval(wo, wi);
            let parts = rest.eval(wo, wi) + bsdf.eval_component(wo, wi, Component::NearSpecular);
            let tol = 1e-4 * whole.max_element().max(1.0);
            assert!(
                (whole - parts).abs().max_element() <= tol,
                "{name}: {whole} vs {parts}"
            );
            let s = bsdf.eval_component(wo, wi, Component::Specular);
            let split = bsdf.eval_component(wo, wi, Component::NearSpecular)
                + bsdf.eval_component(wo, wi, Component::SpecularOther);
            assert!((s - split).abs().max_element() <= 1e-4 * s.max_element().max(1.0));
        }
    }
    for must in [
        "conductor r=0.1",
        "principled metal r=0.1",
        "principled coat",
    ] {
        assert!(
            flagged.iter().any(|n| n == must),
            "{must} not near-specular: {flagged:?}"
        );
    }
    for not in [
        "conductor r=0.4",
        "diffuse",
        "principled metal r=0.4",
        "principled plastic r=0.4",
    ] {
        assert!(
            !flagged.iter().any(|n| n == not),
            "{not} near-specular: {flagged:?}"
        );
    }
}
