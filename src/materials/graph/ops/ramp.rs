//! The Color Ramp node.
//!
//! | field | meaning |
//! | --- | --- |
//! | `stops` | [`ColorStop`]s (RNA `elements`: `position`, `color` RGBA), kept sorted by position |
//! | `interpolation` | [`RampInterpolation`], RNA `interpolation` |
//! | `color_mode` | [`RampColorMode`], RNA `color_mode` |
//! | `hue_interpolation` | [`HueInterpolation`], RNA `hue_interpolation` (HSV/HSL modes) |
//!
//! [`ColorRamp::evaluate`] is Blender's colour-band evaluation
//! (`BKE_colorband_evaluate`). Cycles does not call it per shading point: it
//! bakes it at 257 evenly spaced factors ([`ColorRamp::bake`]) and the node
//! looks the table up, interpolating linearly between entries unless the
//! ramp is Constant ([`BakedColorRamp::eval`]); this is what renders match.
//!
//! In HSV and HSL colour modes Blender interpolates linearly whatever
//! `interpolation` says.

use super::math::{float_to_int, saturate};
use glam::{Vec3, Vec4};

/// Number of table intervals Cycles bakes ramps and curves into
/// (`RAMP_TABLE_SIZE`); the table has one more entry.
pub const RAMP_TABLE_SIZE: usize = 256;

/// Interpolation between stops (RNA `interpolation`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RampInterpolation {
    Ease,
    Cardinal,
    Linear,
    BSpline,
    Constant,
}

impl RampInterpolation {
    /// From Blender's RNA identifier (`"EASE"`, `"CARDINAL"`, `"LINEAR"`, `"B_SPLINE"`, `"CONSTANT"`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        match identifier {
            "EASE" => Some(Self::Ease),
            "CARDINAL" => Some(Self::Cardinal),
            "LINEAR" => Some(Self::Linear),
            "B_SPLINE" => Some(Self::BSpline),
            "CONSTANT" => Some(Self::Constant),
            _ => None,
        }
    }
}

/// Colour space the ramp interpolates in (RNA `color_mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RampColorMode {
    Rgb,
    Hsv,
    Hsl,
}

impl RampColorMode {
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

/// Direction of hue interpolation (RNA `hue_interpolation`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum HueInterpolation {
    Near,
    Far,
    Cw,
    Ccw,
}

impl HueInterpolation {
    /// From Blender's RNA identifier (`"NEAR"`, `"FAR"`, `"CW"`, `"CCW"`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        match identifier {
            "NEAR" => Some(Self::Near),
            "FAR" => Some(Self::Far),
            "CW" => Some(Self::Cw),
            "CCW" => Some(Self::Ccw),
            _ => None,
        }
    }
}

/// One stop of a ramp: position and RGBA colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColorStop {
    pub position: f32,
    pub color: Vec4,
}

/// A colour ramp (Blender's `ColorBand`).
#[derive(Clone, Debug, PartialEq)]
pub struct ColorRamp {
    stops: Vec<ColorStop>,
    pub interpolation: RampInterpolation,
    pub color_mode: RampColorMode,
    pub hue_interpolation: HueInterpolation,
}

// Blender's own (BLI) colour-model conversions, used by the colour band.
fn bli_rgb_to_hsv(c: Vec3) -> Vec3 {
    let (mut r, mut g, mut b) = (c.x, c.y, c.z);
    let mut k = 0.0;
    if g < b {
        std::mem::swap(&mut g, &mut b);
        k = -1.0;
    }
    let mut min_gb = b;
    if r < g {
        std::mem::swap(&mut r, &mut g);
        k = -2.0 / 6.0 - k;
        min_gb = g.min(b);
    }
    let chroma = r - min_gb;
    Vec3::new(
        (k + (g - b) / (6.0 * chroma + 1e-20)).abs(),
        chroma / (r + 1e-20),
        r,
    )
}

fn hue_weights(h: f32) -> Vec3 {
    Vec3::new(
        ((h * 6.0 - 3.0).abs() - 1.0).clamp(0.0, 1.0),
        (2.0 - (h * 6.0 - 2.0).abs()).clamp(0.0, 1.0),
        (2.0 - (h * 6.0 - 4.0).abs()).clamp(0.0, 1.0),
    )
}

