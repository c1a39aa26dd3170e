//! A Jensen frame rendered in tiles, on as many machines as there are tiles, to the same
//! bits as the frame rendered whole.
//!
//! Every pixel draws from its own random stream (seed, pixel index), so a tile's pixels are
//! the frame's pixels as long as every tile reads the same photon maps and the same
//! irradiance cache: those are built once for the frame (`Renderer::maps_only`, a
//! `map_file::MapSet` filled for the frame's view) and given to every tile, so the tiles
//! share one estimate and show no seams.
//!
//! Adaptive sampling decides each pixel's further rounds from its neighbours' noise and the
//! whole image's brightness after the first round, so with it a tile renders in two stages:
//! [`TileStage::First`] (the first round: each pixel's mean and standard error, and the
//! pixels' state to continue from) and, once [`adaptive_rounds`] has decided the rounds from
//! every tile's first round, [`TileStage::Finish`]. Without adaptive sampling one
//! `Finish` stage renders a tile.

use super::accumulate::Sums;
use super::adaptive::{self, Adaptive};
use super::aov::Term;
use super::driver::Pixel;
use super::error_aov::{Replicates, REPLICATES};
use super::film::{Film, TermRadiance};
use super::renderer::Renderer;
use super::settings::{RenderMode, RenderSettings};
use super::stats::RenderStats;
use super::stratified::Rect;
use crate::error::{Error, Result};
use crate::io::container::{Reader, Writer};
use crate::math::Spectrum;
use crate::sampling::Rng;
use std::path::Path;

/// Which stage of a tile to render.
pub enum TileStage {
    /// The first round of samples only.
    First,
    /// The tile's image: from the first stage's `state` (or from scratch), with the further
    /// `rounds` of adaptive sampling per pixel (row-major in the tile; `None` without
    /// adaptive sampling).
    Finish {
        rounds: Option<Vec<u32>>,
        state: Option<Vec<u8>>,
    },
}

/// What a stage of a tile gives.
pub enum TileOutput {
    /// Each pixel's mean and standard error of the combined image after the first round
    /// (row-major in the tile), and the pixels' state.
    First {
        means: Vec<Spectrum>,
        errors: Vec<Spectrum>,
        state: Vec<u8>,
    },
    /// The tile's film (the tile's size) and its stats.
    Finished { film: Film, stats: RenderStats },
}

/// Bytes of one pixel's state: its random stream (16), term sums (Term::COUNT x 12) and
/// replicates (REPLICATES x 16), transparency (4).
const PIXEL_BYTES: usize = 16 + Term::COUNT * 12 + REPLICATES * 16 + 4;

/// The state of Jensen pixels after their first round, as bytes.
pub fn encode_pixels(pixels: &[Pixel<()>]) -> Vec<u8> {
    let mut w = Writer::default();
    w.buf.reserve(pixels.len() * PIXEL_BYTES);
    for px in pixels {
        let (state, inc) = px.rng.to_parts();
        w.u64(state);
        w.u64(inc);
        for v in px.sums.acc.0 {
            w.f32(v.x);
            w.f32(v.y);
            w.f32(v.z);
        }
        let (sums, counts) = px.sums.batches.to_parts();
        for (s, c) in sums.iter().zip(counts) {
            w.f32(s.x);
            w.f32(s.y);
            w.f32(s.z);
            w.u32(c);
        }
        w.f32(px.sums.transparent);
    }
    w.buf
}

/// The pixels of [`encode_pixels`]; `n` of them are expected.
pub fn decode_pixels(bytes: &[u8], n: usize) -> Result<Vec<Pixel<()>>> {
    if bytes.len() != n * PIXEL_BYTES {
        return Err(Error::Internal(format!(
            "a tile's state of {} bytes is not {n} pixels of {PIXEL_BYTES} bytes",
            bytes.len()
        )));
    }
    let mut r = Reader::new(bytes, Path::new("tile state"), "tile state");
    let mut out = Vec::with_capacity(n);
    for _ in 0..n {
        let rng = Rng::from_parts(r.u64("rng")?, r.u64("rng")?);
        let mut acc = TermRadiance::default();
        for v in acc.0.iter_mut() {
            *v = Spectrum::new(r.f32("acc")?, r.f32("acc")?, r.f32("acc")?);
        }
        let mut sums = [Spectrum::ZERO; REPLICATES];
        let mut counts = [0u32; REPLICATES];
        for (s, c) in sums.iter_mut().zip(counts.iter_mut()) {
            *s = Spectrum::new(
                r.f32("replicates")?,
                r.f32("replicates")?,
                r.f32("replicates")?,
            );
            *c = r.u32("replicates")?;
        }
        out.push(Pixel {
            rng,
            sums: Sums {
                acc,
                batches: Replicates::from_parts(sums, counts),
                transparent: r.f32("transparency")?,
            },
            aovs: Default::default(),
            extra: (),
        });
    }
    Ok(out)
}

/// The rounds per pixel that adaptive sampling gives a `width`-by-`height` image whose
/// pixels have these means and standard errors after their first round (row-major over the
/// whole image, from every tile's first stage); `None` when `s` does not sample adaptively.
pub fn adaptive_rounds(
    s: &RenderSettings,
    means: &[Spectrum],
    errors: &[Spectrum],
    width: usize,
    height: usize,
) -> Result<Option<Vec<u32>>> {
    if means.len() != width * height || errors.len() != width * height {
        return Err(Error::Internal(format!(
            "{} means and {} errors for a {width}x{height} image",
            means.len(),
            errors.len()
        )));
    }
    Ok(Adaptive::of(s).map(|a| a.rounds(&adaptive::noise_map(means, errors), width, height)))
}

