//! Directional-albedo tables of GGX reflection (Schlick's, and one per tabulated coat F0,
//! embedded from `ggx_albedo.bin`) and Cycles' compensation for multiple scattering between
//! microfacets (Kulla & Conty 2017) built on them.

use crate::materials::fresnel::{fresnel_dielectric, ior_from_f0};
use crate::materials::microfacet::{alpha_from_roughness, reflect, Ggx};
use crate::math::Spectrum;
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::sync::Mutex;

const N_MU: usize = 48;
const N_ROUGH: usize = 32;
const STRATA: usize = 32;

/// Directional albedo E(mu) = integral of f_coat |cos| of a coat's single-scattering
/// reflection (GGX with dielectric Fresnel, or the smooth Fresnel R(mu) at roughness 0) for
/// one coat F0, tabulated over (sqrt(mu), perceptual roughness), with the coat's average
/// Fresnel reflectance F_avg = 2 integral F(mu) mu dmu (the F_ss of the compensation).
#[derive(Debug, PartialEq)]
pub struct CoatAlbedoTable {
    f0: f32,
    e: Vec<f32>,
    fresnel_avg: f32,
}

fn coat_albedo(mu: f32, roughness: f32, eta: f32) -> f32 {
    if roughness <= 0.0 {
        return fresnel_dielectric(mu.clamp(1e-3, 1.0), eta).0;
    }
    ggx_albedo(mu, roughness, |c| fresnel_dielectric(c, eta).0)
}

/// Directional albedo of GGX reflection with the microfacet reflectance `fresnel(wo . m)`,
/// integral of F(wo.m) G2/G1 over the visible normals ([`visible_normal_integral`]).
fn ggx_albedo(mu: f32, roughness: f32, fresnel: impl Fn(f32) -> f32) -> f32 {
    ggx_albedo2(mu, roughness, |c| Vec2::new(fresnel(c), 0.0)).x
}

/// [`ggx_albedo`] for two reflectance functions at once (one set of GGX samples).
fn ggx_albedo2(mu: f32, roughness: f32, fresnel: impl Fn(f32) -> Vec2) -> Vec2 {
    visible_normal_integral(mu, roughness, |ggx, wo, m, lo| {
        let wi = reflect(wo, m);
        if wi.z > 0.0 {
            fresnel(wo.dot(m)) * ((1.0 + lo) / (1.0 + lo + ggx.lambda(wi)))
        } else {
            Vec2::ZERO
        }
    })
}

/// The integral over GGX's visible normals m of `f(ggx, wo, m, Lambda(wo))` for the view
/// cosine `mu` (clamped to [1e-3, 1]): a midpoint rule over the visible-normal warp in t, where
/// sin t = sqrt(u1) is the radius on the projected disk (the integrands are smooth in t; they
/// have a square-root edge in u1 at the rim and at the centre), and du1 = sin 2t dt.
pub(in crate::materials) fn visible_normal_integral(
    mu: f32,
    roughness: f32,
    f: impl Fn(&Ggx, Vec3, Vec3, f32) -> Vec2,
) -> Vec2 {
    let mu = mu.clamp(1e-3, 1.0);
    let ggx = Ggx::new(alpha_from_roughness(roughness));
    let wo = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let lo = ggx.lambda(wo);
    let (mut sx, mut sy) = (0.0f64, 0.0f64);
    let h = std::f64::consts::FRAC_PI_2 / STRATA as f64;
    for i in 0..STRATA {
        let t = (i as f64 + 0.5) * h;
        let w = (2.0 * t).sin() * h;
        let st = t.sin();
        for j in 0..STRATA {
            let u = Vec2::new((st * st) as f32, (j as f32 + 0.5) / STRATA as f32);
            let v = f(&ggx, wo, ggx.sample_visible(wo, u), lo);
            sx += w * v.x as f64;
            sy += w * v.y as f64;
        }
    }
    Vec2::new((sx / STRATA as f64) as f32, (sy / STRATA as f64) as f32)
}

/// Cells of one (sqrt(mu), roughness) table.
const CELLS: usize = N_MU * N_ROUGH;

/// Coats tabulated in `ggx_albedo.bin`, uniformly in sqrt(F0) from 0 to [`MAX_F0`].
pub const N_F0: usize = 33;
const MAX_F0: f32 = 0.99;

/// The tables, as `tables()` computes them: Schlick's A and B, then the coat albedo for each
/// of the [`N_F0`] tabulated F0, each over (sqrt(mu), roughness); little-endian f32.
/// Regenerate with `cargo run --release --example ggx_albedo_tables` (a test checks they
/// agree).
static EMBEDDED: &[u8] = include_bytes!("../ggx_albedo.bin");

