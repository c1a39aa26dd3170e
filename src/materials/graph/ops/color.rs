//! Colour nodes and Cycles' colour-model conversions.
//!
//! | node | function | parameters |
//! | --- | --- | --- |
//! | Hue/Saturation/Value | [`hue_saturation_value`] | `hue` (0.5 = unchanged, wraps), `saturation` and `value` (multipliers), `fac`, `color` |
//! | Brightness/Contrast | [`bright_contrast`] | `color`, `bright` (offset), `contrast` |
//! | Gamma | [`gamma`] | `color`, `gamma` (exponent; 0 gives white) |
//! | Invert | [`invert`] | `fac`, `color` |
//! | RGB to BW | [`rgb_to_bw`] | `color` |
//! | Separate Color | [`separate_color`] | [`ColorMode`] (RNA `mode`), `color` |
//! | Combine Color | [`combine_color`] | [`ColorMode`], the three components as a `Vec3` |
//!
//! The conversions are Cycles' (`util/color.h`), which differ in rounding and
//! edge cases from Blender's own `BLI` ones used by colour ramps.

use super::math::{clamp_c, fract, max_c, min_c, saturate};
use glam::Vec3;

/// Luminance weights of linear Rec.709 as Cycles derives them in Blender 5.0:
/// the Y row of the inverse of its XYZ → scene-linear matrix, itself built
/// from the OpenColorIO config's `aces_interchange` role
/// (`ShaderManager::init_xyz_transforms`). Close to, not equal to,
/// (0.2126, 0.7152, 0.0722).
#[allow(clippy::excessive_precision)]
pub const REC709_TO_Y: Vec3 = Vec3::new(0.212_639_09, 0.715_169_13, 0.072_192_75);

/// Cycles' `rgb_to_hsv`: hue in [0, 1), saturation, value.
pub fn rgb_to_hsv(rgb: Vec3) -> Vec3 {
    let cmax = rgb.x.max(rgb.y.max(rgb.z));
    let cmin = min_c(rgb.x, min_c(rgb.y, rgb.z));
    let cdelta = cmax - cmin;
    let v = cmax;
    let s = if cmax != 0.0 { cdelta / cmax } else { 0.0 };
    let mut h = 0.0;
    if s != 0.0 {
        let c = (Vec3::splat(cmax) - rgb) / cdelta;
        h = if rgb.x == cmax {
            c.z - c.y
        } else if rgb.y == cmax {
            2.0 + c.x - c.z
        } else {
            4.0 + c.y - c.x
        };
        h /= 6.0;
        if h < 0.0 {
            h += 1.0;
        }
    }
    Vec3::new(h, s, v)
}

/// Cycles' `hsv_to_rgb`.
pub fn hsv_to_rgb(hsv: Vec3) -> Vec3 {
    let (mut h, s, v) = (hsv.x, hsv.y, hsv.z);
    if s == 0.0 {
        return Vec3::splat(v);
    }
    if h == 1.0 {
        h = 0.0;
    }
    h *= 6.0;
    let i = h.floor();
    let f = h - i;
    let p = v * (1.0 - s);
    let q = v * (1.0 - s * f);
    let t = v * (1.0 - s * (1.0 - f));
    if i == 0.0 {
        Vec3::new(v, t, p)
    } else if i == 1.0 {
        Vec3::new(q, v, p)
    } else if i == 2.0 {
        Vec3::new(p, v, t)
    } else if i == 3.0 {
        Vec3::new(p, q, v)
    } else if i == 4.0 {
        Vec3::new(t, p, v)
    } else {
        Vec3::new(v, p, q)
    }
}

/// Cycles' `rgb_to_hsl`: hue, saturation, lightness (capped at 1).
pub fn rgb_to_hsl(rgb: Vec3) -> Vec3 {
    let cmax = rgb.x.max(rgb.y.max(rgb.z));
    let cmin = min_c(rgb.x, min_c(rgb.y, rgb.z));
    let l = min_c(1.0, (cmax + cmin) / 2.0);
    let (mut h, s);
    if cmax == cmin {
        h = 0.0;
        s = 0.0;
    } else {
        let d = cmax - cmin;
        s = if l > 0.5 {
            d / (2.0 - cmax - cmin)
        } else {
            d / (cmax + cmin)
        };
        h = if cmax == rgb.x {
            (rgb.y - rgb.z) / d + if rgb.y < rgb.z { 6.0 } else { 0.0 }
        } else if cmax == rgb.y {
            (rgb.z - rgb.x) / d + 2.0
        } else {
            (rgb.x - rgb.y) / d + 4.0
        };
    }
    h /= 6.0;
    Vec3::new(h, s, l)
}

/// Cycles' `hsl_to_rgb`.
pub fn hsl_to_rgb(hsl: Vec3) -> Vec3 {
    let (h, s, l) = (hsl.x, hsl.y, hsl.z);
    let nr = clamp_c((h * 6.0 - 3.0).abs() - 1.0, 0.0, 1.0);
    let ng = clamp_c(2.0 - (h * 6.0 - 2.0).abs(), 0.0, 1.0);
    let nb = clamp_c(2.0 - (h * 6.0 - 4.0).abs(), 0.0, 1.0);
    let chroma = (1.0 - (2.0 * l - 1.0).abs()) * s;
    Vec3::new(
        (nr - 0.5) * chroma + l,
        (ng - 0.5) * chroma + l,
        (nb - 0.5) * chroma + l,
    )
}

