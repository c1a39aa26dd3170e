//! Image textures and the colour/scalar parameters that may read them.

use crate::scene::desc::{ColorInput, FloatInput, TextureDesc, TextureEncoding, WrapMode};
use glam::{Vec2, Vec3};

/// How an image is read between its texels (Cycles' image interpolation; Blender's Smart is
/// Cubic, as Cycles reads it on the CPU).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Interp {
    #[default]
    Linear,
    /// The texel the point lies in.
    Closest,
    /// A uniform cubic B-spline over 4 x 4 texels.
    Cubic,
}

impl Interp {
    /// From Blender's name (`Linear`, `Closest`, `Cubic`, `Smart`).
    pub fn from_blender(s: &str) -> Option<Self> {
        Some(match s {
            "Linear" => Interp::Linear,
            "Closest" => Interp::Closest,
            "Cubic" | "Smart" => Interp::Cubic,
            _ => return None,
        })
    }
}

/// The cubic B-spline's weights of the four texels around a point at fraction `t`.
#[inline]
fn cubic_weights(t: f32) -> [f32; 4] {
    let t2 = t * t;
    let t3 = t2 * t;
    [
        (1.0 - 3.0 * t + 3.0 * t2 - t3) / 6.0,
        (4.0 - 6.0 * t2 + 3.0 * t3) / 6.0,
        (1.0 + 3.0 * t + 3.0 * t2 - 3.0 * t3) / 6.0,
        t3 / 6.0,
    ]
}

/// A float image looked up by UV, bilinearly unless told otherwise ([`Interp`]).
///
/// | parameter | meaning |
/// |---|---|
/// | `width`, `height` | size in texels |
/// | `channels` | 1 (grey), 3 (RGB) or 4 (RGBA; alpha is readable as channel 3 only) |
/// | `data` | rows from top to bottom; u goes right, v goes up, so v = 0 is the bottom row |
/// | `wrap` | `repeat`, `clamp`, `mirror` (texel indices reflect at the edges), `black` (outside [0,1) is zero) |
/// | `encoding` | `linear`, or `srgb`: colour channels interpolated as stored, then decoded |
///
/// Texel (i, j) (j counted from the bottom) is centred at ((i + 0.5)/width, (j + 0.5)/height).
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    width: usize,
    height: usize,
    channels: usize,
    data: Vec<f32>,
    wrap: WrapMode,
    /// Colour channels hold sRGB-encoded values, decoded after interpolation.
    srgb: bool,
}

/// The sRGB transfer function's inverse (IEC 61966-2-1), encoded [0, 1] to linear.
#[inline]
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

impl Texture {
    /// Builds from the IR. Missing data reads as zero; nothing here panics.
    pub fn from_desc(desc: &TextureDesc) -> Self {
        let width = desc.width.max(1) as usize;
        let height = desc.height.max(1) as usize;
        let channels = match desc.channels {
            1 | 3 | 4 => desc.channels as usize,
            _ => 1,
        };
        let n = width * height * channels;
        let mut data: Vec<f32> = desc
            .data
            .iter()
            .take(n)
            .map(|v| if v.is_finite() { *v } else { 0.0 })
            .collect();
        data.resize(n, 0.0);
        Texture {
            width,
            height,
            channels,
            data,
            wrap: desc.wrap,
            srgb: desc.encoding == TextureEncoding::Srgb,
        }
    }

    pub fn width(&self) -> usize {
        self.width
    }
    pub fn height(&self) -> usize {
        self.height
    }
    pub fn channels(&self) -> usize {
        self.channels
    }

    /// Wraps texel index `i` into [0, n); `None` is black.
    fn wrap_index(&self, i: i64, n: usize) -> Option<usize> {
        let n = n as i64;
        let j = match self.wrap {
            WrapMode::Repeat => i.rem_euclid(n),
            WrapMode::Clamp | WrapMode::Black => i.clamp(0, n - 1),
            WrapMode::Mirror => {
                let p = i.rem_euclid(2 * n);
                if p >= n {
                    2 * n - 1 - p
                } else {
                    p
                }
            }
        };
        Some(j as usize)
    }