fn bli_hsv_to_rgb(hsv: Vec3) -> Vec3 {
    let n = hue_weights(hsv.x);
    ((n - Vec3::ONE) * hsv.y + Vec3::ONE) * hsv.z
}

fn bli_rgb_to_hsl(c: Vec3) -> Vec3 {
    let cmax = c.x.max(c.y).max(c.z);
    let cmin = c.x.min(c.y).min(c.z);
    let l = (1.0f32).min((cmax + cmin) / 2.0);
    if cmax == cmin {
        return Vec3::new(0.0, 0.0, l);
    }
    let d = cmax - cmin;
    let s = if l > 0.5 {
        d / (2.0 - cmax - cmin)
    } else {
        d / (cmax + cmin)
    };
    let h = if cmax == c.x {
        (c.y - c.z) / d + if c.y < c.z { 6.0 } else { 0.0 }
    } else if cmax == c.y {
        (c.z - c.x) / d + 2.0
    } else {
        (c.x - c.y) / d + 4.0
    };
    Vec3::new(h / 6.0, s, l)
}

fn bli_hsl_to_rgb(hsl: Vec3) -> Vec3 {
    let n = hue_weights(hsl.x);
    let chroma = (1.0 - (2.0 * hsl.z - 1.0).abs()) * hsl.y;
    (n - Vec3::splat(0.5)) * chroma + Vec3::splat(hsl.z)
}

fn hue_interp(mode: HueInterpolation, mfac: f32, fac: f32, h1: f32, h2: f32) -> f32 {
    let wrap = |h: f32| if h < 1.0 { h } else { h - 1.0 };
    let h1 = wrap(h1);
    let h2 = wrap(h2);
    // 0: direct, 1: through h1 + 1, 2: through h2 + 1.
    let way = match mode {
        HueInterpolation::Near => {
            if h1 < h2 && h2 - h1 > 0.5 {
                1
            } else if h1 > h2 && h2 - h1 < -0.5 {
                2
            } else {
                0
            }
        }
        HueInterpolation::Far => {
            if h1 == h2 || (h1 < h2 && h2 - h1 < 0.5) {
                1
            } else if h1 > h2 && h2 - h1 > -0.5 {
                2
            } else {
                0
            }
        }
        HueInterpolation::Ccw => {
            if h1 > h2 {
                2
            } else {
                0
            }
        }
        HueInterpolation::Cw => {
            if h1 < h2 {
                1
            } else {
                0
            }
        }
    };
    match way {
        1 => wrap(mfac * (h1 + 1.0) + fac * h2),
        2 => wrap(mfac * h1 + fac * (h2 + 1.0)),
        _ => mfac * h1 + fac * h2,
    }
}

/// Blender's `key_curve_position_weights` for Cardinal and B-spline (with
/// Blender's digits).
#[allow(clippy::excessive_precision)]
fn spline_weights(t: f32, cardinal: bool) -> [f32; 4] {
    let t2 = t * t;
    let t3 = t2 * t;
    if cardinal {
        let fc = 0.71;
        [
            -fc * t3 + 2.0 * fc * t2 - fc * t,
            (2.0 - fc) * t3 + (fc - 3.0) * t2 + 1.0,
            (fc - 2.0) * t3 + (3.0 - 2.0 * fc) * t2 + fc * t,
            fc * t3 - fc * t2,
        ]
    } else {
        [
            -0.166_666_66 * t3 + 0.5 * t2 - 0.5 * t + 0.166_666_66,
            0.5 * t3 - t2 + 0.666_666_66,
            -0.5 * t3 + 0.5 * t2 + 0.5 * t + 0.166_666_66,
            0.166_666_66 * t3,
        ]
    }
}

impl ColorRamp {
    /// A ramp from stops in any order (sorted by position, stably).
    pub fn new(
        mut stops: Vec<ColorStop>,
        interpolation: RampInterpolation,
        color_mode: RampColorMode,
        hue_interpolation: HueInterpolation,
    ) -> Self {
        stops.sort_by(|a, b| a.position.total_cmp(&b.position));
        Self {
            stops,
            interpolation,
            color_mode,
            hue_interpolation,
        }
    }