fn max0(c: Vec3) -> Vec3 {
    Vec3::new(max_c(c.x, 0.0), max_c(c.y, 0.0), max_c(c.z, 0.0))
}

/// The Hue/Saturation/Value node.
pub fn hue_saturation_value(hue: f32, saturation: f32, value: f32, fac: f32, color: Vec3) -> Vec3 {
    let mut hsv = rgb_to_hsv(color);
    hsv.x = fract(hsv.x + hue + 0.5);
    hsv.y = saturate(hsv.y * saturation);
    hsv.z *= value;
    let c = hsv_to_rgb(hsv);
    max0(fac * c + (1.0 - fac) * color)
}

/// The Brightness/Contrast node.
pub fn bright_contrast(color: Vec3, bright: f32, contrast: f32) -> Vec3 {
    let a = 1.0 + contrast;
    let b = bright - contrast * 0.5;
    max0(a * color + Vec3::splat(b))
}

/// The Gamma node: positive components raised to `gamma`.
pub fn gamma(color: Vec3, gamma: f32) -> Vec3 {
    if gamma == 0.0 {
        return Vec3::ONE;
    }
    let f = |c: f32| if c > 0.0 { c.powf(gamma) } else { c };
    Vec3::new(f(color.x), f(color.y), f(color.z))
}

/// The Invert node.
pub fn invert(fac: f32, color: Vec3) -> Vec3 {
    let f = |c: f32| fac * (1.0 - c) + (1.0 - fac) * c;
    Vec3::new(f(color.x), f(color.y), f(color.z))
}

/// The RGB to BW node (also Cycles' implicit colour → float conversion).
pub fn rgb_to_bw(color: Vec3) -> f32 {
    color.x * REC709_TO_Y.x + color.y * REC709_TO_Y.y + color.z * REC709_TO_Y.z
}

/// Colour model of Separate/Combine Color (RNA `mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ColorMode {
    Rgb,
    Hsv,
    Hsl,
}

impl ColorMode {
    /// From Blender's RNA identifier (`"RGB"`, `"HSV"`, `"HSL"`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        match identifier {
            "RGB" => Some(Self::Rgb),
            "HSV" => Some(Self::Hsv),
            "HSL" => Some(Self::Hsl),
            _ => None,
        }
    }
}

/// The Separate Color node: the three outputs as a `Vec3`.
pub fn separate_color(mode: ColorMode, color: Vec3) -> Vec3 {
    match mode {
        ColorMode::Rgb => color,
        ColorMode::Hsv => rgb_to_hsv(color),
        ColorMode::Hsl => rgb_to_hsl(color),
    }
}

/// The Combine Color node: the three inputs as a `Vec3`.
pub fn combine_color(mode: ColorMode, components: Vec3) -> Vec3 {
    match mode {
        ColorMode::Rgb => components,
        ColorMode::Hsv => hsv_to_rgb(components),
        ColorMode::Hsl => hsl_to_rgb(components),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::graph::ops::testutil::*;

    #[test]
    fn matches_cycles() {
        let data = parse(include_str!("testdata/color.json"));
        let inp = &data["inputs"];
        let color = vectors(&inp["color"]);
        let comps = vectors(&inp["components"]);
        let hue = floats(&inp["hue"]);
        let sat = floats(&inp["saturation"]);
        let val = floats(&inp["value"]);
        let fac = floats(&inp["factor"]);
        let gam = floats(&inp["gamma"]);
        let bright = floats(&inp["bright"]);
        let contrast = floats(&inp["contrast"]);
        let mut bad = Vec::new();
        let mut nodes = std::collections::HashSet::new();
        for case in data["cases"].as_array().expect("cases") {
            let node = case["node"].as_str().expect("node");
            let mode = case["mode"].as_str().and_then(ColorMode::from_blender);
            nodes.insert(format!("{node}{mode:?}"));
            if node == "RGB_TO_BW" {
                for (i, r) in f32s(&case["result"]).into_iter().enumerate() {
                    let ours = rgb_to_bw(color[i]);
                    if !close(ours, r) {
                        bad.push(format!("{node} {}: {ours} vs {r:?}", color[i]));
                    }
                }
                continue;
            }
            for (i, r) in vec3s(&case["result"]).into_iter().enumerate() {
                let ours = match (node, mode) {
                    ("HUE_SAT", _) => {
                        hue_saturation_value(hue[i], sat[i], val[i], fac[i], color[i])
                    }
                    ("BRIGHT_CONTRAST", _) => bright_contrast(color[i], bright[i], contrast[i]),
                    ("GAMMA", _) => gamma(color[i], gam[i]),
                    ("INVERT", _) => invert(fac[i], color[i]),
                    ("SEPARATE", Some(m)) => separate_color(m, color[i]),
                    ("COMBINE", Some(m)) => combine_color(m, comps[i]),
                    other => panic!("unknown case {other:?}"),
                };
                if !close3(ours, r) {
                    bad.push(format!("{node} {mode:?} #{i}: {ours} vs {r:?}"));
                }
            }
        }
        assert_eq!(nodes.len(), 11);
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
            let v = Vec3::new(x, 0.5, -x);
            let _ = hue_saturation_value(x, x, x, x, v);
            let _ = bright_contrast(v, x, x);
            let _ = gamma(v, x);
            let _ = invert(x, v);
            let _ = rgb_to_bw(v);
            for m in [ColorMode::Rgb, ColorMode::Hsv, ColorMode::Hsl] {
                let _ = separate_color(m, v);
                let _ = combine_color(m, v);
            }
        }
    }
}
