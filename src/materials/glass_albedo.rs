//! Directional albedo of a rough GGX dielectric interface (reflection plus refraction), and
//! the compensation for multiple scattering between its microfacets that Cycles' Multiscatter
//! GGX glass applies: f = f_ss / E(mu_o), with E the fraction of the energy arriving from the
//! view direction that single scattering reflects or refracts (Cycles' `ggx_glass_E` and its
//! inverse for rays inside, after Kulla & Conty 2017; glass is taken as white).

use super::fresnel::fresnel_dielectric;
use super::layer::{cell, decode_f32, visible_normal_integral};
use super::microfacet::{reflect, refract};
use glam::{Vec2, Vec3};
use rayon::prelude::*;

const N_MU: usize = 32;
const N_ROUGH: usize = 32;
const N_Z: usize = 16;
/// The largest tabulated z = F0^(1/4) = sqrt((eta - 1) / (eta + 1)); eta ~ 19.5.
const Z_MAX: f32 = 0.95;
const CELLS: usize = N_MU * N_ROUGH * N_Z;

/// Two tables over (sqrt(mu), roughness, z), little-endian f32: light arriving from the side
/// of lower index (relative IOR eta > 1), then from the side of higher index (1 / eta).
/// Regenerate with `cargo run --release --example ggx_albedo_tables` (a test checks they
/// agree with [`tables`]).
static EMBEDDED: &[u8] = include_bytes!("ggx_glass_albedo.bin");

fn embedded() -> &'static [f32] {
    static DATA: std::sync::OnceLock<Vec<f32>> = std::sync::OnceLock::new();
    DATA.get_or_init(|| decode_f32(EMBEDDED))
}

/// The relative IOR (> 1) of the tabulated z.
fn eta_of_z(z: f32) -> f32 {
    let s = z * z;
    (1.0 + s) / (1.0 - s)
}

fn z_of_eta(eta: f32) -> f32 {
    let e = if eta >= 1.0 { eta } else { 1.0 / eta };
    ((e - 1.0) / (e + 1.0)).max(0.0).sqrt()
}

/// E(mu) of a rough dielectric interface of relative IOR `eta` (the far side's over the
/// view's) for a view cosine `mu` > 0: the integral over the visible normals of F G2/G1 for
/// the reflected direction plus (1 - F) G2/G1 for the refracted one, by
/// `layer::visible_normal_integral` (energy, not radiance: no 1/eta^2).
pub fn glass_albedo(mu: f32, roughness: f32, eta: f32) -> f32 {
    if roughness <= 0.0 || (eta - 1.0).abs() < 1e-6 {
        return 1.0;
    }
    visible_normal_integral(mu, roughness, |ggx, wo, m, lo| {
        let c = wo.dot(m);
        if c <= 0.0 {
            return Vec2::ZERO;
        }
        let (f, cos_t, _, eta_ti) = fresnel_dielectric(c, eta);
        let g = |wi: Vec3| (1.0 + lo) / (1.0 + lo + ggx.lambda(wi));
        let wr = reflect(wo, m);
        let mut e = 0.0;
        if wr.z > 0.0 {
            e += f * g(wr);
        }
        if f < 1.0 {
            let wt = refract(wo, m, cos_t, eta_ti).normalize_or_zero();
            if wt.z < 0.0 {
                e += (1.0 - f) * g(wt);
            }
        }
        Vec2::new(e, 0.0)
    })
    .x
}

/// The tables of `ggx_glass_albedo.bin` (a few seconds on two cores).
pub fn tables() -> Vec<f32> {
    let mut out = Vec::with_capacity(2 * CELLS);
    for inside in [false, true] {
        out.extend(table(inside));
    }
    out
}

fn table(inside: bool) -> Vec<f32> {
    (0..CELLS)
        .into_par_iter()
        .map(|idx| {
            let (k, rest) = (idx / (N_MU * N_ROUGH), idx % (N_MU * N_ROUGH));
            let (j, i) = (rest / N_MU, rest % N_MU);
            let z = Z_MAX * k as f32 / (N_Z - 1) as f32;
            let r = j as f32 / (N_ROUGH - 1) as f32;
            let s = i as f32 / (N_MU - 1) as f32;
            let eta = eta_of_z(z);
            glass_albedo(s * s, r, if inside { 1.0 / eta } else { eta })
        })
        .collect()
}

