//! Perlin gradient noise in 1 to 4 dimensions, with Cycles' gradient sets,
//! quintic fade, output scaling and period.
//!
//! The `snoise_*` functions are signed (roughly `[-1, 1]`), the `noise_*`
//! functions are remapped to roughly `[0, 1]`.  Every axis repeats with a
//! period of 100 000 (coordinates are reduced with `fmod`) to keep the lattice
//! arithmetic precise; non-finite coordinates give non-finite or arbitrary
//! values but never panic.

use super::hash::{hash_uint, hash_uint2, hash_uint3, hash_uint4};
use glam::{Vec2, Vec3, Vec4};

/// Period of the noise on every axis.
const PERIOD: f32 = 100_000.0;

/// Output scale factors that bring each dimension's Perlin noise to about
/// `[-1, 1]` (determined experimentally by the Open Shading Language authors).
const SCALE_1D: f32 = 0.2500;
const SCALE_2D: f32 = 0.6616;
const SCALE_3D: f32 = 0.9820;
const SCALE_4D: f32 = 0.8344;

#[inline]
fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

#[inline]
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    (1.0 - t) * a + t * b
}

/// Integer lattice cell (as the wrapped `u32` the hashes take) and the
/// fractional position inside it.
#[inline]
fn floor_frac(x: f32) -> (u32, f32) {
    let f = x.floor();
    (f as i32 as u32, x - f)
}

#[inline]
fn negate_if(v: f32, cond: u32) -> f32 {
    if cond != 0 {
        -v
    } else {
        v
    }
}

#[inline]
fn grad1(hash: u32, x: f32) -> f32 {
    let h = hash & 15;
    let g = (1 + (h & 7)) as f32;
    negate_if(g, h & 8) * x
}

#[inline]
fn grad2(hash: u32, x: f32, y: f32) -> f32 {
    let h = hash & 7;
    let (u, v) = if h < 4 { (x, y) } else { (y, x) };
    negate_if(u, h & 1) + negate_if(2.0 * v, h & 2)
}

#[inline]
fn grad3(hash: u32, x: f32, y: f32, z: f32) -> f32 {
    let h = hash & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    negate_if(u, h & 1) + negate_if(v, h & 2)
}

#[inline]
fn grad4(hash: u32, x: f32, y: f32, z: f32, w: f32) -> f32 {
    let h = hash & 31;
    let u = if h < 24 { x } else { y };
    let v = if h < 16 { y } else { z };
    let s = if h < 8 { z } else { w };
    negate_if(u, h & 1) + negate_if(v, h & 2) + negate_if(s, h & 4)
}

/// Unscaled 1D Perlin noise.
pub fn perlin_1d(x: f32) -> f32 {
    let (xi, fx) = floor_frac(x);
    let u = fade(fx);
    let a = grad1(hash_uint(xi), fx);
    let b = grad1(hash_uint(xi.wrapping_add(1)), fx - 1.0);
    a + u * (b - a)
}

/// Unscaled 2D Perlin noise.
pub fn perlin_2d(x: f32, y: f32) -> f32 {
    let (xi, fx) = floor_frac(x);
    let (yi, fy) = floor_frac(y);
    let (u, v) = (fade(fx), fade(fy));
    let (x1, y1) = (xi.wrapping_add(1), yi.wrapping_add(1));
    let g = |hx, hy, dx: f32, dy: f32| grad2(hash_uint2(hx, hy), dx, dy);
    let bottom = lerp(g(xi, yi, fx, fy), g(x1, yi, fx - 1.0, fy), u);
    let top = lerp(g(xi, y1, fx, fy - 1.0), g(x1, y1, fx - 1.0, fy - 1.0), u);
    lerp(bottom, top, v)
}

/// Unscaled 3D Perlin noise.
pub fn perlin_3d(x: f32, y: f32, z: f32) -> f32 {
    let (xi, fx) = floor_frac(x);
    let (yi, fy) = floor_frac(y);
    let (zi, fz) = floor_frac(z);
    let (u, v, w) = (fade(fx), fade(fy), fade(fz));
    let corner = |dx: u32, dy: u32, dz: u32| {
        grad3(
            hash_uint3(
                xi.wrapping_add(dx),
                yi.wrapping_add(dy),
                zi.wrapping_add(dz),
            ),
            fx - dx as f32,
            fy - dy as f32,
            fz - dz as f32,
        )
    };
    let plane = |dz: u32| {
        let bottom = lerp(corner(0, 0, dz), corner(1, 0, dz), u);
        let top = lerp(corner(0, 1, dz), corner(1, 1, dz), u);
        lerp(bottom, top, v)
    };
    lerp(plane(0), plane(1), w)
}

