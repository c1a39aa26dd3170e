//! Homogeneous medium.
//!
//! | parameter | meaning |
//! |---|---|
//! | `sigma_a` | absorption coefficient per unit length, RGB |
//! | `sigma_s` | scattering coefficient per unit length, RGB |
//! | `g` | Henyey-Greenstein anisotropy |

use super::phase::HenyeyGreenstein;
use crate::math::Spectrum;

#[derive(Clone, Debug)]
pub struct Homogeneous {
    pub sigma_a: Spectrum,
    pub sigma_s: Spectrum,
    pub sigma_t: Spectrum,
    pub phase: HenyeyGreenstein,
}

impl Homogeneous {
    pub fn new(sigma_a: Spectrum, sigma_s: Spectrum, g: f32) -> Self {
        Homogeneous {
            sigma_a,
            sigma_s,
            sigma_t: sigma_a + sigma_s,
            phase: HenyeyGreenstein::new(g),
        }
    }

    /// exp(-sigma_t d) per channel. The optical depth is formed in f64 and the exponential of
    /// a huge depth is exactly 0, never NaN (0 x inf is avoided for d = inf, sigma_t = 0).
    pub fn transmittance(&self, d: f32) -> Spectrum {
        let f = |s: f32| -> f32 {
            if s <= 0.0 || d <= 0.0 {
                1.0
            } else if !d.is_finite() {
                0.0
            } else {
                (-(s as f64) * d as f64).exp() as f32
            }
        };
        Spectrum::new(f(self.sigma_t.x), f(self.sigma_t.y), f(self.sigma_t.z))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transmittance_is_exact_and_robust() {
        for st in [1e-6f32, 1e-3, 0.5, 3.0, 1e2, 1e4] {
            let m = Homogeneous::new(Spectrum::splat(st * 0.3), Spectrum::splat(st * 0.7), 0.0);
            for d in [0.0f32, 1e-4, 0.37, 2.0, 1e3] {
                let t = m.transmittance(d).x;
                let exact = (-(st as f64) * (d as f64)).exp();
                assert!(
                    t.is_finite()
                        && (t as f64 - exact).abs()
                            <= 1e-7 * exact.max(1e-30) + f32::MIN_POSITIVE as f64,
                    "{st} {d}: {t} vs {exact}"
                );
            }
            assert_eq!(m.transmittance(f32::INFINITY).x, 0.0);
        }
        let vacuum = Homogeneous::new(Spectrum::ZERO, Spectrum::ZERO, 0.0);
        assert_eq!(vacuum.transmittance(f32::INFINITY), Spectrum::ONE);
    }
}