fn embedded() -> &'static [f32] {
    static DATA: std::sync::OnceLock<Vec<f32>> = std::sync::OnceLock::new();
    DATA.get_or_init(|| decode_f32(EMBEDDED))
}

/// A table embedded as little-endian f32.
pub(in crate::materials) fn decode_f32(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// Computes the tables of `ggx_albedo.bin` (a few seconds on two cores).
pub fn tables() -> Vec<f32> {
    let mut out = schlick_tables();
    for k in 0..N_F0 {
        out.extend(coat_slice(k));
    }
    out
}

/// Schlick's A then B over (sqrt(mu), roughness).
fn schlick_tables() -> Vec<f32> {
    let ab: Vec<Vec2> = tabulate(CELLS, |idx| {
        let (j, i) = (idx / N_MU, idx % N_MU);
        let r = j as f32 / (N_ROUGH - 1) as f32;
        let s = i as f32 / (N_MU - 1) as f32;
        let mu = s * s;
        if r <= 0.0 {
            let t = (1.0 - mu.clamp(1e-3, 1.0)).powi(5);
            Vec2::new(1.0 - t, t)
        } else {
            ggx_albedo2(mu, r, |c| {
                let t = (1.0 - c.clamp(0.0, 1.0)).powi(5);
                Vec2::new(1.0 - t, t)
            })
        }
    });
    let mut out: Vec<f32> = ab.iter().map(|v| v.x).collect();
    out.extend(ab.iter().map(|v| v.y));
    out
}

/// The coat albedo table of the `k`-th tabulated F0.
fn coat_slice(k: usize) -> Vec<f32> {
    let sq = MAX_F0.sqrt() * k as f32 / (N_F0 - 1) as f32;
    let eta = ior_from_f0(sq * sq);
    tabulate(CELLS, |idx| {
        let (j, i) = (idx / N_MU, idx % N_MU);
        let r = j as f32 / (N_ROUGH - 1) as f32;
        let s = i as f32 / (N_MU - 1) as f32;
        coat_albedo(s * s, r, eta)
    })
}

/// `f(0..n)`, in parallel unless the caller is a worker of a rayon pool: a worker waiting
/// for its parallel loop may run other jobs of its pool meanwhile, and one of them could ask
/// for the very table this builds (a one-time initialisation it already holds).
fn tabulate<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
    if rayon::current_thread_index().is_some() {
        (0..n).map(f).collect()
    } else {
        (0..n).into_par_iter().map(f).collect()
    }
}

/// Directional albedo of GGX reflection with Schlick's Fresnel, F = F0 + (1 - F0)(1 - c)^5:
/// linear in F0, so two tables over (sqrt(mu), perceptual roughness) give it for any F0 (and
/// per channel): E = F0 A + B with A the albedo of weight 1 - (1 - c)^5 and B of (1 - c)^5.
/// A + B is the albedo of a perfect reflector, 1 less the single-scattering energy loss.
#[derive(Debug)]
pub struct SchlickAlbedoTable {
    a: Vec<f32>,
    b: Vec<f32>,
    /// Per roughness, the cosine-weighted average of A + B over the hemisphere.
    e1_avg: Vec<f32>,
}

impl SchlickAlbedoTable {
    /// The table, built on first use.
    pub fn get() -> &'static SchlickAlbedoTable {
        static TABLE: std::sync::OnceLock<SchlickAlbedoTable> = std::sync::OnceLock::new();
        TABLE.get_or_init(|| {
            let data = embedded();
            let a = data[..CELLS].to_vec();
            let b = data[CELLS..2 * CELLS].to_vec();
            // 2 integral mu E1 dmu = integral 4 s^3 E1(s) ds with s = sqrt(mu); E1 is linear in
            // s on each segment, so 3-point Gauss-Legendre is exact for the interpolant.
            let h = 1.0 / (N_MU - 1) as f64;
            let e1_avg = (0..N_ROUGH)
                .map(|j| {
                    let e1 = |i: usize| (a[j * N_MU + i] + b[j * N_MU + i]) as f64;
                    let mut acc = 0.0f64;
                    for i in 0..N_MU - 1 {
                        for (x, w) in GL3 {
                            let s = (i as f64 + x) * h;
                            acc += w * h * 4.0 * s * s * s * (e1(i) + (e1(i + 1) - e1(i)) * x);
                        }
                    }
                    acc as f32
                })
                .collect();
            SchlickAlbedoTable { a, b, e1_avg }
        })
    }

    /// Albedo of a perfect GGX reflector (F = 1) at (mu, perceptual roughness).
    pub fn e1(&self, mu: f32, roughness: f32) -> f32 {
        let (a, b) = self.ab(mu, roughness);
        a + b
    }

    /// The hemispherical average of [`SchlickAlbedoTable::e1`].
    pub fn e1_avg(&self, roughness: f32) -> f32 {
        let (j, tj) = CoatAlbedoTable::cell(roughness, N_ROUGH);
        self.e1_avg[j] * (1.0 - tj) + self.e1_avg[j + 1] * tj
    }

    /// (A, B) at (mu, perceptual roughness), bilinear in (sqrt(mu), roughness).
    pub fn ab(&self, mu: f32, roughness: f32) -> (f32, f32) {
        let (j, tj) = CoatAlbedoTable::cell(roughness, N_ROUGH);
        let (i, ti) = CoatAlbedoTable::cell(mu.max(0.0).sqrt(), N_MU);
        let lerp = |t: &[f32]| {
            let at = |j: usize| {
                let b = j * N_MU + i;
                t[b] * (1.0 - ti) + t[b + 1] * ti
            };
            at(j) * (1.0 - tj) + at(j + 1) * tj
        };
        (lerp(&self.a), lerp(&self.b))
    }

    /// Albedo of GGX reflection with Schlick's F0 `f0` at (mu, perceptual roughness).
    pub fn albedo(&self, mu: f32, roughness: f32, f0: Spectrum) -> Spectrum {
        let (a, b) = self.ab(mu, roughness);
        f0 * a + Spectrum::splat(b)
    }
}

