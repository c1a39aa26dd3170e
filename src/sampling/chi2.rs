//! Chi-square goodness-of-fit test for direction samplers on the sphere (after Mitsuba 3
//! `chi2.py` and pbrt-v4 `bsdfs_test.cpp`). Used for BSDFs, lights and phase functions.
//!
//! The test draws N samples, histograms them on a (cos theta, phi) grid, and integrates the
//! claimed pdf over every cell with Gauss-Legendre quadrature in (theta, phi). Cells expected
//! to receive fewer than `min_expected` samples are pooled. The chi-square statistic's
//! p-value comes from the regularised incomplete gamma function; the null hypothesis
//! ("samples follow pdf") is rejected below the significance level after Šidák correction
//! for the number of tests run. Beside the histogram it checks that every sample's reported
//! pdf equals pdf(direction), that the pdf integrates to at most one (exactly one when
//! `normalized`), and that the fraction of successful samples equals that integral.

use super::Rng;
use glam::Vec3;
use rayon::prelude::*;
use std::f64::consts::PI;
use std::fmt;

/// Settings of one chi-square test.
#[derive(Clone, Debug)]
pub struct Chi2Config {
    /// Bins in cos theta over [-1, 1].
    pub theta_bins: usize,
    /// Bins in phi over [0, 2 pi).
    pub phi_bins: usize,
    /// Number of sample attempts.
    pub samples: usize,
    /// Significance level before correction.
    pub significance: f64,
    /// Number of tests in the family (Šidák correction).
    pub num_tests: usize,
    /// Cells expecting fewer samples are pooled.
    pub min_expected: f64,
    /// Largest width, in radians, of one 8-point Gauss-Legendre panel; must be below the
    /// width of the sharpest pdf feature where no sample fell.
    pub quad_step: f64,
    /// Panel width used in cells that received samples; set it below the width of the
    /// sharpest pdf feature (about alpha |wo.h| for GGX reflection).
    pub fine_step: f64,
    /// Relative tolerance between a sample's reported pdf and pdf(direction).
    pub pdf_rel_tol: f32,
    /// Whether the pdf must integrate to one (no absorption, no delta components).
    pub normalized: bool,
    pub seed: u64,
}

impl Default for Chi2Config {
    fn default() -> Self {
        Chi2Config {
            theta_bins: 10,
            phi_bins: 20,
            samples: 1_000_000,
            significance: 0.01,
            num_tests: 1,
            min_expected: 5.0,
            quad_step: 0.02,
            fine_step: 0.02,
            pdf_rel_tol: 1e-3,
            normalized: false,
            seed: 0,
        }
    }
}

/// Outcome of [`chi2_test`].
#[derive(Clone, Debug)]
pub struct Chi2Report {
    pub chi2: f64,
    pub dof: usize,
    pub p_value: f64,
    /// Significance after Šidák correction: 1 - (1 - significance)^(1 / num_tests).
    pub threshold: f64,
    /// Integral of the pdf over the sphere.
    pub pdf_integral: f64,
    pub samples: usize,
    /// Samples that returned a direction.
    pub valid_samples: usize,
    /// Samples whose reported pdf differs from pdf(direction).
    pub pdf_mismatches: usize,
    /// Worst mismatch: (direction, reported pdf, pdf(direction)).
    pub worst_mismatch: Option<(Vec3, f32, f32)>,
    /// Samples whose direction was not a finite unit vector.
    pub bad_directions: usize,
    /// Cells merged into the pool.
    pub pooled_cells: usize,
    /// Every failed check, in words; empty when the test passed.
    pub failures: Vec<String>,
}

impl Chi2Report {
    pub fn passed(&self) -> bool {
        self.failures.is_empty()
    }
}

impl fmt::Display for Chi2Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "chi2 = {:.2} (dof {}), p = {:.4} (threshold {:.2e}), integral of pdf = {:.5}, \
             {} / {} samples valid, {} pdf mismatches, {} pooled cells",
            self.chi2,
            self.dof,
            self.p_value,
            self.threshold,
            self.pdf_integral,
            self.valid_samples,
            self.samples,
            self.pdf_mismatches,
            self.pooled_cells
        )?;
        if let Some((d, a, b)) = self.worst_mismatch {
            write!(f, "; worst mismatch at {d:?}: sampled pdf {a} vs pdf {b}")?;
        }
        for msg in &self.failures {
            write!(f, "\n  FAILED: {msg}")?;
        }
        Ok(())
    }
}

