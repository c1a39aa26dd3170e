//! The hashes Cycles' procedural textures use.
//!
//! * Jenkins "lookup3": integer keys are hashed with the `final` (and for four
//!   keys, `mix`) steps of Bob Jenkins' lookup3, seeded with
//!   `0xdeadbeef + (n << 2) + 13` for `n` keys.  Float keys are hashed through
//!   their bit patterns, and hashes map to `[0, 1]` by multiplying with 2^-32.
//!   Used by Perlin noise, White Noise, 1D Voronoi and the noise seeds.
//! * PCG 2D/3D/4D (Jarzynski and Olano, "Hash Functions for GPU Rendering",
//!   JCGT 2020) restricted to signed arithmetic, mapping to `[0, 1]` by
//!   2^-31.  Used for the integer cells of 2D to 4D Voronoi.

use glam::{IVec2, IVec3, IVec4, Vec2, Vec3, Vec4};

#[inline]
fn seed(keys: u32) -> u32 {
    0xdead_beef_u32.wrapping_add(keys << 2).wrapping_add(13)
}

/// lookup3's `mix` step.
#[inline]
fn mix(a: &mut u32, b: &mut u32, c: &mut u32) {
    *a = a.wrapping_sub(*c);
    *a ^= c.rotate_left(4);
    *c = c.wrapping_add(*b);
    *b = b.wrapping_sub(*a);
    *b ^= a.rotate_left(6);
    *a = a.wrapping_add(*c);
    *c = c.wrapping_sub(*b);
    *c ^= b.rotate_left(8);
    *b = b.wrapping_add(*a);
    *a = a.wrapping_sub(*c);
    *a ^= c.rotate_left(16);
    *c = c.wrapping_add(*b);
    *b = b.wrapping_sub(*a);
    *b ^= a.rotate_left(19);
    *a = a.wrapping_add(*c);
    *c = c.wrapping_sub(*b);
    *c ^= b.rotate_left(4);
    *b = b.wrapping_add(*a);
}

/// lookup3's `final` step; returns `c`.
#[inline]
fn finish(mut a: u32, mut b: u32, mut c: u32) -> u32 {
    c ^= b;
    c = c.wrapping_sub(b.rotate_left(14));
    a ^= c;
    a = a.wrapping_sub(c.rotate_left(11));
    b ^= a;
    b = b.wrapping_sub(a.rotate_left(25));
    c ^= b;
    c = c.wrapping_sub(b.rotate_left(16));
    a ^= c;
    a = a.wrapping_sub(c.rotate_left(4));
    b ^= a;
    b = b.wrapping_sub(a.rotate_left(14));
    c ^= b;
    c.wrapping_sub(b.rotate_left(24))
}

/// Hash of one 32-bit key.
#[inline]
pub fn hash_uint(kx: u32) -> u32 {
    let s = seed(1);
    finish(s.wrapping_add(kx), s, s)
}

/// Hash of two 32-bit keys.
#[inline]
pub fn hash_uint2(kx: u32, ky: u32) -> u32 {
    let s = seed(2);
    finish(s.wrapping_add(kx), s.wrapping_add(ky), s)
}

/// Hash of three 32-bit keys.
#[inline]
pub fn hash_uint3(kx: u32, ky: u32, kz: u32) -> u32 {
    let s = seed(3);
    finish(s.wrapping_add(kx), s.wrapping_add(ky), s.wrapping_add(kz))
}

/// Hash of four 32-bit keys.
#[inline]
pub fn hash_uint4(kx: u32, ky: u32, kz: u32, kw: u32) -> u32 {
    let s = seed(4);
    let (mut a, mut b, mut c) = (s.wrapping_add(kx), s.wrapping_add(ky), s.wrapping_add(kz));
    mix(&mut a, &mut b, &mut c);
    finish(a.wrapping_add(kw), b, c)
}

/// `[0, u32::MAX]` to `[0, 1]`.
#[inline]
pub fn uint_to_float_incl(n: u32) -> f32 {
    // 1 / (float)0xFFFFFFFF is exactly 2^-32 in single precision.
    n as f32 * (1.0 / 4_294_967_296.0)
}