    /// The stops, sorted by position.
    pub fn stops(&self) -> &[ColorStop] {
        &self.stops
    }

    /// Blender's exact colour-band evaluation at `pos` (RGBA).
    pub fn evaluate(&self, pos: f32) -> Vec4 {
        let stops = &self.stops;
        let tot = stops.len();
        let Some(first) = stops.first() else {
            return Vec4::ZERO;
        };
        let ipo = if self.color_mode == RampColorMode::Rgb {
            self.interpolation
        } else {
            RampInterpolation::Linear
        };
        let simple = matches!(
            ipo,
            RampInterpolation::Linear | RampInterpolation::Ease | RampInterpolation::Constant
        );
        if tot == 1 || (pos <= first.position && simple) {
            return first.color;
        }
        // First stop strictly after `pos` (a == tot: none).
        let a = stops.iter().position(|s| s.position > pos).unwrap_or(tot);
        // `right` is Blender's cbd1, `left` its cbd2.
        let (right, left) = if a == tot {
            let last = stops[tot - 1];
            (
                ColorStop {
                    position: 1.0,
                    ..last
                },
                last,
            )
        } else if a == 0 {
            (
                stops[0],
                ColorStop {
                    position: 0.0,
                    ..stops[0]
                },
            )
        } else {
            (stops[a], stops[a - 1])
        };
        if (a == tot && simple) || ipo == RampInterpolation::Constant {
            return left.color;
        }
        let mut fac = if left.position != right.position {
            (pos - right.position) / (left.position - right.position)
        } else if a != tot {
            0.0
        } else {
            1.0
        };
        if matches!(
            ipo,
            RampInterpolation::BSpline | RampInterpolation::Cardinal
        ) {
            let next = if a + 1 >= tot { right } else { stops[a + 1] };
            let prev = if a < 2 { left } else { stops[a - 2] };
            let fac = fac.clamp(0.0, 1.0);
            let t = spline_weights(fac, ipo == RampInterpolation::Cardinal);
            let out =
                t[3] * prev.color + t[2] * left.color + t[1] * right.color + t[0] * next.color;
            return out.clamp(Vec4::ZERO, Vec4::ONE);
        }
        if ipo == RampInterpolation::Ease {
            let fac2 = fac * fac;
            fac = 3.0 * fac2 - 2.0 * fac2 * fac;
        }
        let mfac = 1.0 - fac;
        let alpha = mfac * right.color.w + fac * left.color.w;
        match self.color_mode {
            RampColorMode::Rgb => mfac * right.color + fac * left.color,
            RampColorMode::Hsv | RampColorMode::Hsl => {
                let hsv = self.color_mode == RampColorMode::Hsv;
                let to = |c: Vec4| {
                    if hsv {
                        bli_rgb_to_hsv(c.truncate())
                    } else {
                        bli_rgb_to_hsl(c.truncate())
                    }
                };
                let (c1, c2) = (to(right.color), to(left.color));
                let mixed = Vec3::new(
                    hue_interp(self.hue_interpolation, mfac, fac, c1.x, c2.x),
                    mfac * c1.y + fac * c2.y,
                    mfac * c1.z + fac * c2.z,
                );
                let rgb = if hsv {
                    bli_hsv_to_rgb(mixed)
                } else {
                    bli_hsl_to_rgb(mixed)
                };
                rgb.extend(alpha)
            }
        }
    }

    /// The table Cycles renders with: the ramp at `i / 256`, `i = 0..=256`.
    pub fn bake(&self) -> BakedColorRamp {
        let table = (0..=RAMP_TABLE_SIZE)
            .map(|i| self.evaluate(i as f32 / RAMP_TABLE_SIZE as f32))
            .collect();
        BakedColorRamp {
            table,
            interpolate: self.interpolation != RampInterpolation::Constant,
        }
    }
}

/// A colour ramp baked as Cycles bakes it.
#[derive(Clone, Debug, PartialEq)]
pub struct BakedColorRamp {
    table: Vec<Vec4>,
    interpolate: bool,
}

