//! Per-term AOV buffers and the reconstruction filter.
//!
//! Filtering is by filter importance sampling (pbrt-v4 §8.8): each sample's offset from the
//! pixel centre is drawn from the filter, and every sample of a pixel has weight 1. Pixels are
//! thus independent, which keeps the output bit-identical whatever the thread count.

use super::aov::{AovSpec, Term};
use crate::math::Spectrum;
use crate::sampling::Distribution1D;
use glam::Vec2;
use std::collections::BTreeMap;

/// Pixel reconstruction filter.
#[derive(Clone, Debug)]
pub enum Filter {
    /// Uniform over the pixel (radius 0.5).
    Box,
    /// Triangle of the given radius in pixels.
    Tent { radius: f32 },
    /// Gaussian with standard deviation `sigma` pixels, truncated at 3 sigma.
    Gaussian { sigma: f32, table: Distribution1D },
}

impl Filter {
    pub fn gaussian(sigma: f32) -> Filter {
        let n = 256;
        let f: Vec<f32> = (0..n)
            .map(|i| {
                let x = ((i as f32 + 0.5) / n as f32 * 2.0 - 1.0) * 3.0;
                (-0.5 * x * x).exp()
            })
            .collect();
        Filter::Gaussian {
            sigma,
            table: Distribution1D::new(&f),
        }
    }

    /// Offset from the pixel centre, in pixels, for a uniform `u` in [0,1)^2.
    pub fn sample(&self, u: Vec2) -> Vec2 {
        match self {
            Filter::Box => u - Vec2::splat(0.5),
            Filter::Tent { radius } => Vec2::new(sample_tent(u.x), sample_tent(u.y)) * *radius,
            Filter::Gaussian { sigma, table } => {
                let x = table.sample_continuous(u.x).0;
                let y = table.sample_continuous(u.y).0;
                (Vec2::new(x, y) * 2.0 - Vec2::ONE) * 3.0 * *sigma
            }
        }
    }
}

/// A filter is written by its name (`box`, `tent`, `gaussian`, as `options::FilterName`),
/// or, with another width than the named one, as `{"tent": {"radius": r}}` / `{"gaussian": {"sigma": s}}`.
impl serde::Serialize for Filter {
    fn serialize<S: serde::Serializer>(&self, ser: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let (name, key, value, parsed) = match self {
            Filter::Box => return ser.serialize_str("box"),
            Filter::Tent { radius } => ("tent", "radius", *radius, 1.0),
            Filter::Gaussian { sigma, .. } => ("gaussian", "sigma", *sigma, 0.5),
        };
        if value == parsed {
            return ser.serialize_str(name);
        }
        let mut m = ser.serialize_map(Some(1))?;
        m.serialize_entry(name, &std::collections::BTreeMap::from([(key, value)]))?;
        m.end()
    }
}

/// Inverse CDF of the unit tent on [-1, 1].
fn sample_tent(u: f32) -> f32 {
    if u < 0.5 {
        (2.0 * u).sqrt() - 1.0
    } else {
        1.0 - (2.0 - 2.0 * u).max(0.0).sqrt()
    }
}

/// One float RGB image.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: usize,
    pub height: usize,
    /// Row-major RGB, top row first.
    pub data: Vec<[f32; 3]>,
}

impl Image {
    pub fn new(width: usize, height: usize) -> Self {
        Image {
            width,
            height,
            data: vec![[0.0; 3]; width * height],
        }
    }
    pub fn get(&self, x: usize, y: usize) -> Spectrum {
        Spectrum::from(self.data[y * self.width + x])
    }
    pub fn mean(&self) -> Spectrum {
        let mut s = [0.0f64; 3];
        for p in &self.data {
            for c in 0..3 {
                s[c] += p[c] as f64;
            }
        }
        let n = self.data.len().max(1) as f64;
        Spectrum::new((s[0] / n) as f32, (s[1] / n) as f32, (s[2] / n) as f32)
    }
}

/// Radiance of one pixel, split by term.
#[derive(Clone, Copy, Debug, Default)]
pub struct TermRadiance(pub [Spectrum; Term::COUNT]);

