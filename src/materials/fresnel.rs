//! Fresnel reflectance: exact dielectric and conductor equations, Schlick's approximation,
//! and the closed set of Fresnel models a reflection lobe can carry.

use crate::math::Spectrum;
use glam::Vec3;

/// Unpolarised Fresnel reflectance of a dielectric interface (after Mitsuba 3 `fresnel`).
///
/// `cos_i` is the cosine between the direction and the normal (+z); positive means the
/// direction lies on the outside. `eta` is the relative IOR inside/outside.
///
/// Returns `(R, cos_t, eta_it, eta_ti)`: the reflectance, the signed cosine of the refracted
/// direction (opposite sign to `cos_i`; 0 under total internal reflection), and the relative
/// IOR crossed (`eta_it` = eta_transmitted / eta_incident) and its reciprocal.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> (f32, f32, f32, f32) {
    let outside = cos_i >= 0.0;
    let eta = if eta > 0.0 && eta.is_finite() {
        eta
    } else {
        1.0
    };
    let (eta_it, eta_ti) = if outside {
        (eta, 1.0 / eta)
    } else {
        (1.0 / eta, eta)
    };
    let cos_i_abs = cos_i.abs().min(1.0);
    let cos_t_sqr = 1.0 - eta_ti * eta_ti * (1.0 - cos_i_abs * cos_i_abs);
    let cos_t_abs = cos_t_sqr.max(0.0).sqrt();
    let r = if eta == 1.0 {
        0.0
    } else if cos_i_abs == 0.0 || cos_t_sqr <= 0.0 {
        1.0
    } else {
        let a_s = (cos_i_abs - eta_it * cos_t_abs) / (cos_i_abs + eta_it * cos_t_abs);
        let a_p = (cos_t_abs - eta_it * cos_i_abs) / (cos_t_abs + eta_it * cos_i_abs);
        (0.5 * (a_s * a_s + a_p * a_p)).clamp(0.0, 1.0)
    };
    let cos_t = if outside { -cos_t_abs } else { cos_t_abs };
    (r, cos_t, eta_it, eta_ti)
}

/// Reflectance at normal incidence of an interface with relative IOR `eta`.
#[inline]
pub fn f0_from_ior(eta: f32) -> f32 {
    let r = (eta - 1.0) / (eta + 1.0);
    r * r
}

/// Relative IOR whose normal-incidence reflectance is `f0` (inverse of [`f0_from_ior`]).
#[inline]
pub fn ior_from_f0(f0: f32) -> f32 {
    let s = f0.clamp(0.0, 0.99).sqrt();
    (1.0 + s) / (1.0 - s)
}

#[derive(Clone, Copy)]
struct Complex {
    re: f64,
    im: f64,
}

