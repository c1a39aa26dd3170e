//! Piecewise-constant 1D and 2D distributions (pbrt-v4 §A.5), used for light selection
//! and environment-map importance sampling.

use glam::Vec2;

#[derive(Clone, Debug)]
pub struct Distribution1D {
    func: Vec<f32>,
    cdf: Vec<f32>,
    integral: f32,
}

impl Distribution1D {
    /// Negative or non-finite entries count as zero. An all-zero function samples uniformly.
    pub fn new(f: &[f32]) -> Self {
        let n = f.len().max(1);
        let func: Vec<f32> = (0..n)
            .map(|i| {
                f.get(i)
                    .copied()
                    .filter(|v| v.is_finite() && *v > 0.0)
                    .unwrap_or(0.0)
            })
            .collect();
        let mut cdf = vec![0.0f32; n + 1];
        let mut acc = 0.0f64;
        for i in 0..n {
            acc += func[i] as f64 / n as f64;
            cdf[i + 1] = acc as f32;
        }
        let integral = acc as f32;
        if integral > 0.0 {
            for c in cdf.iter_mut().skip(1) {
                *c /= integral;
            }
        } else {
            for (i, c) in cdf.iter_mut().enumerate() {
                *c = i as f32 / n as f32;
            }
        }
        cdf[n] = 1.0;
        Distribution1D {
            func,
            cdf,
            integral,
        }
    }

    pub fn len(&self) -> usize {
        self.func.len()
    }
    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }
    pub fn integral(&self) -> f32 {
        self.integral
    }

    fn find(&self, u: f32) -> usize {
        // Last index i with cdf[i] <= u, clamped to a valid bucket.
        let idx = self.cdf.partition_point(|&c| c <= u);
        idx.saturating_sub(1).min(self.func.len() - 1)
    }

    /// Discrete probability of bucket `i`.
    pub fn discrete_pdf(&self, i: usize) -> f32 {
        self.cdf[i + 1] - self.cdf[i]
    }

    /// Picks a bucket; returns (index, probability, u remapped to [0,1) within the bucket).
    pub fn sample_discrete(&self, u: f32) -> (usize, f32, f32) {
        let i = self.find(u);
        let p = self.discrete_pdf(i);
        let du = if p > 0.0 {
            ((u - self.cdf[i]) / p).clamp(0.0, 0.999_999_94)
        } else {
            0.5
        };
        (i, p, du)
    }

    /// Continuous sample in [0,1); returns (x, density, bucket).
    pub fn sample_continuous(&self, u: f32) -> (f32, f32, usize) {
        let (i, p, du) = self.sample_discrete(u);
        let n = self.func.len() as f32;
        let x = ((i as f32 + du) / n).min(0.999_999_94);
        (x, p * n, i)
    }

    /// Density of the continuous sampling at x in [0,1).
    pub fn pdf_continuous(&self, x: f32) -> f32 {
        let n = self.func.len();
        let i = ((x * n as f32) as usize).min(n - 1);
        self.discrete_pdf(i) * n as f32
    }
}

/// 2D piecewise-constant distribution over [0,1)^2: marginal over rows (v), conditional per row (u).
#[derive(Clone, Debug)]
pub struct Distribution2D {
    conditional: Vec<Distribution1D>,
    marginal: Distribution1D,
}

impl Distribution2D {
    /// `f` is row-major with `width` columns.
    pub fn new(f: &[f32], width: usize, height: usize) -> Self {
        let conditional: Vec<Distribution1D> = (0..height)
            .map(|v| Distribution1D::new(&f[v * width..(v + 1) * width]))
            .collect();
        let marg: Vec<f32> = conditional.iter().map(|c| c.integral()).collect();
        Distribution2D {
            conditional,
            marginal: Distribution1D::new(&marg),
        }
    }

    /// Returns (point in [0,1)^2, density).
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (y, pdf_y, row) = self.marginal.sample_continuous(u.y);
        let (x, pdf_x, _) = self.conditional[row].sample_continuous(u.x);
        (Vec2::new(x, y), pdf_x * pdf_y)
    }

    pub fn pdf(&self, p: Vec2) -> f32 {
        let h = self.conditional.len();
        let row = ((p.y * h as f32) as usize).min(h - 1);
        self.marginal.pdf_continuous(p.y) * self.conditional[row].pdf_continuous(p.x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn discrete_probabilities_match_function() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0, 4.0]);
        assert!((d.discrete_pdf(0) - 0.125).abs() < 1e-6);
        assert_eq!(d.discrete_pdf(1), 0.0);
        assert!((d.discrete_pdf(3) - 0.5).abs() < 1e-6);
        for k in 0..1000 {
            let (i, _, du) = d.sample_discrete(k as f32 / 1000.0);
            assert_ne!(i, 1, "zero bucket never chosen");
            assert!((0.0..1.0).contains(&du));
        }
    }

    #[test]
    fn pdf_2d_integrates_to_one() {
        let (w, h) = (16, 8);
        let f: Vec<f32> = (0..w * h).map(|i| ((i * 7919) % 13) as f32).collect();
        let d = Distribution2D::new(&f, w, h);
        let n = 256;
        let mut sum = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let p = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                sum += d.pdf(p) as f64;
            }
        }
        assert!((sum / (n * n) as f64 - 1.0).abs() < 1e-3);
        let (p, pdf) = d.sample(Vec2::new(0.3, 0.7));
        assert!((d.pdf(p) - pdf).abs() < 1e-3 * pdf);
    }
}