/// Hash of a float (its bit pattern) to `[0, 1]`.
#[inline]
pub fn hash_float_to_float(k: f32) -> f32 {
    uint_to_float_incl(hash_uint(k.to_bits()))
}

/// Hash of a 2D point to `[0, 1]`.
#[inline]
pub fn hash_vec2_to_float(k: Vec2) -> f32 {
    uint_to_float_incl(hash_uint2(k.x.to_bits(), k.y.to_bits()))
}

/// Hash of a 3D point to `[0, 1]`.
#[inline]
pub fn hash_vec3_to_float(k: Vec3) -> f32 {
    uint_to_float_incl(hash_uint3(k.x.to_bits(), k.y.to_bits(), k.z.to_bits()))
}

/// Hash of a 4D point to `[0, 1]`.
#[inline]
pub fn hash_vec4_to_float(k: Vec4) -> f32 {
    uint_to_float_incl(hash_uint4(
        k.x.to_bits(),
        k.y.to_bits(),
        k.z.to_bits(),
        k.w.to_bits(),
    ))
}

/// Two independent hashes of a 2D point, each in `[0, 1]`.
#[inline]
pub fn hash_vec2_to_vec2(k: Vec2) -> Vec2 {
    Vec2::new(hash_vec2_to_float(k), hash_vec3_to_float(k.extend(1.0)))
}

/// Three independent hashes of a 3D point, each in `[0, 1]`.
#[inline]
pub fn hash_vec3_to_vec3(k: Vec3) -> Vec3 {
    Vec3::new(
        hash_vec3_to_float(k),
        hash_vec4_to_float(k.extend(1.0)),
        hash_vec4_to_float(k.extend(2.0)),
    )
}

/// Four independent hashes of a 4D point (rotations of its components).
#[inline]
pub fn hash_vec4_to_vec4(k: Vec4) -> Vec4 {
    Vec4::new(
        hash_vec4_to_float(k),
        hash_vec4_to_float(Vec4::new(k.w, k.x, k.y, k.z)),
        hash_vec4_to_float(Vec4::new(k.z, k.w, k.x, k.y)),
        hash_vec4_to_float(Vec4::new(k.y, k.z, k.w, k.x)),
    )
}

/// A colour (three hashes in `[0, 1]`) from a float.
#[inline]
pub fn hash_float_to_vec3(k: f32) -> Vec3 {
    Vec3::new(
        hash_float_to_float(k),
        hash_vec2_to_float(Vec2::new(k, 1.0)),
        hash_vec2_to_float(Vec2::new(k, 2.0)),
    )
}

/// A colour (three hashes in `[0, 1]`) from a 2D point.
#[inline]
pub fn hash_vec2_to_vec3(k: Vec2) -> Vec3 {
    Vec3::new(
        hash_vec2_to_float(k),
        hash_vec3_to_float(k.extend(1.0)),
        hash_vec3_to_float(k.extend(2.0)),
    )
}

/// A colour (three hashes in `[0, 1]`) from a 4D point.
#[inline]
pub fn hash_vec4_to_vec3(k: Vec4) -> Vec3 {
    Vec3::new(
        hash_vec4_to_float(k),
        hash_vec4_to_float(Vec4::new(k.z, k.x, k.w, k.y)),
        hash_vec4_to_float(Vec4::new(k.w, k.z, k.y, k.x)),
    )
}

const PCG_MUL: i32 = 1_664_525;
const PCG_ADD: i32 = 1_013_904_223;
/// 1 / 2^31, as `1.0f / (float)0x7FFFFFFF` rounds to.
const PCG_TO_FLOAT: f32 = 1.0 / 2_147_483_648.0;

#[inline]
fn pcg_start(v: i32) -> i32 {
    v.wrapping_mul(PCG_MUL).wrapping_add(PCG_ADD)
}

/// PCG hash of two integers; components in `[0, 2^31)`.
pub fn hash_pcg2d(v: IVec2) -> IVec2 {
    let (mut x, mut y) = (pcg_start(v.x), pcg_start(v.y));
    x = x.wrapping_add(y.wrapping_mul(PCG_MUL));
    y = y.wrapping_add(x.wrapping_mul(PCG_MUL));
    x ^= x >> 16;
    y ^= y >> 16;
    x = x.wrapping_add(y.wrapping_mul(PCG_MUL));
    y = y.wrapping_add(x.wrapping_mul(PCG_MUL));
    IVec2::new(x & 0x7FFF_FFFF, y & 0x7FFF_FFFF)
}