impl Complex {
    fn new(re: f64, im: f64) -> Self {
        Complex { re, im }
    }
    fn add(self, o: Complex) -> Complex {
        Complex::new(self.re + o.re, self.im + o.im)
    }
    fn sub(self, o: Complex) -> Complex {
        Complex::new(self.re - o.re, self.im - o.im)
    }
    fn mul(self, o: Complex) -> Complex {
        Complex::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
    fn div(self, o: Complex) -> Complex {
        let d = o.re * o.re + o.im * o.im;
        if d == 0.0 {
            return Complex::new(0.0, 0.0);
        }
        Complex::new(
            (self.re * o.re + self.im * o.im) / d,
            (self.im * o.re - self.re * o.im) / d,
        )
    }
    fn norm(self) -> f64 {
        self.re * self.re + self.im * self.im
    }
    fn sqrt(self) -> Complex {
        let n = self.norm().sqrt();
        if n == 0.0 {
            return Complex::new(0.0, 0.0);
        }
        let t1 = (0.5 * (n + self.re.abs())).sqrt();
        let t2 = 0.5 * self.im / t1;
        if self.re >= 0.0 {
            Complex::new(t1, t2)
        } else {
            Complex::new(t2.abs(), t1.copysign(self.im))
        }
    }
}

/// Fresnel reflectance of a conductor with complex IOR `eta + i k` (pbrt-v4 `FrComplex`).
pub fn fresnel_conductor_1(cos_i: f32, eta: f32, k: f32) -> f32 {
    let c = (cos_i as f64).clamp(0.0, 1.0);
    let eta = Complex::new(eta as f64, k as f64);
    let sin2_i = Complex::new(1.0 - c * c, 0.0);
    let sin2_t = sin2_i.div(eta.mul(eta));
    let cos_t = Complex::new(1.0, 0.0).sub(sin2_t).sqrt();
    let ci = Complex::new(c, 0.0);
    let r_parl = eta.mul(ci).sub(cos_t).div(eta.mul(ci).add(cos_t));
    let r_perp = ci.sub(eta.mul(cos_t)).div(ci.add(eta.mul(cos_t)));
    let r = 0.5 * (r_parl.norm() + r_perp.norm());
    if r.is_finite() {
        r.clamp(0.0, 1.0) as f32
    } else {
        1.0
    }
}

/// Per-channel conductor Fresnel.
pub fn fresnel_conductor(cos_i: f32, eta: Vec3, k: Vec3) -> Spectrum {
    Vec3::new(
        fresnel_conductor_1(cos_i, eta.x, k.x),
        fresnel_conductor_1(cos_i, eta.y, k.y),
        fresnel_conductor_1(cos_i, eta.z, k.z),
    )
}

/// Schlick's approximation `F0 + (1 - F0)(1 - cos)^5`.
#[inline]
pub fn fresnel_schlick(cos_i: f32, f0: Spectrum) -> Spectrum {
    let m = (1.0 - cos_i.abs().min(1.0)).max(0.0);
    let m2 = m * m;
    f0 + (Vec3::ONE - f0) * (m2 * m2 * m)
}

/// The Fresnel model of a reflection lobe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fresnel {
    /// Constant reflectance (an ideal mirror of the given colour).
    Constant(Spectrum),
    /// Conductor with complex IOR `eta + i k` per channel.
    Conductor { eta: Spectrum, k: Spectrum },
    /// Schlick's approximation with normal-incidence reflectance `f0` (a tint).
    Schlick { f0: Spectrum },
    /// Reflection off a dielectric of relative IOR `eta` (seen from outside).
    Dielectric { eta: f32 },
}

impl Fresnel {
    /// Reflectance for the cosine between the direction and the (micro)normal.
    pub fn eval(&self, cos_i: f32) -> Spectrum {
        match *self {
            Fresnel::Constant(c) => c,
            Fresnel::Conductor { eta, k } => fresnel_conductor(cos_i, eta, k),
            Fresnel::Schlick { f0 } => fresnel_schlick(cos_i, f0),
            Fresnel::Dielectric { eta } => Vec3::splat(fresnel_dielectric(cos_i.abs(), eta).0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dielectric_normal_incidence_and_tir() {
        let (r, cos_t, eta_it, _) = fresnel_dielectric(1.0, 1.5);
        assert!((r - 0.04).abs() < 1e-6);
        assert!((cos_t + 1.0).abs() < 1e-6);
        assert_eq!(eta_it, 1.5);
        // From inside beyond the critical angle asin(1/1.5) = 41.8 degrees.
        let (r, cos_t, _, _) = fresnel_dielectric(-(50f32.to_radians().cos()), 1.5);
        assert_eq!(r, 1.0);
        assert_eq!(cos_t, 0.0);
        assert_eq!(fresnel_dielectric(0.3, 1.0).0, 0.0);
    }

    #[test]
    fn conductor_reduces_to_dielectric_when_k_is_zero() {
        for i in 0..=20 {
            let c = i as f32 / 20.0;
            let a = fresnel_conductor_1(c, 1.5, 0.0);
            let b = fresnel_dielectric(c, 1.5).0;
            assert!((a - b).abs() < 1e-5, "cos {c}: {a} vs {b}");
        }
        // Gold-like values stay in [0, 1] and reach 1 at grazing.
        let f = fresnel_conductor(0.0, Vec3::new(0.2, 0.4, 1.4), Vec3::new(3.6, 2.4, 1.8));
        assert!((f - Vec3::ONE).abs().max_element() < 1e-5);
    }

    #[test]
    fn ior_f0_round_trip() {
        for eta in [1.0f32, 1.33, 1.5, 2.4] {
            assert!((ior_from_f0(f0_from_ior(eta)) - eta).abs() < 1e-4);
        }
    }
}
