//! The Sobol (0,2)-sequence in 32-bit fixed point, and fixed point to [0, 1).

/// Point `i` of the Sobol (0,2)-sequence in 32-bit fixed point: the first coordinate is the
/// van der Corput radical inverse, the second uses the Pascal-matrix generator.
pub fn sobol02(i: u32) -> (u32, u32) {
    let x = i.reverse_bits();
    let mut y = 0u32;
    let mut v = 1u32 << 31;
    let mut i = i;
    while i != 0 {
        if i & 1 != 0 {
            y ^= v;
        }
        i >>= 1;
        v ^= v >> 1;
    }
    (x, y)
}

/// Fixed point to [0, 1).
#[inline]
pub fn to_unit(v: u32) -> f32 {
    ((v >> 8) as f32) * (1.0 / (1u32 << 24) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sobol_prefixes_are_stratified() {
        // Every power-of-two prefix of length 2^m puts one point in each elementary
        // interval of area 2^-m, e.g. in each cell of the 2^a x 2^(m-a) grid.
        for m in 0..=8u32 {
            let n = 1u32 << m;
            for a in 0..=m {
                let mut seen = vec![false; n as usize];
                for i in 0..n {
                    let (x, y) = sobol02(i);
                    let cx = if a == 0 { 0 } else { x >> (32 - a) };
                    let cy = if m - a == 0 { 0 } else { y >> (32 - (m - a)) };
                    let cell = (cx << (m - a)) | cy;
                    assert!(!seen[cell as usize], "m={m} a={a} i={i}");
                    seen[cell as usize] = true;
                }
            }
        }
    }
}
