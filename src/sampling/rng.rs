//! PCG32 (O'Neill 2014), seeded from (seed, stream index) so that every tile or photon
//! batch has its own reproducible sequence whatever the thread count.

use glam::{Vec2, Vec3};

#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
    inc: u64,
}

const MULT: u64 = 6364136223846793005;

/// SplitMix64 finaliser: decorrelates nearby seeds and indices.
#[inline]
pub fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl Rng {
    /// Generator for stream `index` of the render seeded with `seed`.
    pub fn new(seed: u64, index: u64) -> Self {
        let init_state = mix64(seed ^ mix64(index.wrapping_mul(0xA24B_AED4_963E_E407)));
        let seq = mix64(index ^ 0x5851_F42D_4C95_7F2D) ^ seed.rotate_left(17);
        let mut rng = Rng {
            state: 0,
            inc: (seq << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(init_state);
        rng.next_u32();
        rng
    }

    /// The generator's state (to continue it elsewhere, e.g. a pixel's stream on another
    /// machine).
    pub fn to_parts(&self) -> (u64, u64) {
        (self.state, self.inc)
    }

    /// The generator of [`Rng::to_parts`].
    pub fn from_parts(state: u64, inc: u64) -> Self {
        Rng { state, inc }
    }

    /// Derives a child generator for sub-stream `index` (e.g. a pixel inside a tile).
    pub fn derive(seed: u64, a: u64, b: u64) -> Self {
        Self::new(seed, mix64(a) ^ b.wrapping_mul(0x9E37_79B9_7F4A_7C15))
    }

    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(MULT).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// Uniform in [0, 1).
    #[inline]
    pub fn f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }

    #[inline]
    pub fn vec2(&mut self) -> Vec2 {
        let a = self.f32();
        Vec2::new(a, self.f32())
    }

    #[inline]
    pub fn vec3(&mut self) -> Vec3 {
        let a = self.f32();
        let b = self.f32();
        Vec3::new(a, b, self.f32())
    }

    /// Uniform integer in [0, n).
    #[inline]
    pub fn below(&mut self, n: u32) -> u32 {
        ((self.next_u32() as u64 * n as u64) >> 32) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproducible_and_stream_distinct() {
        let a: Vec<u32> = (0..8)
            .scan(Rng::new(7, 3), |r, _| Some(r.next_u32()))
            .collect();
        let b: Vec<u32> = (0..8)
            .scan(Rng::new(7, 3), |r, _| Some(r.next_u32()))
            .collect();
        let c: Vec<u32> = (0..8)
            .scan(Rng::new(7, 4), |r, _| Some(r.next_u32()))
            .collect();
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn uniform_mean_and_range() {
        let mut r = Rng::new(1, 0);
        let n = 200_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let x = r.f32();
            assert!((0.0..1.0).contains(&x));
            sum += x as f64;
        }
        // Standard error of the mean is 1/sqrt(12 n) ~ 6.5e-4; allow 5 sigma.
        assert!((sum / n as f64 - 0.5).abs() < 5.0 * (1.0 / (12.0 * n as f64)).sqrt());
    }
}
