//! sRGB 8-bit PNG preview.

use crate::error::{Error, Result};
use crate::render::film::Image;
use std::path::Path;

/// Linear to sRGB-encoded [0,1] (IEC 61966-2-1).
pub fn linear_to_srgb(x: f32) -> f32 {
    let x = if x.is_finite() {
        x.clamp(0.0, 1.0)
    } else {
        0.0
    };
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// Encodes an image with the given exposure multiplier; with `alpha` (one per pixel, the
/// image premultiplied by it, as the film is) an RGBA PNG of straight colour, as PNG stores it.
pub fn write_png(
    path: impl AsRef<Path>,
    img: &Image,
    exposure: f32,
    alpha: Option<&[f32]>,
) -> Result<()> {
    let path = path.as_ref();
    let file = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
    let mut enc = png::Encoder::new(
        std::io::BufWriter::new(file),
        img.width as u32,
        img.height as u32,
    );
    enc.set_color(if alpha.is_some() {
        png::ColorType::Rgba
    } else {
        png::ColorType::Rgb
    });
    enc.set_depth(png::BitDepth::Eight);
    enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let mut w = enc.write_header().map_err(|e| Error::io(path, e))?;
    let byte = |c: f32| (linear_to_srgb(c) * 255.0 + 0.5) as u8;
    let bytes: Vec<u8> = match alpha {
        None => img
            .data
            .iter()
            .flat_map(|p| p.map(|c| byte(c * exposure)))
            .collect(),
        Some(alpha) => img
            .data
            .iter()
            .zip(alpha)
            .flat_map(|(p, &a)| {
                let a = if a.is_finite() {
                    a.clamp(0.0, 1.0)
                } else {
                    1.0
                };
                let k = if a > 0.0 { exposure / a } else { 0.0 };
                let [r, g, b] = p.map(|c| byte(c * k));
                [r, g, b, (a * 255.0 + 0.5) as u8]
            })
            .collect(),
    };
    w.write_image_data(&bytes).map_err(|e| Error::io(path, e))
}