/// Whether `s` renders a Jensen frame in two stages per tile (adaptive sampling).
pub fn two_stages(s: &RenderSettings) -> bool {
    s.mode == RenderMode::Jensen && Adaptive::of(s).is_some()
}

/// `width`-by-`height` tiles (the last row and column take the remainder) covering an image.
pub fn split(width: usize, height: usize, columns: usize, rows: usize) -> Vec<Rect> {
    let (columns, rows) = (columns.clamp(1, width.max(1)), rows.clamp(1, height.max(1)));
    let mut out = Vec::new();
    for r in 0..rows {
        let (y0, y1) = (r * height / rows, (r + 1) * height / rows);
        for c in 0..columns {
            let (x0, x1) = (c * width / columns, (c + 1) * width / columns);
            out.push(Rect {
                x: x0,
                y: y0,
                width: x1 - x0,
                height: y1 - y0,
            });
        }
    }
    out
}

/// Copies `tile` (a film of `rect`'s size) into `film` at `rect`.
pub fn place(film: &mut Film, rect: Rect, tile: &Film) -> Result<()> {
    if !rect.fits(film.width, film.height) || (tile.width, tile.height) != (rect.width, rect.height)
    {
        return Err(Error::Internal(format!(
            "a {}x{} tile does not fit at {rect:?} in a {}x{} film",
            tile.width, tile.height, film.width, film.height
        )));
    }
    for ty in 0..rect.height {
        let dst = (rect.y + ty) * film.width + rect.x;
        let src = ty * rect.width;
        for (d, s) in film.terms.iter_mut().zip(&tile.terms) {
            d.data[dst..dst + rect.width].copy_from_slice(&s.data[src..src + rect.width]);
        }
        film.error.data[dst..dst + rect.width]
            .copy_from_slice(&tile.error.data[src..src + rect.width]);
        film.alpha[dst..dst + rect.width].copy_from_slice(&tile.alpha[src..src + rect.width]);
    }
    Ok(())
}

/// Floats per pixel of [`film_to_bytes`]: RGB of every term, then of the `error` AOV, then
/// the alpha.
pub const FILM_FLOATS: usize = (Term::COUNT + 1) * 3 + 1;

/// A film as little-endian `f32`s, pixel by pixel (row-major): RGB of every term in
/// `Term::ALL` order, then of the `error` AOV, then the alpha (to ship a tile between
/// machines).
pub fn film_to_bytes(film: &Film) -> Vec<u8> {
    let mut out = Vec::with_capacity(film.width * film.height * FILM_FLOATS * 4);
    for i in 0..film.width * film.height {
        for img in film.terms.iter().chain(std::iter::once(&film.error)) {
            for v in img.data[i] {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        out.extend_from_slice(&film.alpha[i].to_le_bytes());
    }
    out
}

/// The `width`-by-`height` film of [`film_to_bytes`].
pub fn film_from_bytes(bytes: &[u8], width: usize, height: usize) -> Result<Film> {
    if bytes.len() != width * height * FILM_FLOATS * 4 {
        return Err(Error::Internal(format!(
            "{} bytes are not a {width}x{height} film",
            bytes.len()
        )));
    }
    let mut film = Film::new(width, height);
    let mut f = bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]));
    for i in 0..width * height {
        for img in film
            .terms
            .iter_mut()
            .chain(std::iter::once(&mut film.error))
        {
            for c in 0..3 {
                img.data[i][c] = f.next().unwrap_or(0.0);
            }
        }
        film.alpha[i] = f.next().unwrap_or(1.0);
    }
    Ok(film)
}

impl Renderer<'_> {
    /// One stage of tile `rect` of a Jensen frame (see the module documentation): the photon
    /// maps and irradiance cache of the frame must be given with
    /// [`Renderer::reuse_photon_maps`].
    pub fn render_tile(self, rect: Rect, stage: TileStage) -> Result<TileOutput> {
        let s = &self.settings;
        if s.mode != RenderMode::Jensen {
            return Err(Error::InvalidSetting {
                setting: "mode".into(),
                message: "tiles are a jensen-mode split; the progressive pppm mode splits a \
                          frame into blocks of passes"
                    .into(),
            });
        }
        super::compositing::require_none(self.scene, s, "tiles")?;
        if !rect.fits(self.scene.width, self.scene.height) {
            return Err(Error::InvalidSetting {
                setting: "tile".into(),
                message: format!(
                    "{rect:?} is empty or outside the {}x{} image",
                    self.scene.width, self.scene.height
                ),
            });
        }
        if self.reuse.is_none() {
            return Err(Error::InvalidSetting {
                setting: "photon_maps".into(),
                message: "a tile reads the frame's photon maps and irradiance cache: build \
                          them once and give them to every tile"
                    .into(),
            });
        }
        let estimate = self.memory_estimate();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(s.threads)
            .build()
            .map_err(|e| Error::Internal(format!("thread pool: {e}")))?;
        pool.install(|| self.render_jensen_tile(rect, stage, pool.current_num_threads(), estimate))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_the_image_once() {
        for (w, h, c, r) in [(64, 48, 2, 2), (7, 5, 3, 2), (3, 3, 8, 8), (10, 1, 4, 1)] {
            let mut seen = vec![0u32; w * h];
            for t in split(w, h, c, r) {
                assert!(t.fits(w, h), "{t:?}");
                for y in t.y..t.y + t.height {
                    for x in t.x..t.x + t.width {
                        seen[y * w + x] += 1;
                    }
                }
            }
            assert!(seen.iter().all(|&n| n == 1), "{w}x{h} in {c}x{r}");
        }
    }
}