    /// Texel (i, j) with j counted from the bottom row.
    fn texel(&self, i: i64, j: i64, c: usize) -> f32 {
        let (Some(x), Some(y)) = (
            self.wrap_index(i, self.width),
            self.wrap_index(j, self.height),
        ) else {
            return 0.0;
        };
        let row = self.height - 1 - y;
        self.data
            .get((row * self.width + x) * self.channels + c)
            .copied()
            .unwrap_or(0.0)
    }

    /// Bilinear footprint of `uv`: the lower-left texel and the weights towards +u, +v.
    fn footprint(&self, uv: Vec2) -> Option<(i64, i64, f32, f32)> {
        if !uv.is_finite() {
            return None;
        }
        if self.wrap == WrapMode::Black
            && !((0.0..1.0).contains(&uv.x) && (0.0..1.0).contains(&uv.y))
        {
            return None;
        }
        let x = uv.x as f64 * self.width as f64 - 0.5;
        let y = uv.y as f64 * self.height as f64 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        Some((x0 as i64, y0 as i64, (x - x0) as f32, (y - y0) as f32))
    }

    fn bilinear(&self, fp: (i64, i64, f32, f32), c: usize) -> f32 {
        let (i, j, tx, ty) = fp;
        let a = self.texel(i, j, c) * (1.0 - tx) + self.texel(i + 1, j, c) * tx;
        let b = self.texel(i, j + 1, c) * (1.0 - tx) + self.texel(i + 1, j + 1, c) * tx;
        a * (1.0 - ty) + b * ty
    }

    fn bicubic(&self, fp: (i64, i64, f32, f32), c: usize) -> f32 {
        let (i, j, tx, ty) = fp;
        let (wx, wy) = (cubic_weights(tx), cubic_weights(ty));
        let mut v = 0.0;
        for (b, wy) in wy.iter().enumerate() {
            let row: f32 = wx
                .iter()
                .enumerate()
                .map(|(a, wx)| wx * self.texel(i - 1 + a as i64, j - 1 + b as i64, c))
                .sum();
            v += wy * row;
        }
        v
    }

    /// The texel `uv` lies in.
    fn closest(&self, uv: Vec2, c: usize) -> f32 {
        let i = (uv.x as f64 * self.width as f64).floor() as i64;
        let j = (uv.y as f64 * self.height as f64).floor() as i64;
        self.texel(i, j, c)
    }

    /// Channel `c` at `uv` read by `interp`, before decoding.
    fn lookup(&self, uv: Vec2, c: usize, interp: Interp) -> Option<f32> {
        let fp = self.footprint(uv)?;
        Some(match interp {
            Interp::Linear => self.bilinear(fp, c),
            Interp::Cubic => self.bicubic(fp, c),
            Interp::Closest => self.closest(uv, c),
        })
    }

    /// Channel `c` at `uv`; zero for a channel the texture does not have.
    pub fn eval_channel(&self, uv: Vec2, c: usize) -> f32 {
        self.eval_channel_with(uv, c, Interp::Linear)
    }

    /// As [`Texture::eval_channel`], read by `interp`.
    pub fn eval_channel_with(&self, uv: Vec2, c: usize, interp: Interp) -> f32 {
        if c >= self.channels {
            return 0.0;
        }
        self.lookup(uv, c, interp)
            .map_or(0.0, |v| self.decoded(v, c))
    }

    /// As [`Texture::eval_rgb`], read by `interp`.
    pub fn eval_rgb_with(&self, uv: Vec2, interp: Interp) -> Vec3 {
        if interp == Interp::Linear {
            return self.eval_rgb(uv);
        }
        if self.channels == 1 {
            Vec3::splat(self.eval_channel_with(uv, 0, interp))
        } else {
            Vec3::new(
                self.eval_channel_with(uv, 0, interp),
                self.eval_channel_with(uv, 1, interp),
                self.eval_channel_with(uv, 2, interp),
            )
        }
    }