/// Cycles' compensation of single-scattering GGX for the energy that multiple scattering
/// between microfacets would reflect (`microfacet_ggx_preserve_energy`, after Kulla & Conty
/// 2017): f = f_ss (1 + F_ms (1 - E1(mu_o)) / E1(mu_o)), with E1 the albedo of a perfect
/// reflector at the view angle, E1_avg its average, and F_ms = F_ss E1_avg / (1 - F_ss (1 -
/// E1_avg)) from the lobe's average Fresnel reflectance F_ss. Like Cycles it depends on the
/// view direction only (the photon pass uses it with the directions swapped).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MultiScatter {
    roughness: f32,
    f_ms: Spectrum,
}

impl MultiScatter {
    pub fn new(roughness: f32, f_ss: Spectrum) -> Self {
        let e_avg = SchlickAlbedoTable::get().e1_avg(roughness);
        let f_ms = f_ss * e_avg / (Spectrum::ONE - f_ss * (1.0 - e_avg)).max(Spectrum::splat(1e-6));
        MultiScatter { roughness, f_ms }
    }

    /// The factor on f for the view cosine `mu_o`.
    pub fn factor(&self, mu_o: f32) -> Spectrum {
        let e1 = SchlickAlbedoTable::get().e1(mu_o, self.roughness).max(1e-3);
        Spectrum::ONE + self.f_ms * ((1.0 - e1) / e1)
    }
}

/// The cell of `x` in [0, 1] (clamped; NaN reads as 0) on a grid of `n` points, and the
/// position inside it, for linear interpolation.
pub(in crate::materials) fn cell(x: f32, n: usize) -> (usize, f32) {
    let x = if x.is_finite() {
        x.clamp(0.0, 1.0)
    } else {
        0.0
    } * (n - 1) as f32;
    let i = (x as usize).min(n - 2);
    (i, x - i as f32)
}