/// Natural log of the gamma function (Lanczos, g = 7, n = 9).
pub fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection formula.
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + G + 0.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// Regularised upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a)
/// (series for x < a + 1, Lentz's continued fraction otherwise; Numerical Recipes §6.2).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if a.is_nan() || a <= 0.0 || x.is_nan() {
        return f64::NAN;
    }
    if x <= 0.0 {
        return 1.0;
    }
    let log_prefix = -x + a * x.ln() - ln_gamma(a);
    if x < a + 1.0 {
        let mut ap = a;
        let mut del = 1.0 / a;
        let mut sum = del;
        for _ in 0..10_000 {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if del.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - sum * log_prefix.exp()).clamp(0.0, 1.0)
    } else {
        const TINY: f64 = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < TINY {
                d = TINY;
            }
            c = b + an / c;
            if c.abs() < TINY {
                c = TINY;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-16 {
                break;
            }
        }
        (log_prefix.exp() * h).clamp(0.0, 1.0)
    }
}

/// Probability that a chi-square variable with `dof` degrees of freedom exceeds `chi2`.
pub fn chi2_p_value(chi2: f64, dof: usize) -> f64 {
    if dof == 0 {
        return 1.0;
    }
    gamma_q(0.5 * dof as f64, 0.5 * chi2)
}

/// 8-point Gauss-Legendre nodes and weights on [-1, 1].
const GL_X: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
const GL_W: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// Nodes and weights covering [a, b] with panels no wider than `step`.
fn quadrature(a: f64, b: f64, step: f64) -> Vec<(f64, f64)> {
    let n = (((b - a) / step.max(1e-6)).ceil() as usize).max(1);
    let h = (b - a) / n as f64;
    let mut out = Vec::with_capacity(8 * n);
    for p in 0..n {
        let mid = a + (p as f64 + 0.5) * h;
        for k in 0..4 {
            for s in [-1.0, 1.0] {
                out.push((mid + s * GL_X[k] * 0.5 * h, GL_W[k] * 0.5 * h));
            }
        }
    }
    out
}

fn cell_of(d: Vec3, cfg: &Chi2Config) -> usize {
    let z = d.z.clamp(-1.0, 1.0) as f64;
    let ti = (((1.0 - z) * 0.5 * cfg.theta_bins as f64) as usize).min(cfg.theta_bins - 1);
    let mut phi = (d.y as f64).atan2(d.x as f64);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    let pj = ((phi / (2.0 * PI) * cfg.phi_bins as f64) as usize).min(cfg.phi_bins - 1);
    ti * cfg.phi_bins + pj
}