/// Unscaled 4D Perlin noise.
pub fn perlin_4d(x: f32, y: f32, z: f32, w: f32) -> f32 {
    let (xi, fx) = floor_frac(x);
    let (yi, fy) = floor_frac(y);
    let (zi, fz) = floor_frac(z);
    let (wi, fw) = floor_frac(w);
    let (u, v, t, s) = (fade(fx), fade(fy), fade(fz), fade(fw));
    let corner = |dx: u32, dy: u32, dz: u32, dw: u32| {
        grad4(
            hash_uint4(
                xi.wrapping_add(dx),
                yi.wrapping_add(dy),
                zi.wrapping_add(dz),
                wi.wrapping_add(dw),
            ),
            fx - dx as f32,
            fy - dy as f32,
            fz - dz as f32,
            fw - dw as f32,
        )
    };
    let cube = |dw: u32| {
        let plane = |dz: u32| {
            let bottom = lerp(corner(0, 0, dz, dw), corner(1, 0, dz, dw), u);
            let top = lerp(corner(0, 1, dz, dw), corner(1, 1, dz, dw), u);
            lerp(bottom, top, v)
        };
        lerp(plane(0), plane(1), t)
    };
    let a = cube(0);
    a + s * (cube(1) - a)
}

/// Signed 1D noise, about `[-1, 1]`.
#[inline]
pub fn snoise_1d(p: f32) -> f32 {
    SCALE_1D * perlin_1d(p % PERIOD)
}

/// Signed 2D noise, about `[-1, 1]`.
#[inline]
pub fn snoise_2d(p: Vec2) -> f32 {
    SCALE_2D * perlin_2d(p.x % PERIOD, p.y % PERIOD)
}

/// Signed 3D noise, about `[-1, 1]`.
#[inline]
pub fn snoise_3d(p: Vec3) -> f32 {
    SCALE_3D * perlin_3d(p.x % PERIOD, p.y % PERIOD, p.z % PERIOD)
}

/// Signed 4D noise, about `[-1, 1]`.
#[inline]
pub fn snoise_4d(p: Vec4) -> f32 {
    SCALE_4D * perlin_4d(p.x % PERIOD, p.y % PERIOD, p.z % PERIOD, p.w % PERIOD)
}

/// Unsigned 1D noise, about `[0, 1]`.
#[inline]
pub fn noise_1d(p: f32) -> f32 {
    0.5 * snoise_1d(p) + 0.5
}

/// Unsigned 2D noise, about `[0, 1]`.
#[inline]
pub fn noise_2d(p: Vec2) -> f32 {
    0.5 * snoise_2d(p) + 0.5
}

/// Unsigned 3D noise, about `[0, 1]`.
#[inline]
pub fn noise_3d(p: Vec3) -> f32 {
    0.5 * snoise_3d(p) + 0.5
}

/// Unsigned 4D noise, about `[0, 1]`.
#[inline]
pub fn noise_4d(p: Vec4) -> f32 {
    0.5 * snoise_4d(p) + 0.5
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_on_lattice_points_and_finite_elsewhere() {
        // Gradient noise vanishes at integer lattice points.
        assert_eq!(snoise_3d(Vec3::new(1.0, -2.0, 3.0)), 0.0);
        assert_eq!(snoise_4d(Vec4::new(1.0, -2.0, 3.0, 7.0)), 0.0);
        for v in [f32::NAN, f32::INFINITY, -f32::INFINITY, 1e30] {
            let _ = snoise_1d(v);
            let _ = snoise_2d(Vec2::splat(v));
            let _ = snoise_3d(Vec3::splat(v));
            let _ = snoise_4d(Vec4::splat(v));
        }
        for i in 0..1000 {
            let p = Vec4::new(i as f32 * 0.37, i as f32 * -0.11, i as f32 * 0.05, 0.3);
            assert!(snoise_4d(p).abs() <= 1.5 && snoise_2d(p.truncate().truncate()).abs() <= 1.5);
        }
    }
}