/// 3-point Gauss-Legendre on [0, 1] (exact to degree 5).
const GL3: [(f64, f64); 3] = [
    (0.112_701_665_379_258_3, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];

impl CoatAlbedoTable {
    /// The table of a coat of normal reflectance `f0`: the two tabulated coats nearest in
    /// sqrt(F0) ([`N_F0`] of them, precomputed in `ggx_albedo.bin`), blended linearly.
    fn build(f0: f32) -> Self {
        let eta = ior_from_f0(f0);
        let data = embedded();
        let x = (f0.max(0.0).sqrt() / MAX_F0.sqrt()).clamp(0.0, 1.0) * (N_F0 - 1) as f32;
        let k = (x as usize).min(N_F0 - 2);
        let t = x - k as f32;
        let slice = |k: usize| &data[(2 + k) * CELLS..(3 + k) * CELLS];
        let (lo, hi) = (slice(k), slice(k + 1));
        let e: Vec<f32> = lo
            .iter()
            .zip(hi)
            .map(|(a, b)| a * (1.0 - t) + b * t)
            .collect();
        // 2 integral F(mu) mu dmu by the midpoint rule in mu^2.
        const STEPS: usize = 1024;
        let fresnel_avg = (0..STEPS)
            .map(|i| {
                let mu = ((i as f64 + 0.5) / STEPS as f64).sqrt() as f32;
                fresnel_dielectric(mu, eta).0 as f64
            })
            .sum::<f64>()
            / STEPS as f64;
        CoatAlbedoTable {
            f0,
            e,
            fresnel_avg: fresnel_avg as f32,
        }
    }

    /// The table for a coat of normal reflectance `f0`, made on first use and kept for the
    /// life of the process.
    pub fn for_f0(f0: f32) -> &'static CoatAlbedoTable {
        static TABLES: Mutex<Vec<&'static CoatAlbedoTable>> = Mutex::new(Vec::new());
        let f0 = if f0.is_finite() {
            f0.clamp(0.0, 0.99)
        } else {
            0.0
        };
        let mut tables = TABLES.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = tables.iter().find(|t| t.f0.to_bits() == f0.to_bits()) {
            return t;
        }
        let t: &'static CoatAlbedoTable = Box::leak(Box::new(CoatAlbedoTable::build(f0)));
        tables.push(t);
        t
    }

    pub fn f0(&self) -> f32 {
        self.f0
    }

    fn cell(x: f32, n: usize) -> (usize, f32) {
        cell(x, n)
    }

    /// E(mu) by bilinear interpolation in (sqrt(mu), roughness).
    pub fn albedo(&self, mu: f32, roughness: f32) -> f32 {
        if roughness <= 0.0 {
            // The smooth coat: its exact Fresnel reflectance, so that a delta coat and the
            // base under it add up to one at every angle.
            return fresnel_dielectric(mu.clamp(1e-3, 1.0), ior_from_f0(self.f0)).0;
        }
        let (j, tj) = Self::cell(roughness, N_ROUGH);
        let (i, ti) = Self::cell(mu.max(0.0).sqrt(), N_MU);
        let at = |j: usize| {
            let b = j * N_MU + i;
            self.e[b] * (1.0 - ti) + self.e[b + 1] * ti
        };
        at(j) * (1.0 - tj) + at(j + 1) * tj
    }

    /// The coat's average Fresnel reflectance over the hemisphere.
    pub fn fresnel_avg(&self) -> f32 {
        self.fresnel_avg
    }

    /// Directional albedo with Cycles' multiple-scattering compensation when `multiscatter`.
    pub fn albedo_ms(&self, mu: f32, roughness: f32, multiscatter: bool) -> f32 {
        let e = self.albedo(mu, roughness);
        if multiscatter {
            e * MultiScatter::new(roughness, Spectrum::splat(self.fresnel_avg))
                .factor(mu)
                .x
        } else {
            e
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Reference E(mu): plain Monte Carlo with a million samples (unbiased, independent of
    /// the table's quadrature).
    fn reference(mu: f32, roughness: f32, eta: f32) -> f64 {
        let ggx = Ggx::new(alpha_from_roughness(roughness));
        let wo = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
        let lo = ggx.lambda(wo);
        let mut rng = Rng::new(77, (mu * 1e6) as u64);
        let n = 1 << 20;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let m = ggx.sample_visible(wo, rng.vec2());
            let wi = reflect(wo, m);
            if wi.z > 0.0 {
                let f = fresnel_dielectric(wo.dot(m), eta).0;
                sum += (f * (1.0 + lo) / (1.0 + lo + ggx.lambda(wi))) as f64;
            }
        }
        sum / n as f64
    }

    /// `ggx_albedo.bin` is what `tables()` computes (Schlick's tables and two coats).
    #[test]
    fn embedded_tables_are_the_generator_s() {
        let data = embedded();
        assert_eq!(data.len(), (2 + N_F0) * CELLS);
        assert_eq!(&data[..2 * CELLS], &schlick_tables()[..], "Schlick tables");
        for k in [1, N_F0 / 2] {
            assert_eq!(
                &data[(2 + k) * CELLS..(3 + k) * CELLS],
                &coat_slice(k)[..],
                "coat {k}"
            );
        }
    }

    #[test]
    fn table_matches_brute_force() {
        let mut rng = Rng::new(12, 0);
        for f0 in [0.04f32, 0.2] {
            let t = CoatAlbedoTable::for_f0(f0);
            assert!(std::ptr::eq(t, CoatAlbedoTable::for_f0(f0)), "cached");
            let eta = ior_from_f0(f0);
            let mut worst = 0.0f64;
            for _ in 0..12 {
                let mu = 0.02 + 0.98 * rng.f32();
                let r = 0.05 + 0.95 * rng.f32();
                let err = (t.albedo(mu, r) as f64 - reference(mu, r, eta)).abs();
                worst = worst.max(err);
            }
            eprintln!("F0 {f0}: worst table error {worst:.2e}");
            assert!(worst < 6e-4, "F0 {f0}: {worst}");
            // Smooth coat: the exact Fresnel reflectance.
            for mu in [0.05f32, 0.3, 1.0] {
                let e = t.albedo(mu, 0.0);
                assert!(
                    (e - fresnel_dielectric(mu, eta).0).abs() < 5e-3,
                    "{mu}: {e}"
                );
            }
        }
    }
}
