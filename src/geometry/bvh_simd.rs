//! Four-lane slab tests for the wide BVH ([`super::bvh_wide`]).
//!
//! Each lane computes exactly what the scalar box test of [`super::bvh`] computes, operation
//! for operation, so a lane's entry distance and hit decision are bit-identical to the scalar
//! test of the same box:
//!
//! | step | scalar | lanes |
//! |------|--------|-------|
//! | slab distances | `(p − o) · (1/d)` per axis | `subps`, `mulps` |
//! | entry | `max(tx, max(ty, max(tz, 0)))`, a NaN first operand ignored | `maxps` (returns the second operand when unordered) |
//! | exit | `min(tx, min(ty, min(tz, t_max)))`, likewise | `minps` |
//! | hit | `entry ≤ exit · (1 + 2γ₃)`, an infinite entry counting as a miss | `cmpleps` against `min(f32::MAX, exit · (1 + 2γ₃))`, `movmskps` |
//!
//! On x86-64 the lanes are SSE2 registers (SSE2 is part of the x86-64 baseline, so no
//! run-time detection is needed); elsewhere a scalar loop over four `f32` with the same
//! semantics stands in.

use super::bvh::{BoxRay, ROBUST_SCALE};

#[cfg(target_arch = "x86_64")]
mod imp {
    use std::arch::x86_64::*;

    /// Four `f32` lanes.
    #[derive(Clone, Copy, Debug)]
    pub struct F4(__m128);

    // SAFETY (all functions below): SSE2 is enabled on every x86-64 target, and the only
    // memory access is an unaligned load from a `&[f32; 4]`.
    impl F4 {
        #[inline(always)]
        pub fn splat(v: f32) -> F4 {
            unsafe { F4(_mm_set1_ps(v)) }
        }
        #[inline(always)]
        pub fn load(a: &[f32; 4]) -> F4 {
            unsafe { F4(_mm_loadu_ps(a.as_ptr())) }
        }
        #[inline(always)]
        pub fn sub(self, o: F4) -> F4 {
            unsafe { F4(_mm_sub_ps(self.0, o.0)) }
        }
        #[inline(always)]
        pub fn mul(self, o: F4) -> F4 {
            unsafe { F4(_mm_mul_ps(self.0, o.0)) }
        }
        /// Per lane `if a < b { a } else { b }`.
        #[inline(always)]
        pub fn min(self, o: F4) -> F4 {
            unsafe { F4(_mm_min_ps(self.0, o.0)) }
        }
        /// Per lane `if a > b { a } else { b }`.
        #[inline(always)]
        pub fn max(self, o: F4) -> F4 {
            unsafe { F4(_mm_max_ps(self.0, o.0)) }
        }
        /// Bit `i` set when lane `i` of `self` ≤ lane `i` of `o`.
        #[inline(always)]
        pub fn le_mask(self, o: F4) -> u32 {
            unsafe { _mm_movemask_ps(_mm_cmple_ps(self.0, o.0)) as u32 }
        }
        /// Lanes `[a0, a2, a0, a2]` and `[a1, a3, a1, a3]`.
        #[inline(always)]
        pub fn even_odd(self) -> (F4, F4) {
            unsafe {
                (
                    F4(_mm_shuffle_ps::<0b10_00_10_00>(self.0, self.0)),
                    F4(_mm_shuffle_ps::<0b11_01_11_01>(self.0, self.0)),
                )
            }
        }
        #[inline(always)]
        pub fn to_array(self) -> [f32; 4] {
            let mut out = [0.0f32; 4];
            unsafe { _mm_storeu_ps(out.as_mut_ptr(), self.0) };
            out
        }
    }
}

#[cfg(not(target_arch = "x86_64"))]
mod imp {
    /// Four `f32` lanes (portable fallback with the SSE semantics of min and max).
    #[derive(Clone, Copy, Debug)]
    pub struct F4([f32; 4]);

    impl F4 {
        #[inline(always)]
        pub fn splat(v: f32) -> F4 {
            F4([v; 4])
        }
        #[inline(always)]
        pub fn load(a: &[f32; 4]) -> F4 {
            F4(*a)
        }
        #[inline(always)]
        fn zip(self, o: F4, f: impl Fn(f32, f32) -> f32) -> F4 {
            F4(std::array::from_fn(|i| f(self.0[i], o.0[i])))
        }
        #[inline(always)]
        pub fn sub(self, o: F4) -> F4 {
            self.zip(o, |a, b| a - b)
        }
        #[inline(always)]
        pub fn mul(self, o: F4) -> F4 {
            self.zip(o, |a, b| a * b)
        }
        #[inline(always)]
        pub fn min(self, o: F4) -> F4 {
            self.zip(o, |a, b| if a < b { a } else { b })
        }
        #[inline(always)]
        pub fn max(self, o: F4) -> F4 {
            self.zip(o, |a, b| if a > b { a } else { b })
        }
        #[inline(always)]
        pub fn le_mask(self, o: F4) -> u32 {
            (0..4).fold(0, |m, i| m | (((self.0[i] <= o.0[i]) as u32) << i))
        }
        #[inline(always)]
        pub fn even_odd(self) -> (F4, F4) {
            let a = self.0;
            (F4([a[0], a[2], a[0], a[2]]), F4([a[1], a[3], a[1], a[3]]))
        }
        #[inline(always)]
        pub fn to_array(self) -> [f32; 4] {
            self.0
        }
    }
}