/// PCG hash of three integers; components in `[0, 2^31)`.
pub fn hash_pcg3d(v: IVec3) -> IVec3 {
    let (mut x, mut y, mut z) = (pcg_start(v.x), pcg_start(v.y), pcg_start(v.z));
    for round in 0..2 {
        x = x.wrapping_add(y.wrapping_mul(z));
        y = y.wrapping_add(z.wrapping_mul(x));
        z = z.wrapping_add(x.wrapping_mul(y));
        if round == 0 {
            x ^= x >> 16;
            y ^= y >> 16;
            z ^= z >> 16;
        }
    }
    IVec3::new(x & 0x7FFF_FFFF, y & 0x7FFF_FFFF, z & 0x7FFF_FFFF)
}

/// PCG hash of four integers; components in `[0, 2^31)`.
pub fn hash_pcg4d(v: IVec4) -> IVec4 {
    let (mut x, mut y, mut z, mut w) = (
        pcg_start(v.x),
        pcg_start(v.y),
        pcg_start(v.z),
        pcg_start(v.w),
    );
    for round in 0..2 {
        x = x.wrapping_add(y.wrapping_mul(w));
        y = y.wrapping_add(z.wrapping_mul(x));
        z = z.wrapping_add(x.wrapping_mul(y));
        w = w.wrapping_add(y.wrapping_mul(z));
        if round == 0 {
            x ^= x >> 16;
            y ^= y >> 16;
            z ^= z >> 16;
            w ^= w >> 16;
        }
    }
    IVec4::new(
        x & 0x7FFF_FFFF,
        y & 0x7FFF_FFFF,
        z & 0x7FFF_FFFF,
        w & 0x7FFF_FFFF,
    )
}

/// Two hashes in `[0, 1]` of an integer 2D cell.
#[inline]
pub fn hash_ivec2_to_vec2(k: IVec2) -> Vec2 {
    hash_pcg2d(k).as_vec2() * PCG_TO_FLOAT
}

/// Three hashes in `[0, 1]` of an integer 3D cell.
#[inline]
pub fn hash_ivec3_to_vec3(k: IVec3) -> Vec3 {
    hash_pcg3d(k).as_vec3() * PCG_TO_FLOAT
}

/// Four hashes in `[0, 1]` of an integer 4D cell.
#[inline]
pub fn hash_ivec4_to_vec4(k: IVec4) -> Vec4 {
    hash_pcg4d(k).as_vec4() * PCG_TO_FLOAT
}

/// A colour from an integer 2D cell (the 3D hash of `(x, y, 0)`).
#[inline]
pub fn hash_ivec2_to_vec3(k: IVec2) -> Vec3 {
    hash_ivec3_to_vec3(k.extend(0))
}

/// A colour from an integer 4D cell (the first three of its four hashes).
#[inline]
pub fn hash_ivec4_to_vec3(k: IVec4) -> Vec3 {
    hash_ivec4_to_vec4(k).truncate()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hashes_are_total() {
        // Values are checked against Blender through the White Noise node,
        // which is nothing but the lookup3 hashes (see white_noise.rs), and
        // the PCG hashes through 2D to 4D Voronoi (voronoi.rs).
        assert_eq!(seed(1), 0xdead_beef + 4 + 13);
        assert_ne!(hash_uint(0), hash_uint(1));
        assert_ne!(hash_uint2(1, 0), hash_uint2(0, 1));
        assert!(hash_float_to_float(f32::NAN).is_finite());
        let h = hash_vec4_to_vec4(Vec4::splat(f32::INFINITY));
        assert!(h.is_finite() && h.min_element() >= 0.0 && h.max_element() <= 1.0);
        let h = hash_ivec4_to_vec4(IVec4::new(i32::MIN, i32::MAX, -1, 0));
        assert!(h.min_element() >= 0.0 && h.max_element() <= 1.0);
    }
}