impl TermRadiance {
    #[inline]
    pub fn add(&mut self, t: Term, l: Spectrum) {
        self.0[t.index()] += l;
    }
    pub fn total(&self) -> Spectrum {
        self.0.iter().copied().sum()
    }
}

/// The AOV buffers of a render: one image per term. The combined image is derived.
#[derive(Clone, Debug)]
pub struct Film {
    pub width: usize,
    pub height: usize,
    pub terms: Vec<Image>,
    /// The `error` AOV: the estimated standard error of each pixel of the combined image,
    /// per channel (see `render::error_aov`); not a term, not part of the sum.
    pub error: Image,
    /// Each pixel's alpha, the beauty's `A`: one minus the share of its samples that saw a
    /// transparent background (Film > Transparent) or a Holdout; 1 where none did.
    pub alpha: Vec<f32>,
    /// The compositing AOVs the render was asked for, in the order of
    /// `aov::AovRequest::aovs` (after `error`): denoising guides, noisy terms, light
    /// groups, Cryptomatte (`render::compositing`). Empty unless asked for.
    pub aovs: Vec<AovImage>,
    /// Each Cryptomatte type's manifest: type name -> names (`compositing::cryptomatte_header`
    /// makes the EXR metadata of it).
    pub cryptomatte: BTreeMap<String, Vec<String>>,
}

impl Film {
    pub fn new(width: usize, height: usize) -> Self {
        Film {
            width,
            height,
            terms: (0..Term::COUNT)
                .map(|_| Image::new(width, height))
                .collect(),
            error: Image::new(width, height),
            alpha: vec![1.0; width * height],
            aovs: Vec::new(),
            cryptomatte: BTreeMap::new(),
        }
    }

    /// The compositing AOV named `name` (`albedo`, `lightgroup.key`, ...).
    pub fn aov(&self, name: &str) -> Option<&AovImage> {
        self.aovs.iter().find(|a| a.spec.name == name)
    }

    /// Every image beside the terms, in the order of `aov::AovRequest::aovs`: `error` first,
    /// then the compositing AOVs, each as (spec, channels of each pixel together).
    pub fn extra_images(&self) -> Vec<(AovSpec, std::borrow::Cow<'_, [f32]>)> {
        let error: Vec<f32> = self.error.data.iter().flatten().copied().collect();
        let spec = AovSpec {
            name: super::aov::ERROR_AOV.to_string(),
            pass_name: super::aov::ERROR_PASS.to_string(),
            kind: super::aov::AovKind::Color,
        };
        std::iter::once((spec, std::borrow::Cow::Owned(error)))
            .chain(self.aovs.iter().map(|a| {
                (
                    a.spec.clone(),
                    std::borrow::Cow::Borrowed(a.data.as_slice()),
                )
            }))
            .collect()
    }

    pub fn set_pixel(&mut self, x: usize, y: usize, value: &TermRadiance) {
        let i = y * self.width + x;
        for t in Term::ALL {
            self.terms[t.index()].data[i] = value.0[t.index()].to_array();
        }
    }

    pub fn term(&self, t: Term) -> &Image {
        &self.terms[t.index()]
    }

    /// The beauty image: the sum of the terms, in the fixed order of `Term::ALL`.
    pub fn combined(&self) -> Image {
        let mut out = Image::new(self.width, self.height);
        for (i, px) in out.data.iter_mut().enumerate() {
            let mut s = [0.0f32; 3];
            for t in Term::ALL {
                let v = self.terms[t.index()].data[i];
                for c in 0..3 {
                    s[c] += v[c];
                }
            }
            *px = s;
        }
        out
    }
}

/// One AOV image of a film: its spec and its pixels, the channels of each pixel together,
/// rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct AovImage {
    pub spec: AovSpec,
    pub data: Vec<f32>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filters_stay_in_support_and_are_centred() {
        for f in [
            Filter::Box,
            Filter::Tent { radius: 1.0 },
            Filter::gaussian(0.5),
        ] {
            let mut mean = Vec2::ZERO;
            let n = 64;
            for j in 0..n {
                for i in 0..n {
                    let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    let o = f.sample(u);
                    assert!(o.abs().max_element() <= 1.5 + 1e-5, "{f:?} {o}");
                    mean += o;
                }
            }
            assert!((mean / (n * n) as f32).length() < 1e-3);
        }
    }
}