/// E(mu_o) of a rough interface of perceptual `roughness` and relative IOR `eta` (the far
/// side's over the view's), trilinear in (sqrt(mu), roughness, z) over the tables.
pub fn albedo(mu: f32, roughness: f32, eta: f32) -> f32 {
    let data = embedded();
    let base = if eta >= 1.0 { 0 } else { CELLS };
    let (i, ti) = cell(mu.max(0.0).sqrt(), N_MU);
    let (j, tj) = cell(roughness, N_ROUGH);
    let (k, tk) = cell(z_of_eta(eta) / Z_MAX, N_Z);
    let at = |k: usize, j: usize| {
        let b = base + (k * N_ROUGH + j) * N_MU + i;
        data[b] * (1.0 - ti) + data[b + 1] * ti
    };
    let at_k = |k: usize| at(k, j) * (1.0 - tj) + at(k, j + 1) * tj;
    at_k(k) * (1.0 - tk) + at_k(k + 1) * tk
}

/// Cycles' Multiscatter GGX factor on a rough dielectric's f for the view cosine `mu_o`:
/// 1 / E(mu_o).
pub fn compensation(mu: f32, roughness: f32, eta: f32) -> f32 {
    1.0 / albedo(mu, roughness, eta).clamp(0.05, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::microfacet::{alpha_from_roughness, Ggx};
    use crate::materials::rough_dielectric::RoughDielectric;
    use crate::sampling::Rng;

    #[test]
    fn embedded_tables_are_the_generator_s() {
        let data = embedded();
        assert_eq!(data.len(), 2 * CELLS);
        // Two z slices of each table (the whole takes seconds).
        for (t, inside) in [(0, false), (1, true)] {
            for k in [3, 9] {
                for idx in (k * N_MU * N_ROUGH..(k + 1) * N_MU * N_ROUGH).step_by(7) {
                    let rest = idx % (N_MU * N_ROUGH);
                    let (j, i) = (rest / N_MU, rest % N_MU);
                    let z = Z_MAX * k as f32 / (N_Z - 1) as f32;
                    let s = i as f32 / (N_MU - 1) as f32;
                    let eta = eta_of_z(z);
                    let e = glass_albedo(
                        s * s,
                        j as f32 / (N_ROUGH - 1) as f32,
                        if inside { 1.0 / eta } else { eta },
                    );
                    assert_eq!(data[t * CELLS + idx], e, "table {t} cell {idx}");
                }
            }
        }
    }

    /// The table against the mean sampled weight of the lobe itself (reflection or refraction
    /// chosen by Fresnel, weight G2/G1).
    #[test]
    fn albedo_is_the_lobe_s_sampled_energy() {
        let mut rng = Rng::new(5, 1);
        for (r, ior, mu, outside) in [
            (0.3f32, 1.5f32, 0.9f32, true),
            (0.3, 1.5, 0.3, true),
            (0.3, 1.5, 0.6, false),
            (0.7, 1.33, 0.2, false),
            (0.5, 2.2, 0.5, true),
        ] {
            let lobe = RoughDielectric {
                ggx: Ggx::new(alpha_from_roughness(r)),
                eta: ior,
                tint: Vec3::ONE,
                multiscatter: false,
                refraction_only: false,
            };
            let z = if outside { mu } else { -mu };
            let wo = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, z);
            let n = 200_000;
            let mut sum = 0.0f64;
            for _ in 0..n {
                if let Some(s) = lobe.sample(wo, rng.f32(), rng.vec2(), 0xff) {
                    sum += s.weight.x as f64;
                }
            }
            let mc = sum / n as f64;
            let rel = if outside { ior } else { 1.0 / ior };
            let t = albedo(mu, r, rel) as f64;
            assert!(
                (mc - t).abs() < 4e-3,
                "r {r} ior {ior} mu {mu} outside {outside}: {mc} vs {t}"
            );
            assert!(t < 1.0 && t > 0.5, "{t}");
        }
    }

    #[test]
    fn smooth_or_index_matched_interfaces_lose_nothing() {
        assert_eq!(glass_albedo(0.5, 0.0, 1.5), 1.0);
        assert_eq!(glass_albedo(0.5, 0.4, 1.0), 1.0);
        assert!((albedo(0.7, 0.0, 1.5) - 1.0).abs() < 1e-6);
        assert!((compensation(0.7, 0.0, 1.0 / 1.5) - 1.0).abs() < 1e-6);
    }
}
