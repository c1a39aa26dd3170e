//! The stratified camera pass of Jensen's mode (`driver::CameraPass::stratified`): every
//! sample of a pixel at once, each replicate of the `error` AOV stratified over its own grid,
//! then adaptive sampling's further rounds; and the rectangles (tiles) it renders.

use super::accumulate::Sums;
use super::adaptive::{self, Adaptive, AdaptiveStats};
use super::driver::{CameraPass, Integrator, Pixel};
use super::error_aov::{replicate_of, REPLICATES};
use super::film::Film;
use crate::error::{Error, Result};
use crate::math::Spectrum;
use crate::sampling::Rng;
use glam::Vec2;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A rectangle of the image, in pixels: columns `x..x + width`, rows `y..y + height`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Rect {
    pub x: usize,
    pub y: usize,
    pub width: usize,
    pub height: usize,
}

impl Rect {
    /// The whole `width`-by-`height` image.
    pub fn full(width: usize, height: usize) -> Rect {
        Rect {
            x: 0,
            y: 0,
            width,
            height,
        }
    }

    /// Pixels in the rectangle.
    pub fn len(&self) -> usize {
        self.width * self.height
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether the rectangle lies within a `width`-by-`height` image and is not empty.
    pub fn fits(&self, width: usize, height: usize) -> bool {
        !self.is_empty()
            && self.x.checked_add(self.width).is_some_and(|e| e <= width)
            && self.y.checked_add(self.height).is_some_and(|e| e <= height)
    }
}

/// Each pixel's mean and standard error of the combined image after its first round: what
/// adaptive sampling decides the further rounds from (`adaptive::noise_map`).
pub fn first_round_noise<X>(pixels: &[Pixel<X>]) -> (Vec<Spectrum>, Vec<Spectrum>) {
    (
        pixels.iter().map(|px| px.sums.batches.mean()).collect(),
        pixels
            .iter()
            .map(|px| px.sums.batches.standard_error())
            .collect(),
    )
}

/// The nx-by-ny stratification grid of each replicate's samples when a pixel takes `spp`:
/// exactly one cell per sample (nx the largest divisor of the replicate's count n with
/// nx <= sqrt(n)), so that the samples cover the pixel uniformly. A grid with more cells than
/// samples would leave its last row empty and pull every pixel's samples towards its top
/// edge (with 128 samples, 32 per replicate on 5 x 7 cells, edges moved 0.06 px).
pub(super) fn replicate_grids(spp: u32) -> [(u32, u32); REPLICATES] {
    std::array::from_fn(|r| {
        let n = spp
            .saturating_sub(r as u32)
            .div_ceil(REPLICATES as u32)
            .max(1);
        let nx = (1..=n)
            .take_while(|d| d * d <= n)
            .filter(|d| n % d == 0)
            .last()
            .unwrap_or(1);
        (nx, n / nx)
    })
}

/// Film position of sample `i` in one stratified pass: the `jitter` in its replicate's
/// grid cell.
pub(super) fn stratified_point(grids: &[(u32, u32); REPLICATES], i: u32, jitter: Vec2) -> Vec2 {
    let (r, j) = replicate_of(i);
    let (nx, ny) = grids[r];
    let (cx, cy) = (j % nx, (j / nx) % ny);
    Vec2::new(
        (cx as f32 + jitter.x) / nx as f32,
        (cy as f32 + jitter.y) / ny as f32,
    )
}

impl CameraPass<'_> {
    /// All `spp` samples of a pixel at once, one pass, rows in parallel. Sample `i` belongs
    /// to replicate `i mod R` (see `error_aov`); each replicate is stratified over its own
    /// nx-by-ny grid, and the jittered point is warped by the filter.
    ///
    /// With `adaptive`, pixels in noisy regions then take further rounds of `spp` samples,
    /// each round stratified as the first, as many as their neighbours' noise after the
    /// first round asks for (`adaptive`).
    pub fn stratified<I: Integrator<Acc = Sums>>(
        &self,
        it: &mut I,
        spp: u32,
        adaptive: Option<Adaptive>,
    ) -> Result<(Film, Option<AdaptiveStats>)> {
        let full = Rect::full(self.scene.width, self.scene.height);
        self.report(0.0, self.phase);
        let pass = it.begin_pass(0)?;
        let it_ref: &I = it;
        let first_share = if adaptive.is_some() { 0.8 } else { 1.0 };
        let mut pixels = self.first_round(it_ref, &pass, spp, full, (0.0, first_share))?;

        // Further rounds, decided once from the first round's noise.
        let rounds: Vec<u32> = match adaptive {
            Some(a) => {
                let (means, errors) = first_round_noise(&pixels);
                a.rounds(
                    &adaptive::noise_map(&means, &errors),
                    full.width,
                    full.height,
                )
            }
            None => vec![1; full.len()],
        };
        let extra_total = self.more_rounds(
            it_ref,
            &pass,
            spp,
            full,
            &mut pixels,
            &rounds,
            (first_share, 1.0),
        )?;
        self.report(1.0, self.phase);
        let film = self.rect_film(it_ref, full, &pixels, &rounds, spp);
        it.end_pass(pass, 0.0);
        let stats = adaptive.map(|a| AdaptiveStats::of(a, &rounds, spp, extra_total));
        Ok((film, stats))
    }

