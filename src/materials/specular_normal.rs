//! The normal Cycles gives glossy closures under a bump or normal map.

use glam::Vec3;

/// The shading normal `n` bent towards the geometric normal `ng` just enough that the mirror
/// reflection of the view `wo` (unit, on the side of `ng`) leaves above the surface, at
/// least min(0.9 wo.ng, 0.01) above it; `n` itself when its reflection already does.
///
/// Cycles' `ensure_valid_specular_reflection`: the bent normal N' lies in the plane of `ng`
/// and `n`, and solves 2 (N'.wo) (N'.ng) - wo.ng = t. With x the unit tangent of `n`
/// across `ng`, N' = sqrt(1 - z^2) x + z ng, and z^2 is the root of
/// 4 a z^4 - 2 b z^2 + c = 0 (a = wo.x^2 + wo.ng^2, b = 2 (a + wo.ng t), c = (wo.ng + t)^2)
/// that solves the equation before squaring.
pub fn valid_specular_normal(ng: Vec3, wo: Vec3, n: Vec3) -> Vec3 {
    let r = 2.0 * n.dot(wo) * n - wo;
    let iz = wo.dot(ng);
    let t = (0.9 * iz).min(0.01);
    if ng.dot(r) >= t {
        return n;
    }
    let x = {
        let v = n - n.dot(ng) * ng;
        let l = v.length();
        if l > 0.0 && l.is_finite() {
            v / l
        } else {
            n
        }
    };
    let ix = wo.dot(x);
    let a = ix * ix + iz * iz;
    let b = 2.0 * (a + iz * t);
    let c = (t + iz) * (t + iz);
    if !(a > 0.0) {
        return n;
    }
    let disc = (b * b - 4.0 * a * c).max(0.0).sqrt();
    let nz2 = if ix < 0.0 {
        0.25 * (b + disc) / a
    } else {
        0.25 * (b - disc) / a
    };
    let nx = (1.0 - nz2).max(0.0).sqrt();
    let nz = nz2.max(0.0).sqrt();
    let out = nx * x + nz * ng;
    if out.is_finite() {
        out
    } else {
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reflect(n: Vec3, wo: Vec3) -> Vec3 {
        2.0 * n.dot(wo) * n - wo
    }

    #[test]
    fn a_valid_reflection_keeps_the_normal() {
        let ng = Vec3::Z;
        let n = Vec3::new(0.2, 0.0, 1.0).normalize();
        let wo = Vec3::new(0.0, 0.3, 1.0).normalize();
        assert_eq!(valid_specular_normal(ng, wo, n), n);
    }

    #[test]
    fn an_invalid_reflection_is_lifted_to_the_threshold() {
        let ng = Vec3::Z;
        // A normal tilted 60 degrees away from a grazing view reflects it below the surface.
        for (tilt, view) in [(1.0f32, 1.2f32), (0.8, 1.4), (1.3, 0.9), (0.6, 1.5)] {
            let n = Vec3::new(tilt.sin(), 0.0, tilt.cos());
            let wo = Vec3::new(-view.sin(), 0.0, view.cos());
            assert!(ng.dot(reflect(n, wo)) < 0.0);
            let m = valid_specular_normal(ng, wo, n);
            let t = (0.9 * wo.dot(ng)).min(0.01);
            assert!((m.length() - 1.0).abs() < 1e-5, "{m}");
            let rz = ng.dot(reflect(m, wo));
            assert!(
                (rz - t).abs() < 2e-4,
                "tilt {tilt} view {view}: R.z {rz}, wanted {t}"
            );
            // Bent towards ng, in the plane of n and ng.
            assert!(m.z > n.z && m.y.abs() < 1e-6 && m.x > 0.0);
        }
    }
}