/// Cycles' `rgb_ramp_lookup` without extrapolation: `f` clamped to [0, 1].
pub(crate) fn table_lookup<T>(table: &[T], f: f32, interpolate: bool) -> T
where
    T: Copy + Default + std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T>,
{
    let Some(last) = table.len().checked_sub(1) else {
        return T::default();
    };
    let f = saturate(f) * last as f32;
    let i = float_to_int(f).clamp(0, last as i32) as usize;
    let t = f - i as f32;
    let a = table[i];
    match table.get(i + 1) {
        Some(&b) if interpolate && t > 0.0 => a * (1.0 - t) + b * t,
        _ => a,
    }
}

impl BakedColorRamp {
    /// The node's outputs for the Factor input: Color (rgb) and Alpha (w).
    pub fn eval(&self, fac: f32) -> Vec4 {
        table_lookup(&self.table, fac, self.interpolate)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::graph::ops::testutil::*;

    fn ramp_from(case: &serde_json::Value) -> ColorRamp {
        let stops = case["stops"]
            .as_array()
            .expect("stops")
            .iter()
            .map(|s| {
                let c = floats(&s["color"]);
                ColorStop {
                    position: s["position"].as_f64().expect("pos") as f32,
                    color: Vec4::new(c[0], c[1], c[2], c[3]),
                }
            })
            .collect();
        ColorRamp::new(
            stops,
            RampInterpolation::from_blender(case["interpolation"].as_str().expect("i")).expect("i"),
            RampColorMode::from_blender(case["color_mode"].as_str().expect("m")).expect("m"),
            HueInterpolation::from_blender(case["hue_interpolation"].as_str().expect("h"))
                .expect("h"),
        )
    }

    fn rgba(v: &serde_json::Value) -> Vec<Vec4> {
        v.as_array()
            .expect("rows")
            .iter()
            .map(|r| {
                let c = floats(r);
                Vec4::new(c[0], c[1], c[2], c[3])
            })
            .collect()
    }

    #[test]
    fn matches_blender_colorband() {
        let data = parse(include_str!("testdata/ramp.json"));
        let fac = floats(&data["inputs"]["factor"]);
        let mut bad = Vec::new();
        for case in data["cases"].as_array().expect("cases") {
            let ramp = ramp_from(case);
            for (i, r) in rgba(&case["exact"]).into_iter().enumerate() {
                let ours = ramp.evaluate(fac[i]);
                if !(0..4).all(|k| close(ours[k], Some(r[k]))) {
                    bad.push(format!(
                        "{:?} {:?} {:?} at {}: {ours} vs {r}",
                        ramp.interpolation, ramp.color_mode, ramp.hue_interpolation, fac[i]
                    ));
                }
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
    fn matches_cycles() {
        let data = parse(include_str!("testdata/ramp.json"));
        let fac = floats(&data["inputs"]["factor"]);
        let mut bad = Vec::new();
        for case in data["cases"].as_array().expect("cases") {
            let baked = ramp_from(case).bake();
            let colors = vec3s(&case["cycles_color"]);
            let alphas = f32s(&case["cycles_alpha"]);
            for i in 0..fac.len() {
                let ours = baked.eval(fac[i]);
                if !close3(ours.truncate(), colors[i]) || !close(ours.w, alphas[i]) {
                    bad.push(format!(
                        "{} at {}: {ours} vs {:?} {:?}",
                        case["interpolation"], fac[i], colors[i], alphas[i]
                    ));
                }
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
    fn degenerate_ramps_do_not_panic() {
        let empty = ColorRamp::new(
            vec![],
            RampInterpolation::BSpline,
            RampColorMode::Rgb,
            HueInterpolation::Near,
        );
        assert_eq!(empty.evaluate(0.5), Vec4::ZERO);
        let _ = empty.bake().eval(f32::NAN);
        let stop = ColorStop {
            position: f32::NAN,
            color: Vec4::splat(f32::NAN),
        };
        for ipo in [RampInterpolation::Cardinal, RampInterpolation::Linear] {
            for mode in [RampColorMode::Rgb, RampColorMode::Hsv, RampColorMode::Hsl] {
                let r = ColorRamp::new(vec![stop, stop, stop], ipo, mode, HueInterpolation::Far);
                for x in [f32::NAN, f32::INFINITY, -1.0] {
                    let _ = r.evaluate(x);
                    let _ = r.bake().eval(x);
                }
            }
        }
    }
}