    /// The first round of a stratified camera pass over the pixels of `rect`: `spp` samples
    /// each, rows in parallel. Progress goes from `share.0` to `share.1`.
    pub fn first_round<I: Integrator>(
        &self,
        it: &I,
        pass: &I::Pass,
        spp: u32,
        rect: Rect,
        share: (f32, f32),
    ) -> Result<Vec<Pixel<I::Extra, I::Acc>>> {
        use rayon::prelude::*;
        let w = self.scene.width;
        let grids = replicate_grids(spp);
        let rows_done = AtomicUsize::new(0);
        let rows: Vec<Option<Vec<Pixel<I::Extra, I::Acc>>>> = (rect.y..rect.y + rect.height)
            .into_par_iter()
            .map_init(
                || self.scratch(it),
                |scratch, y| {
                    let mut row = Vec::with_capacity(rect.width);
                    for x in rect.x..rect.x + rect.width {
                        if self.cancelled() {
                            return None;
                        }
                        let mut px = Pixel::new(Rng::new(self.seed, (y * w + x) as u64));
                        for i in 0..spp {
                            let u = stratified_point(&grids, i, px.rng.vec2());
                            self.sample(it, pass, &mut px, None, (x, y), u, i, scratch);
                        }
                        row.push(px);
                    }
                    let done = rows_done.fetch_add(1, Ordering::Relaxed) + 1;
                    let f = done as f32 / rect.height.max(1) as f32;
                    self.report(share.0 + (share.1 - share.0) * f, self.phase);
                    Some(row)
                },
            )
            .collect();
        if self.cancelled() {
            return Err(Error::Cancelled);
        }
        let mut pixels = Vec::with_capacity(rect.len());
        for row in rows {
            pixels.extend(row.ok_or(Error::Cancelled)?);
        }
        Ok(pixels)
    }

    /// The further rounds of adaptive sampling over the pixels of `rect` (`pixels` after
    /// their first round, row-major in the rect): pixel `i` takes `rounds[i]` rounds of
    /// `spp` in all. Returns the samples added.
    #[allow(clippy::too_many_arguments)]
    pub fn more_rounds<I: Integrator>(
        &self,
        it: &I,
        pass: &I::Pass,
        spp: u32,
        rect: Rect,
        pixels: &mut [Pixel<I::Extra, I::Acc>],
        rounds: &[u32],
        share: (f32, f32),
    ) -> Result<u64> {
        use rayon::prelude::*;
        let grids = replicate_grids(spp);
        let extra_total: u64 = rounds
            .iter()
            .map(|&r| (r.max(1) - 1) as u64 * spp as u64)
            .sum();
        if extra_total == 0 {
            return Ok(0);
        }
        let rw = rect.width.max(1);
        let extra_done = AtomicUsize::new(0);
        pixels
            .par_chunks_mut(rw)
            .zip(rounds.par_chunks(rw))
            .enumerate()
            .for_each_init(
                || self.scratch(it),
                |scratch, (ry, (row, row_rounds))| {
                    let mut n = 0usize;
                    for (rx, (px, &r)) in row.iter_mut().zip(row_rounds).enumerate() {
                        if self.cancelled() {
                            return;
                        }
                        let (x, y) = (rect.x + rx, rect.y + ry);
                        for i in spp..r * spp {
                            let u = stratified_point(&grids, i % spp, px.rng.vec2());
                            self.sample(it, pass, px, None, (x, y), u, i, scratch);
                        }
                        n += (r.max(1) - 1) as usize * spp as usize;
                    }
                    let done = extra_done.fetch_add(n, Ordering::Relaxed) + n;
                    let f = done as f32 / extra_total as f32;
                    self.report(share.0 + (share.1 - share.0) * f, self.phase);
                },
            );
        if self.cancelled() {
            return Err(Error::Cancelled);
        }
        Ok(extra_total)
    }

    /// The film of `rect` (its size) from its pixels, pixel `i` having taken `rounds[i]`
    /// rounds of `spp` samples.
    pub fn rect_film<I: Integrator>(
        &self,
        it: &I,
        rect: Rect,
        pixels: &[Pixel<I::Extra, I::Acc>],
        rounds: &[u32],
        spp: u32,
    ) -> Film {
        let mut film = self.new_film(rect.width, rect.height);
        for (i, (px, &r)) in pixels.iter().zip(rounds).enumerate() {
            self.resolve(it, &mut film, px, r * spp, i);
        }
        film
    }
}