    /// Channel `c`'s interpolated value as linear: sRGB-encoded colour channels are decoded.
    #[inline]
    fn decoded(&self, v: f32, c: usize) -> f32 {
        if self.srgb && c < 3 {
            srgb_to_linear(v)
        } else {
            v
        }
    }

    /// RGB at `uv`; a grey texture gives (g, g, g), alpha is ignored.
    pub fn eval_rgb(&self, uv: Vec2) -> Vec3 {
        let Some(fp) = self.footprint(uv) else {
            return Vec3::ZERO;
        };
        if self.channels == 1 {
            Vec3::splat(self.decoded(self.bilinear(fp, 0), 0))
        } else {
            Vec3::new(
                self.decoded(self.bilinear(fp, 0), 0),
                self.decoded(self.bilinear(fp, 1), 1),
                self.decoded(self.bilinear(fp, 2), 2),
            )
        }
    }
}

/// A colour parameter: constant, or a texture times a scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColorParam {
    Const(Vec3),
    Tex { tex: u32, scale: Vec3 },
}

impl ColorParam {
    pub fn from_input(input: &ColorInput) -> Self {
        match input {
            ColorInput::Value(c) => ColorParam::Const(Vec3::from_array(*c)),
            ColorInput::Texture { texture, scale } => ColorParam::Tex {
                tex: *texture,
                scale: Vec3::from_array(*scale),
            },
        }
    }

    /// The colour at `uv`; a missing texture reads as black.
    pub fn eval(&self, uv: Vec2, textures: &[Texture]) -> Vec3 {
        match *self {
            ColorParam::Const(c) => c,
            ColorParam::Tex { tex, scale } => textures
                .get(tex as usize)
                .map_or(Vec3::ZERO, |t| t.eval_rgb(uv) * scale),
        }
    }

    /// Whether the parameter is the constant black.
    pub fn is_black(&self) -> bool {
        match *self {
            ColorParam::Const(c) => c.max_element() <= 0.0,
            ColorParam::Tex { scale, .. } => scale.max_element() <= 0.0,
        }
    }
}

/// A scalar parameter: constant, or one texture channel times a scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FloatParam {
    Const(f32),
    Tex { tex: u32, channel: u32, scale: f32 },
}

impl FloatParam {
    pub fn from_input(input: &FloatInput) -> Self {
        match input {
            FloatInput::Value(v) => FloatParam::Const(*v),
            FloatInput::Texture {
                texture,
                channel,
                scale,
            } => FloatParam::Tex {
                tex: *texture,
                channel: *channel,
                scale: *scale,
            },
        }
    }

    /// The value at `uv`; a missing texture reads as zero.
    pub fn eval(&self, uv: Vec2, textures: &[Texture]) -> f32 {
        match *self {
            FloatParam::Const(v) => v,
            FloatParam::Tex {
                tex,
                channel,
                scale,
            } => textures
                .get(tex as usize)
                .map_or(0.0, |t| t.eval_channel(uv, channel as usize) * scale),
        }
    }