pub(crate) use imp::F4;

/// Per-ray constants of the four-lane test: the origin and `1/d` broadcast, and for each
/// axis which of a node's coordinate rows (`0..3` minima, `3..6` maxima) holds the near
/// and the far plane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct WideRay {
    o: [F4; 3],
    inv: [F4; 3],
    near: [usize; 3],
    far: [usize; 3],
}

impl WideRay {
    #[inline(always)]
    pub(crate) fn new(r: &BoxRay) -> Self {
        let n = |a: usize| if r.neg[a] { a + 3 } else { a };
        let f = |a: usize| if r.neg[a] { a } else { a + 3 };
        WideRay {
            o: [F4::splat(r.o.x), F4::splat(r.o.y), F4::splat(r.o.z)],
            inv: [
                F4::splat(r.inv_d.x),
                F4::splat(r.inv_d.y),
                F4::splat(r.inv_d.z),
            ],
            near: [n(0), n(1), n(2)],
            far: [f(0), f(1), f(2)],
        }
    }

    /// Slab test of four boxes given as coordinate rows (`b[0..3]` minima in x, y, z,
    /// `b[3..6]` maxima). Returns the entry distances and the mask of boxes hit below `t_max`.
    #[inline(always)]
    pub(crate) fn test(&self, b: &[F4; 6], t_max: f32) -> (F4, u32) {
        let t0x = b[self.near[0]].sub(self.o[0]).mul(self.inv[0]);
        let t0y = b[self.near[1]].sub(self.o[1]).mul(self.inv[1]);
        let t0z = b[self.near[2]].sub(self.o[2]).mul(self.inv[2]);
        let t1x = b[self.far[0]].sub(self.o[0]).mul(self.inv[0]);
        let t1y = b[self.far[1]].sub(self.o[1]).mul(self.inv[1]);
        let t1z = b[self.far[2]].sub(self.o[2]).mul(self.inv[2]);
        let t0 = t0x.max(t0y.max(t0z.max(F4::splat(0.0))));
        let t1 = t1x.min(t1y.min(t1z.min(F4::splat(t_max))));
        // The scalar test reports an infinite entry distance as a miss: compare against
        // `min(f32::MAX, exit · scale)` (a NaN exit stays NaN and misses too).
        let bound = F4::splat(f32::MAX).min(t1.mul(F4::splat(ROBUST_SCALE)));
        (t0, t0.le_mask(bound))
    }
}

/// Loads the six coordinate rows of a node's four boxes.
#[inline(always)]
pub(crate) fn rows(b: &[[f32; 4]; 6]) -> [F4; 6] {
    [
        F4::load(&b[0]),
        F4::load(&b[1]),
        F4::load(&b[2]),
        F4::load(&b[3]),
        F4::load(&b[4]),
        F4::load(&b[5]),
    ]
}

/// The unions of boxes 0 and 1 and of boxes 2 and 3, in lanes `[01, 23, 01, 23]`.
#[inline(always)]
pub(crate) fn pair_unions(b: &[F4; 6]) -> [F4; 6] {
    let lo = |v: F4| {
        let (e, o) = v.even_odd();
        e.min(o)
    };
    let hi = |v: F4| {
        let (e, o) = v.even_odd();
        e.max(o)
    };
    [lo(b[0]), lo(b[1]), lo(b[2]), hi(b[3]), hi(b[4]), hi(b[5])]
}

/// Hints the cache to load the elements `first..first + count` of `items` (at most four
/// cache lines; a no-op when out of range or not on x86-64).
#[inline(always)]
pub(crate) fn prefetch<T>(items: &[T], first: usize, count: usize) {
    #[cfg(target_arch = "x86_64")]
    if let Some(range) = items.get(first..first + count) {
        let bytes = std::mem::size_of_val(range).min(256);
        let p = range.as_ptr() as *const i8;
        for off in (0..bytes).step_by(64) {
            // SAFETY: prefetching is a hint without memory effects, and the address lies
            // within `range`.
            unsafe {
                use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
                _mm_prefetch::<_MM_HINT_T0>(p.add(off));
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (items, first, count);
}
