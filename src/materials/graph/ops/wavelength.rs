//! The Wavelength node.
//!
//! | parameter | meaning |
//! | --- | --- |
//! | `wavelength` | Wavelength input, in nanometres |
//!
//! Output: linear Rec.709 colour: the CIE 1931 colour-matching functions
//! tabulated every 5 nm from 380 nm (linear interpolation, black outside
//! [380, 780) nm), converted with Cycles' XYZ → scene-linear matrix, scaled by
//! 1/2.52 and clamped to non-negative values.

use super::math::{float_to_int, max_c};
use glam::{Mat3, Vec3};

/// CIE 1931 2° colour-matching functions x̄, ȳ, z̄ from 380 nm in 5 nm steps
/// (81 rows), as Cycles tabulates them.
const CIE_COLOR_MATCH: [[f32; 3]; 81] = [
    [0.0014, 0.0000, 0.0065],
    [0.0022, 0.0001, 0.0105],
    [0.0042, 0.0001, 0.0201],
    [0.0076, 0.0002, 0.0362],
    [0.0143, 0.0004, 0.0679],
    [0.0232, 0.0006, 0.1102],
    [0.0435, 0.0012, 0.2074],
    [0.0776, 0.0022, 0.3713],
    [0.1344, 0.0040, 0.6456],
    [0.2148, 0.0073, 1.0391],
    [0.2839, 0.0116, 1.3856],
    [0.3285, 0.0168, 1.6230],
    [0.3483, 0.0230, 1.7471],
    [0.3481, 0.0298, 1.7826],
    [0.3362, 0.0380, 1.7721],
    [0.3187, 0.0480, 1.7441],
    [0.2908, 0.0600, 1.6692],
    [0.2511, 0.0739, 1.5281],
    [0.1954, 0.0910, 1.2876],
    [0.1421, 0.1126, 1.0419],
    [0.0956, 0.1390, 0.8130],
    [0.0580, 0.1693, 0.6162],
    [0.0320, 0.2080, 0.4652],
    [0.0147, 0.2586, 0.3533],
    [0.0049, 0.3230, 0.2720],
    [0.0024, 0.4073, 0.2123],
    [0.0093, 0.5030, 0.1582],
    [0.0291, 0.6082, 0.1117],
    [0.0633, 0.7100, 0.0782],
    [0.1096, 0.7932, 0.0573],
    [0.1655, 0.8620, 0.0422],
    [0.2257, 0.9149, 0.0298],
    [0.2904, 0.9540, 0.0203],
    [0.3597, 0.9803, 0.0134],
    [0.4334, 0.9950, 0.0087],
    [0.5121, 1.0000, 0.0057],
    [0.5945, 0.9950, 0.0039],
    [0.6784, 0.9786, 0.0027],
    [0.7621, 0.9520, 0.0021],
    [0.8425, 0.9154, 0.0018],
    [0.9163, 0.8700, 0.0017],
    [0.9786, 0.8163, 0.0014],
    [1.0263, 0.7570, 0.0011],
    [1.0567, 0.6949, 0.0010],
    [1.0622, 0.6310, 0.0008],
    [1.0456, 0.5668, 0.0006],
    [1.0026, 0.5030, 0.0003],
    [0.9384, 0.4412, 0.0002],
    [0.8544, 0.3810, 0.0002],
    [0.7514, 0.3210, 0.0001],
    [0.6424, 0.2650, 0.0000],
    [0.5419, 0.2170, 0.0000],
    [0.4479, 0.1750, 0.0000],
    [0.3608, 0.1382, 0.0000],
    [0.2835, 0.1070, 0.0000],
    [0.2187, 0.0816, 0.0000],
    [0.1649, 0.0610, 0.0000],
    [0.1212, 0.0446, 0.0000],
    [0.0874, 0.0320, 0.0000],
    [0.0636, 0.0232, 0.0000],
    [0.0468, 0.0170, 0.0000],
    [0.0329, 0.0119, 0.0000],
    [0.0227, 0.0082, 0.0000],
    [0.0158, 0.0057, 0.0000],
    [0.0114, 0.0041, 0.0000],
    [0.0081, 0.0029, 0.0000],
    [0.0058, 0.0021, 0.0000],
    [0.0041, 0.0015, 0.0000],
    [0.0029, 0.0010, 0.0000],
    [0.0020, 0.0007, 0.0000],
    [0.0014, 0.0005, 0.0000],
    [0.0010, 0.0004, 0.0000],
    [0.0007, 0.0002, 0.0000],
    [0.0005, 0.0002, 0.0000],
    [0.0003, 0.0001, 0.0000],
    [0.0002, 0.0001, 0.0000],
    [0.0002, 0.0001, 0.0000],
    [0.0001, 0.0000, 0.0000],
    [0.0001, 0.0000, 0.0000],
    [0.0001, 0.0000, 0.0000],
    [0.0000, 0.0000, 0.0000],
];