/// Runs the test. `sample` maps three uniform numbers to `Some((direction, pdf))`, or `None`
/// when the sampler fails or produces a delta event (those count against the integral); a
/// reported pdf of NaN skips the pdf comparison for that sample. `pdf` is the claimed
/// solid-angle density.
pub fn chi2_test<S, P>(cfg: &Chi2Config, mut sample: S, pdf: P) -> Chi2Report
where
    S: FnMut(Vec3) -> Option<(Vec3, f32)>,
    P: Fn(Vec3) -> f32 + Sync,
{
    let (nt, np) = (cfg.theta_bins.max(1), cfg.phi_bins.max(1));
    let cfg = Chi2Config {
        theta_bins: nt,
        phi_bins: np,
        ..cfg.clone()
    };
    let mut failures = Vec::new();

    // 1. Histogram, with the pdf and direction checks.
    let mut observed = vec![0.0f64; nt * np];
    let mut rng = Rng::new(cfg.seed, 0x0c41_5e7e);
    let (mut valid, mut mismatches, mut bad) = (0usize, 0usize, 0usize);
    let mut worst: Option<(Vec3, f32, f32)> = None;
    let mut worst_err = 0.0f32;
    for _ in 0..cfg.samples {
        let Some((d, p)) = sample(rng.vec3()) else {
            continue;
        };
        if !d.is_finite() || (d.length() - 1.0).abs() > 1e-3 {
            bad += 1;
            continue;
        }
        valid += 1;
        observed[cell_of(d, &cfg)] += 1.0;
        if !p.is_nan() {
            let q = pdf(d);
            let err = (p - q).abs() / p.abs().max(q.abs()).max(f32::MIN_POSITIVE);
            if err.is_nan() || err > cfg.pdf_rel_tol {
                mismatches += 1;
                if err.is_nan() || err > worst_err {
                    worst_err = err;
                    worst = Some((d, p, q));
                }
            }
        }
    }

    // 2. Expected counts: integral of the pdf over each cell, finer where samples fell.
    let integrals: Vec<f64> = (0..nt * np)
        .into_par_iter()
        .map(|cell| {
            let (ti, pj) = (cell / np, cell % np);
            let step = if observed[cell] > 0.0 {
                cfg.fine_step.min(cfg.quad_step)
            } else {
                cfg.quad_step
            };
            let z0 = 1.0 - 2.0 * ti as f64 / nt as f64;
            let z1 = 1.0 - 2.0 * (ti + 1) as f64 / nt as f64;
            let th = quadrature(z0.clamp(-1.0, 1.0).acos(), z1.clamp(-1.0, 1.0).acos(), step);
            {
                let ph = quadrature(
                    2.0 * PI * pj as f64 / np as f64,
                    2.0 * PI * (pj + 1) as f64 / np as f64,
                    step,
                );
                let mut acc = 0.0f64;
                for &(t, wt) in &th {
                    let (st, ct) = t.sin_cos();
                    let mut row = 0.0f64;
                    for &(p, wp) in &ph {
                        let (sp, cp) = p.sin_cos();
                        let d = Vec3::new((st * cp) as f32, (st * sp) as f32, ct as f32);
                        let v = pdf(d) as f64;
                        if v.is_finite() {
                            row += wp * v;
                        }
                    }
                    acc += wt * st * row;
                }
                acc
            }
        })
        .collect();
    let integral: f64 = integrals.iter().sum();

    if bad > 0 {
        failures.push(format!("{bad} samples were not finite unit vectors"));
    }
    let allowed = (cfg.samples as f64 * 1e-5).floor() as usize;
    if mismatches > allowed {
        failures.push(format!(
            "{mismatches} samples report a pdf different from pdf(direction) (relative error up to {worst_err:.3e})"
        ));
    }
    const QUAD_TOL: f64 = 2e-3;
    if integral > 1.0 + QUAD_TOL {
        failures.push(format!("the pdf integrates to {integral:.5} > 1"));
    }
    if cfg.normalized && (integral - 1.0).abs() > QUAD_TOL {
        failures.push(format!("the pdf integrates to {integral:.5}, expected 1"));
    }
    let n = cfg.samples.max(1) as f64;
    let frac = valid as f64 / n;
    let sigma = (integral.clamp(0.0, 1.0) * (1.0 - integral.clamp(0.0, 1.0)) / n).sqrt();
    if (frac - integral).abs() > 5.0 * sigma + QUAD_TOL {
        failures.push(format!(
            "{:.5} of the samples succeed but the pdf integrates to {integral:.5}",
            frac
        ));
    }

    // 3. Pool sparse cells and compute the statistic.
    let mut cells: Vec<(f64, f64)> = observed
        .iter()
        .zip(&integrals)
        .map(|(&o, &p)| (o, p.max(0.0) * n))
        .collect();
    cells.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut pool = (0.0f64, 0.0f64);
    let mut pooled = 0usize;
    let mut used: Vec<(f64, f64)> = Vec::new();
    for &(o, e) in &cells {
        if e < cfg.min_expected {
            pool.0 += o;
            pool.1 += e;
            pooled += 1;
        } else {
            used.push((o, e));
        }
    }
    if pooled > 0 {
        if pool.1 >= cfg.min_expected || used.is_empty() {
            used.push(pool);
        } else if let Some(first) = used.first_mut() {
            // Merge a still-sparse pool into the sparsest remaining cell.
            first.0 += pool.0;
            first.1 += pool.1;
        }
    }
    let mut chi2 = 0.0f64;
    for &(o, e) in &used {
        if e > 0.0 {
            chi2 += (o - e) * (o - e) / e;
        } else if o > 0.0 {
            failures.push(format!("{o} samples fell where the pdf integrates to zero"));
        }
    }
    let dof = used.len().saturating_sub(1);
    let p_value = chi2_p_value(chi2, dof);
    let threshold = 1.0 - (1.0 - cfg.significance).powf(1.0 / cfg.num_tests.max(1) as f64);
    if p_value.is_nan() || p_value < threshold {
        failures.push(format!(
            "chi-square rejects the sampler: p = {p_value:.3e} < {threshold:.3e}"
        ));
    }

    Chi2Report {
        chi2,
        dof,
        p_value,
        threshold,
        pdf_integral: integral,
        samples: cfg.samples,
        valid_samples: valid,
        pdf_mismatches: mismatches,
        worst_mismatch: worst,
        bad_directions: bad,
        pooled_cells: pooled,
        failures,
    }
}