    /// Bounds on the values the parameter can take ([0, scale x max texel] for textures).
    pub fn range(&self, textures: &[Texture]) -> (f32, f32) {
        match *self {
            FloatParam::Const(v) => (v, v),
            FloatParam::Tex {
                tex,
                channel,
                scale,
            } => {
                let Some(t) = textures.get(tex as usize) else {
                    return (0.0, 0.0);
                };
                let c = channel as usize;
                let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
                if c < t.channels {
                    for v in t.data.iter().skip(c).step_by(t.channels) {
                        lo = lo.min(*v);
                        hi = hi.max(*v);
                    }
                }
                if lo > hi {
                    return (0.0, 0.0);
                }
                // The decoding is monotonic: the bounds of the decoded values.
                let (lo, hi) = (t.decoded(lo, c), t.decoded(hi, c));
                let (mut a, mut b) = (lo * scale, hi * scale);
                if t.wrap == WrapMode::Black {
                    // Black wrapping reads zero outside the image.
                    a = a.min(0.0);
                    b = b.max(0.0);
                }
                (a, b)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tex(w: u32, h: u32, ch: u32, data: Vec<f32>, wrap: WrapMode) -> Texture {
        Texture::from_desc(&TextureDesc {
            name: String::new(),
            width: w,
            height: h,
            channels: ch,
            data,
            wrap,
            encoding: TextureEncoding::Linear,
        })
    }

    #[test]
    fn closest_and_cubic_read_as_cycles_reads() {
        // A ramp 0, 1, ..., 7 along u (one row, repeating).
        let t = tex(8, 1, 1, (0..8).map(|i| i as f32).collect(), WrapMode::Clamp);
        let at = |u: f32, i| t.eval_channel_with(Vec2::new(u, 0.5), 0, i);
        // Closest: the texel the point lies in, even at its edge.
        assert_eq!(at(0.374, Interp::Closest), 2.0);
        assert_eq!(at(0.376, Interp::Closest), 3.0);
        // Cubic: the B-spline reproduces a linear ramp away from the edges (as linear
        // interpolation does), ...
        for u in [0.3, 0.41, 0.5, 0.62] {
            let lin = at(u, Interp::Linear);
            assert!((at(u, Interp::Cubic) - lin).abs() < 1e-5, "{u}");
        }
        // ... and at a texel's centre weighs it 4/6 and its neighbours 1/6 each.
        let spike = tex(5, 1, 1, vec![0.0, 0.0, 6.0, 0.0, 0.0], WrapMode::Clamp);
        let v = |u: f32| spike.eval_channel_with(Vec2::new(u, 0.5), 0, Interp::Cubic);
        assert!((v(0.5) - 4.0).abs() < 1e-5 && (v(0.3) - 1.0).abs() < 1e-5);
        assert!(v(0.1).abs() < 1e-5);
        assert_eq!(Interp::from_blender("Smart"), Some(Interp::Cubic));
        assert_eq!(Interp::from_blender("Nearest"), None);
    }

    #[test]
    fn srgb_texture_interpolates_encoded_then_decodes() {
        // Two texels, sRGB-encoded 0 and 1 (a black/white edge): halfway the encoded value
        // 0.5 decodes to 0.214 (a linear texture would give 0.5); the texels themselves are
        // decoded exactly; alpha stays linear.
        let mut t = tex(
            2,
            1,
            4,
            vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
            WrapMode::Clamp,
        );
        t.srgb = true;
        let mid = t.eval_rgb(Vec2::new(0.5, 0.5));
        assert!((mid.x - srgb_to_linear(0.5)).abs() < 1e-6 && (mid.x - 0.2140).abs() < 1e-3);
        assert!((t.eval_channel(Vec2::new(0.5, 0.5), 3) - 0.5).abs() < 1e-6);
        assert_eq!(t.eval_rgb(Vec2::new(0.25, 0.5)), Vec3::ZERO);
        assert!((t.eval_rgb(Vec2::new(0.75, 0.5)).x - 1.0).abs() < 1e-6);
        // 188/255 decodes to 0.5029 (the sRGB curve, not a 2.2 power).
        assert!((srgb_to_linear(188.0 / 255.0) - 0.5029).abs() < 1e-3);
    }

    #[test]
    fn bottom_row_is_v_zero() {
        // 1x2 grey: top texel 1, bottom texel 0.
        let t = tex(1, 2, 1, vec![1.0, 0.0], WrapMode::Clamp);
        assert_eq!(t.eval_channel(Vec2::new(0.5, 0.25), 0), 0.0);
        assert_eq!(t.eval_channel(Vec2::new(0.5, 0.75), 0), 1.0);
        assert!((t.eval_channel(Vec2::new(0.5, 0.5), 0) - 0.5).abs() < 1e-6);
        assert_eq!(t.eval_channel(Vec2::new(0.5, 0.0), 0), 0.0);
        assert_eq!(t.eval_channel(Vec2::new(0.5, 1.0), 0), 1.0);
    }

    #[test]
    fn bilinear_weights() {
        // 2x2, rows top to bottom: [a b; c d] with c, d at the bottom.
        let (a, b, c, d) = (1.0, 2.0, 4.0, 8.0);
        let t = tex(2, 2, 1, vec![a, b, c, d], WrapMode::Clamp);
        // Texel centres are at 0.25 and 0.75; (u, v) = (0.25 + 0.5 s, 0.25 + 0.5 r).
        let (s, r) = (0.3f32, 0.6f32);
        let uv = Vec2::new(0.25 + 0.5 * s, 0.25 + 0.5 * r);
        let bottom = c * (1.0 - s) + d * s;
        let top = a * (1.0 - s) + b * s;
        let expect = bottom * (1.0 - r) + top * r;
        assert!((t.eval_channel(uv, 0) - expect).abs() < 1e-5);
    }

    #[test]
    fn wrap_modes() {
        // 4x1 ramp 0, 1, 2, 3.
        let data = vec![0.0, 1.0, 2.0, 3.0];
        let at =
            |w: WrapMode, u: f32| tex(4, 1, 1, data.clone(), w).eval_channel(Vec2::new(u, 0.5), 0);
        // Texel centres at 0.125 + 0.25 i.
        assert!((at(WrapMode::Repeat, 1.125) - 0.0).abs() < 1e-5);
        assert!((at(WrapMode::Repeat, -0.125) - 3.0).abs() < 1e-5);
        assert!(
            (at(WrapMode::Repeat, 1.0) - 1.5).abs() < 1e-5,
            "blend of 3 and 0"
        );
        assert!((at(WrapMode::Clamp, 1.6) - 3.0).abs() < 1e-5);
        assert!((at(WrapMode::Clamp, -0.4) - 0.0).abs() < 1e-5);
        // Mirror: texel index 4 reads texel 3, 5 reads 2, -1 reads 0.
        assert!((at(WrapMode::Mirror, 1.125) - 3.0).abs() < 1e-5);
        assert!((at(WrapMode::Mirror, 1.375) - 2.0).abs() < 1e-5);
        assert!((at(WrapMode::Mirror, -0.125) - 0.0).abs() < 1e-5);
        assert_eq!(at(WrapMode::Black, 1.2), 0.0);
        assert_eq!(at(WrapMode::Black, -0.01), 0.0);
        assert!((at(WrapMode::Black, 0.375) - 1.0).abs() < 1e-5);
    }

    #[test]
    fn channels_and_params() {
        let t = tex(1, 1, 4, vec![0.1, 0.2, 0.3, 0.9], WrapMode::Repeat);
        let uv = Vec2::new(0.3, 0.8);
        assert!((t.eval_rgb(uv) - Vec3::new(0.1, 0.2, 0.3)).length() < 1e-6);
        assert!((t.eval_channel(uv, 3) - 0.9).abs() < 1e-6);
        assert_eq!(t.eval_channel(uv, 4), 0.0);
        let g = tex(1, 1, 1, vec![0.5], WrapMode::Repeat);
        assert_eq!(g.eval_rgb(uv), Vec3::splat(0.5));
        let textures = [t, g];
        let c = ColorParam::from_input(&ColorInput::Texture {
            texture: 0,
            scale: [2.0, 2.0, 2.0],
        });
        assert!((c.eval(uv, &textures) - Vec3::new(0.2, 0.4, 0.6)).length() < 1e-6);
        let f = FloatParam::from_input(&FloatInput::Texture {
            texture: 0,
            channel: 3,
            scale: 0.5,
        });
        assert!((f.eval(uv, &textures) - 0.45).abs() < 1e-6);
        // Out-of-range texture index: black, never a panic.
        let missing = ColorParam::Tex {
            tex: 7,
            scale: Vec3::ONE,
        };
        assert_eq!(missing.eval(uv, &textures), Vec3::ZERO);
        // Short data reads as zero.
        let short = tex(2, 2, 3, vec![1.0], WrapMode::Repeat);
        assert!(short.eval_rgb(uv).is_finite());
    }
}