/// XYZ (D65) → linear Rec.709 as Cycles derives it in Blender 5.0 from the
/// OpenColorIO config (`aces_interchange` role and the ACES AP0 → XYZ D65
/// Bradford matrix); rows are R, G, B.
const XYZ_TO_REC709_ROWS: [[f32; 3]; 3] = [
    [3.240_970_1, -1.537_384_5, -0.498_611_45],
    [-0.969_243_5, 1.875_967, 0.041_554_69],
    [0.055_629_88, -0.203_976_5, 1.056_971_2],
];

/// The XYZ → linear Rec.709 matrix the Wavelength node uses.
pub fn xyz_to_rec709() -> Mat3 {
    Mat3::from_cols_array_2d(&XYZ_TO_REC709_ROWS).transpose()
}

fn xyz_to_rgb(xyz: Vec3) -> Vec3 {
    let row = |r: [f32; 3]| r[0] * xyz.x + r[1] * xyz.y + r[2] * xyz.z;
    Vec3::new(
        row(XYZ_TO_REC709_ROWS[0]),
        row(XYZ_TO_REC709_ROWS[1]),
        row(XYZ_TO_REC709_ROWS[2]),
    )
}

/// CIE XYZ of a wavelength, as Cycles interpolates its table.
fn wavelength_xyz(lambda_nm: f32) -> Vec3 {
    let ii = (lambda_nm - 380.0) * (1.0 / 5.0);
    let i = float_to_int(ii);
    if !(0..80).contains(&i) {
        return Vec3::ZERO;
    }
    let i = i as usize;
    let t = ii - i as f32;
    let c0 = Vec3::from_array(CIE_COLOR_MATCH[i]);
    let c1 = Vec3::from_array(CIE_COLOR_MATCH[i + 1]);
    c0 + t * (c1 - c0)
}

/// The Wavelength node: nanometres to linear Rec.709 RGB.
pub fn wavelength(lambda_nm: f32) -> Vec3 {
    let c = xyz_to_rgb(wavelength_xyz(lambda_nm)) * (1.0 / 2.52);
    Vec3::new(max_c(c.x, 0.0), max_c(c.y, 0.0), max_c(c.z, 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::graph::ops::testutil::*;

    #[test]
    fn matches_cycles() {
        let data = parse(include_str!("testdata/wavelength.json"));
        let nm = floats(&data["wavelength"]);
        let mut bad = Vec::new();
        for (i, r) in vec3s(&data["color"]).into_iter().enumerate() {
            let ours = wavelength(nm[i]);
            if !close3(ours, r) {
                bad.push(format!("{} nm: {ours} vs {r:?}", nm[i]));
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
    fn matrix_rows() {
        let m = xyz_to_rec709();
        let v = Vec3::new(0.3, 0.5, 0.2);
        assert!((m * v - xyz_to_rgb(v)).abs().max_element() < 1e-6);
    }

    #[test]
    fn non_finite_inputs_do_not_panic() {
        for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e30, -1e30] {
            let _ = wavelength(x);
        }
    }
}