/// [`chi2_test`] that panics with the full report when any check fails (for tests).
pub fn assert_chi2<S, P>(name: &str, cfg: &Chi2Config, sample: S, pdf: P) -> Chi2Report
where
    S: FnMut(Vec3) -> Option<(Vec3, f32)>,
    P: Fn(Vec3) -> f32 + Sync,
{
    let r = chi2_test(cfg, sample, pdf);
    assert!(r.passed(), "chi-square test `{name}` failed: {r}");
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::warp::*;
    use glam::Vec2;

    #[test]
    fn gamma_and_chi2_cdf_match_tables() {
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
        assert!((ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-12);
        // Critical values of the chi-square distribution.
        assert!((chi2_p_value(3.841_459, 1) - 0.05).abs() < 1e-5);
        assert!((chi2_p_value(23.209_25, 10) - 0.01).abs() < 1e-5);
        assert!((chi2_p_value(124.342, 100) - 0.05).abs() < 1e-4);
        assert!((chi2_p_value(2.0, 2) - (-1.0f64).exp()).abs() < 1e-12);
    }

    fn cfg() -> Chi2Config {
        Chi2Config {
            samples: 200_000,
            normalized: true,
            ..Default::default()
        }
    }

    #[test]
    fn accepts_correct_warps() {
        assert_chi2(
            "cosine hemisphere",
            &cfg(),
            |u| {
                let d = square_to_cosine_hemisphere(Vec2::new(u.x, u.y));
                Some((d, cosine_hemisphere_pdf(d)))
            },
            cosine_hemisphere_pdf,
        );
        assert_chi2(
            "uniform sphere",
            &cfg(),
            |u| {
                Some((
                    square_to_uniform_sphere(Vec2::new(u.x, u.y)),
                    UNIFORM_SPHERE_PDF,
                ))
            },
            |_| UNIFORM_SPHERE_PDF,
        );
        let cm = 0.7f32;
        assert_chi2(
            "cone",
            &cfg(),
            |u| {
                Some((
                    square_to_uniform_cone(Vec2::new(u.y, u.z), cm),
                    uniform_cone_pdf(cm),
                ))
            },
            |d| if d.z >= cm { uniform_cone_pdf(cm) } else { 0.0 },
        );
    }

    #[test]
    fn rejects_wrong_pdfs() {
        // Cosine samples claimed to be uniform on the hemisphere.
        let r = chi2_test(
            &cfg(),
            |u| Some((square_to_cosine_hemisphere(Vec2::new(u.x, u.y)), f32::NAN)),
            |d| {
                if d.z > 0.0 {
                    UNIFORM_HEMISPHERE_PDF
                } else {
                    0.0
                }
            },
        );
        assert!(r.p_value < 1e-10 && !r.passed(), "{r}");
        // A reported pdf that disagrees with the pdf function.
        let r = chi2_test(
            &cfg(),
            |u| {
                let d = square_to_cosine_hemisphere(Vec2::new(u.x, u.y));
                Some((d, 2.0 * cosine_hemisphere_pdf(d)))
            },
            cosine_hemisphere_pdf,
        );
        assert!(r.pdf_mismatches > 0 && !r.passed(), "{r}");
        // A pdf that is not normalised.
        let r = chi2_test(
            &cfg(),
            |u| Some((square_to_uniform_sphere(Vec2::new(u.x, u.y)), f32::NAN)),
            |_| 1.1 * UNIFORM_SPHERE_PDF,
        );
        assert!(!r.passed(), "{r}");
    }
}
