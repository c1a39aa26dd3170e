//! The Blackbody node.
//!
//! | parameter | meaning |
//! | --- | --- |
//! | `temperature` | Temperature input, in kelvin |
//!
//! Output: linear Rec.709 colour, Cycles' piecewise fit of the Planckian locus
//! (normalised so that the luminance stays near 1 over the range, as Cycles
//! does), constant below 800 K and from 12000 K on, negative components
//! clamped to zero. The scene-linear space is Rec.709, so Cycles'
//! `rec709_to_rgb` is the identity.

use super::math::max_c;
use glam::Vec3;

// The fit coefficients are written with Cycles' digits; f32 rounds them as
// Cycles' compiler does.

#[allow(clippy::excessive_precision)]
const TABLE_R: [[f32; 3]; 7] = [
    [1.619_191_06e3, -2.050_109_16e-3, 5.029_957_57],
    [2.488_454_71e3, -1.113_309_07e-3, 3.226_215_44],
    [3.341_431_93e3, -4.865_511_92e-4, 1.764_867_69],
    [4.094_617_42e3, -1.274_465_82e-4, 7.257_316_35e-1],
    [4.670_280_36e3, 2.912_581_99e-5, 1.267_034_42e-1],
    [4.595_091_85e3, 2.874_956_49e-5, 1.503_450_20e-1],
    [3.787_174_50e3, 9.359_078_26e-6, 3.990_758_71e-1],
];

#[allow(clippy::excessive_precision)]
const TABLE_G: [[f32; 3]; 7] = [
    [-4.889_997_48e2, 6.043_307_54e-4, -7.558_075_26e-2],
    [-7.559_942_77e2, 3.167_300_98e-4, 4.783_061_39e-1],
    [-1.023_639_77e3, 1.202_234_70e-4, 9.366_623_19e-1],
    [-1.265_713_16e3, 4.873_408_96e-6, 1.270_544_98],
    [-1.425_293_32e3, -4.011_504_31e-5, 1.439_727_84],
    [-1.175_548_22e3, -2.163_780_48e-5, 1.304_080_23],
    [-5.007_995_71e2, -4.598_320_26e-6, 1.090_987_63],
];

#[allow(clippy::excessive_precision)]
const TABLE_B: [[f32; 4]; 7] = [
    [
        5.969_453_09e-11,
        -4.857_428_87e-8,
        -9.706_222_47e-5,
        -4.079_361_48e-3,
    ],
    [
        2.404_303_66e-11,
        5.550_210_75e-8,
        -1.985_037_12e-4,
        2.893_128_58e-2,
    ],
    [
        -1.409_497_32e-11,
        1.898_789_68e-7,
        -3.566_328_24e-4,
        9.107_677_78e-2,
    ],
    [
        -3.614_608_68e-11,
        2.848_220_09e-7,
        -4.932_113_19e-4,
        1.567_234_40e-1,
    ],
    [
        -1.970_757_38e-11,
        1.753_593_52e-7,
        -2.505_428_25e-4,
        -2.227_832_66e-2,
    ],
    [
        -1.619_979_57e-13,
        -1.642_160_08e-8,
        3.862_162_71e-4,
        -7.380_774_18e-1,
    ],
    [
        6.726_502_83e-13,
        -2.730_788_09e-8,
        4.240_982_64e-4,
        -7.523_356_91e-1,
    ],
];

/// Cycles' fit before clamping (`svm_math_blackbody_color_rec709`).
#[allow(clippy::excessive_precision)]
fn blackbody_unclamped(t: f32) -> Vec3 {
    if t >= 12000.0 {
        return Vec3::new(0.826_295_5, 0.994_508_05, 1.566_307_7);
    }
    if t < 800.0 {
        return Vec3::new(5.413_294_5, -0.203_193_9, -0.082_253_52);
    }
    let i = if t >= 6365.0 {
        6
    } else if t >= 3315.0 {
        5
    } else if t >= 1902.0 {
        4
    } else if t >= 1449.0 {
        3
    } else if t >= 1167.0 {
        2
    } else if t >= 965.0 {
        1
    } else {
        0
    };
    let (r, g, b) = (TABLE_R[i], TABLE_G[i], TABLE_B[i]);
    let t_inv = 1.0 / t;
    Vec3::new(
        r[0] * t_inv + r[1] * t + r[2],
        g[0] * t_inv + g[1] * t + g[2],
        ((b[0] * t + b[1]) * t + b[2]) * t + b[3],
    )
}

/// The Blackbody node: temperature (K) to linear Rec.709 RGB.
///
/// NaN falls through every comparison into the coldest segment and comes out
/// NaN-free only if Cycles' would; it never panics.
pub fn blackbody(temperature: f32) -> Vec3 {
    let c = blackbody_unclamped(temperature);
    Vec3::new(max_c(c.x, 0.0), max_c(c.y, 0.0), max_c(c.z, 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::graph::ops::testutil::*;

    #[test]
    fn matches_cycles() {
        let data = parse(include_str!("testdata/blackbody.json"));
        let t = floats(&data["temperature"]);
        let mut bad = Vec::new();
        for (i, r) in vec3s(&data["color"]).into_iter().enumerate() {
            let ours = blackbody(t[i]);
            if !close3(ours, r) {
                bad.push(format!("{} K: {ours} vs {r:?}", t[i]));
            }
        }
        assert!(
            bad.is_empty(),
            "{} mismatches:\n{}",
            bad.len(),
            bad.join("\n")
        );
    }

    #[test]
    fn non_finite_inputs_do_not_panic() {
        for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let _ = blackbody(x);
        }
    }
}
