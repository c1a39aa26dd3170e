//! Probabilistic progressive photon mapping (Knaus & Zwicker 2011, "Progressive Photon
//! Mapping: A Probabilistic Approach", ACM TOG 30(3)): the `pppm` render mode, the one whose
//! passes can be rendered anywhere and merged.
//!
//! **A pass.** Pass k (0-based; i = k + 1 in the paper's numbering) is an independent
//! estimate of the image: a fresh global (and volume) photon map of `photons.global` stored
//! photons traced with the pass's own seed ([`pass_seed`]), one camera sample per pixel
//! (the pixel's Sobol (0,2)-point k, as the other progressive modes place them, and the rest
//! of its random numbers from a stream of (pass seed, pixel)), traced to its visible points
//! as in `sppm`, where the photons within the pass's radius are gathered (Jensen 2001, eq.
//! 7.6, over a fixed disk) into `caustic` and `indirect` (routed to `specular` behind a
//! specular bounce). Direct light, emission and media are estimated at the eye.
//!
//! **The radius** is global, the same for every pixel, and depends only on the pass index
//! (K&Z 2011, §4.3, eq. 15):
//!
//! ```text
//! r_i² = r_1² · i^(α − 1),   i = 1, 2, ...
//! ```
//!
//! so that the variance of the average of N passes falls as N^(−α) and its bias as
//! N^(α−1), both to zero. r_1 is computed once ([`Renderer::pppm_initial_radius`]: the median
//! over a grid of pixels of the distance to the `initial_photons`-th nearest photon of pass
//! 1's map around the pixel's first visible point, at most the largest search radius) and
//! recorded in the stats and in every partial sum; `initial_radius` gives it explicitly.
//!
//! **Order-free sums.** Each pass's value of each term is rounded to a fixed point of
//! 2^−24 ([`FIXED_ONE`]) and added to 64-bit integer sums per pixel. Integer addition is
//! associative and commutative (wrapping, so even an intermediate overflow cancels out), so
//! the sums of passes 0..N are the same bits whatever blocks they were rendered in, on
//! whatever machines, and in whatever order the blocks are merged: N workers × K passes give
//! the image of one process rendering N·K passes. A pass's value is clamped to
//! ±[`MAX_PASS_VALUE`]; a pixel's image is exact while its sum over the passes stays below
//! 2^39 (5.5e11) in absolute value. The `error` AOV comes from per-replicate sums of the
//! combined image (pass k in replicate k mod 4), the same way.
//!
//! Everything a pass computes depends on (scene, settings, seed, r_1, k) only, and every
//! pixel on its own stream, so the sums are bit-identical for any thread count too.

use super::aov::Term;
use super::compositing::NO_AOVS;
use super::error_aov::{Shifts, REPLICATES};
use super::eye::{self, EyeCtx, EyeSettings, VisiblePoint};
use super::film::{Film, TermRadiance};
use super::memory::MemoryEstimate;
use super::photons::{self, MapStats};
use super::renderer::{RenderOutput, Renderer};
use super::settings::RenderMode;
use super::stats::StatsParts;
use super::terms::volume::MarchSettings;
use crate::error::{Error, Result};
use crate::io::container::{self, Kind, Reader, Writer};
use crate::math::{is_finite3, Spectrum, PI};
use crate::photon::map::PhotonMap;
use crate::photon::KnnScratch;
use crate::sampling::{mix64, Rng};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// One unit of radiance in the fixed point of the sums: 2^24.
pub const FIXED_ONE: f64 = (1u64 << 24) as f64;

/// Largest absolute value of one pass's estimate of one term of one pixel (2^29 ≈ 5.4e8); a
/// larger one is clamped (and counted in `non_finite_samples` if it was not finite).
pub const MAX_PASS_VALUE: f64 = (1u64 << 29) as f64;

/// Integers per pixel of the term sums: RGB per term.
pub const TERM_VALUES: usize = Term::COUNT * 3;
/// Integers per pixel of the replicate sums: RGB of the combined image per replicate.
pub const REPLICATE_VALUES: usize = REPLICATES * 3;

/// The partial-sum file (`.ppart`): a container of this kind.
pub const PARTIAL_FILE: Kind = Kind {
    magic: *b"PMPART\0\n",
    version: 1,
    what: "partial-sum file",
};

/// The seed of pass `k` of a render seeded with `seed`.
pub fn pass_seed(seed: u64, k: u32) -> u64 {
    mix64(seed ^ mix64(0x5050_504D_0000_0000 ^ k as u64))
}

/// The squared radius of pass `k` (0-based): r_1² · (k+1)^(α−1) (K&Z 2011, eq. 15), in f64
/// and rounded once, so that it is the same number on every machine.
pub fn pass_radius2(r1: f32, alpha: f32, k: u32) -> f32 {
    let i = k as f64 + 1.0;
    ((r1 as f64) * (r1 as f64) * i.powf(alpha as f64 - 1.0)) as f32
}

/// The fixed-point value of one pass's estimate.
#[inline]
fn quantize(v: f32) -> i64 {
    let x = (v as f64 * FIXED_ONE).round();
    x.clamp(-MAX_PASS_VALUE * FIXED_ONE, MAX_PASS_VALUE * FIXED_ONE) as i64
}

/// What a progressive (pppm) render did.
#[derive(Clone, Debug, Default, Serialize)]
pub struct PppmStats {
    /// Passes in the image.
    pub passes: u32,
    /// The passes rendered, as half-open ranges `[first, end)` (one for a whole render, one
    /// per block in a merge).
    pub pass_ranges: Vec<(u32, u32)>,
    pub alpha: f32,
    /// The first pass's radius r_1, and whether it was computed or given.
    pub initial_radius: f32,
    pub initial_radius_source: String,
    /// The last pass's radius.
    pub final_radius: f32,
    /// Photons stored per pass (the target; the last batch may overshoot it).
    pub photons_per_pass: u64,
    /// Photon paths emitted over all passes.
    pub photons_emitted: u64,
    /// Seconds in the photon passes and in the camera passes, summed over the blocks.
    pub photon_seconds: f64,
    pub camera_seconds: f64,
    /// Partial sums merged into this image (1 for a render in one piece).
    pub partials: u32,
}

/// What identifies the render that a partial sum belongs to: partials merge only with
/// partials of the same header.
#[derive(Clone, Debug, PartialEq)]
pub struct PartialHeader {
    pub width: u32,
    pub height: u32,
    pub seed: u64,
    pub alpha: f32,
    pub initial_radius: f32,
    pub photons_per_pass: u64,
    /// The passes of the whole render (`spp`): the merge of every block holds `0..total`.
    pub total_passes: u32,
    /// A hash of the scene (camera included) and of the settings that change a pass, from
    /// the front end (0 = not given).
    pub key: u64,
}

/// Totals that are not part of the image, for the stats.
#[derive(Clone, Debug, Default)]
pub struct Tally {
    pub non_finite: u64,
    pub photons_emitted: u64,
    pub photon_seconds: f64,
    pub camera_seconds: f64,
    pub partials: u32,
}

/// The sums of a set of passes of one pppm render: merge several with [`Partial::merge`],
/// and make the image with [`Partial::film`].
#[derive(Clone, Debug)]
pub struct Partial {
    pub header: PartialHeader,
    /// Sorted, disjoint half-open ranges of the passes summed.
    pub ranges: Vec<(u32, u32)>,
    /// Per pixel (row-major), per term, RGB: the sums of the passes' fixed-point values.
    pub terms: Vec<i64>,
    /// Per pixel, per replicate, RGB: the sums of the combined image's fixed-point values.
    pub replicates: Vec<i64>,
    pub tally: Tally,
    /// The render options (JSON) of the render, for the stats of the merged image.
    pub options: String,
    /// The photon maps of the last pass rendered, for the stats.
    pub maps: Vec<MapStats>,
}

impl Partial {
    fn empty(header: PartialHeader) -> Partial {
        let n = header.width as usize * header.height as usize;
        Partial {
            header,
            ranges: Vec::new(),
            terms: vec![0; n * TERM_VALUES],
            replicates: vec![0; n * REPLICATE_VALUES],
            tally: Tally::default(),
            options: String::new(),
            maps: Vec::new(),
        }
    }

    /// Passes summed.
    pub fn passes(&self) -> u32 {
        self.ranges.iter().map(|(a, b)| b - a).sum()
    }

    /// Adds `other`'s passes to these. Errors, naming the difference, when the two belong
    /// to different renders, or when a pass is in both (it would be counted twice).
    pub fn merge(&mut self, other: &Partial) -> Result<()> {
        let (a, b) = (&self.header, &other.header);
        let differ = |what: &str, x: String, y: String| {
            Err(Error::InvalidSetting {
                setting: "partials".into(),
                message: format!("the partial sums are of different renders: {what} {x} and {y}"),
            })
        };
        if (a.width, a.height) != (b.width, b.height) {
            return differ(
                "image size",
                format!("{}x{}", a.width, a.height),
                format!("{}x{}", b.width, b.height),
            );
        }
        if a.seed != b.seed {
            return differ("seed", a.seed.to_string(), b.seed.to_string());
        }
        if a.alpha.to_bits() != b.alpha.to_bits() {
            return differ("alpha", a.alpha.to_string(), b.alpha.to_string());
        }
        if a.initial_radius.to_bits() != b.initial_radius.to_bits() {
            return differ(
                "initial radius",
                a.initial_radius.to_string(),
                b.initial_radius.to_string(),
            );
        }
        if a.photons_per_pass != b.photons_per_pass {
            return differ(
                "photons per pass",
                a.photons_per_pass.to_string(),
                b.photons_per_pass.to_string(),
            );
        }
        if a.total_passes != b.total_passes {
            return differ(
                "passes in all",
                a.total_passes.to_string(),
                b.total_passes.to_string(),
            );
        }
        if a.key != b.key {
            return differ(
                "scene or settings (key)",
                format!("{:016x}", a.key),
                format!("{:016x}", b.key),
            );
        }
        for &(x0, x1) in &other.ranges {
            for &(y0, y1) in &self.ranges {
                let (lo, hi) = (x0.max(y0), x1.min(y1));
                if lo < hi {
                    return Err(Error::InvalidSetting {
                        setting: "partials".into(),
                        message: format!(
                            "passes {lo}..{hi} are in two partial sums: they would be counted \
                             twice"
                        ),
                    });
                }
            }
        }
        for (x, y) in self.terms.iter_mut().zip(&other.terms) {
            *x = x.wrapping_add(*y);
        }
        for (x, y) in self.replicates.iter_mut().zip(&other.replicates) {
            *x = x.wrapping_add(*y);
        }
        self.ranges.extend_from_slice(&other.ranges);
        self.ranges.sort_unstable();
        let mut merged: Vec<(u32, u32)> = Vec::new();
        for &(x0, x1) in &self.ranges {
            match merged.last_mut() {
                Some(last) if last.1 == x0 => last.1 = x1,
                _ => merged.push((x0, x1)),
            }
        }
        self.ranges = merged;
        let t = &other.tally;
        self.tally.non_finite += t.non_finite;
        self.tally.photons_emitted += t.photons_emitted;
        self.tally.photon_seconds += t.photon_seconds;
        self.tally.camera_seconds += t.camera_seconds;
        self.tally.partials += t.partials;
        if self.options.is_empty() {
            self.options = other.options.clone();
        }
        if self.maps.is_empty() {
            self.maps = other.maps.clone();
        }
        Ok(())
    }

    /// Merges `parts` (in any order: the result is the same bits).
    pub fn merge_all(parts: &[Partial]) -> Result<Partial> {
        let Some(first) = parts.first() else {
            return Err(Error::InvalidSetting {
                setting: "partials".into(),
                message: "no partial sums to merge".into(),
            });
        };
        let mut out = first.clone();
        for p in &parts[1..] {
            out.merge(p)?;
        }
        Ok(out)
    }

    /// Errors unless the passes summed are exactly 0..n for some n (a block lost or not yet
    /// rendered leaves a gap).
    pub fn check_complete(&self) -> Result<u32> {
        let total = self.header.total_passes;
        match self.ranges.as_slice() {
            [(0, n)] if *n == total && total > 0 => Ok(total),
            [] => Err(Error::InvalidSetting {
                setting: "partials".into(),
                message: "no passes".into(),
            }),
            r => {
                let mut missing = Vec::new();
                let mut at = 0;
                for &(a, b) in r {
                    if a > at {
                        missing.push(format!("{at}..{a}"));
                    }
                    at = b;
                }
                if at < total {
                    missing.push(format!("{at}..{total}"));
                }
                Err(Error::InvalidSetting {
                    setting: "partials".into(),
                    message: format!(
                        "passes {} of the render's {total} are missing (the partial sums hold \
                         {}): render and merge every block",
                        missing.join(", "),
                        r.iter()
                            .map(|(a, b)| format!("{a}..{b}"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                })
            }
        }
    }

    /// The image of the passes summed: each term's mean over the passes, and the `error`
    /// AOV from the replicates' means.
    pub fn film(&self) -> Film {
        let (w, h) = (self.header.width as usize, self.header.height as usize);
        let mut film = Film::new(w, h);
        let k = self.passes().max(1) as f64;
        let mut per_rep = [0u32; REPLICATES];
        for &(a, b) in &self.ranges {
            for p in a..b {
                per_rep[p as usize % REPLICATES] += 1;
            }
        }
        for i in 0..w * h {
            let mut v = TermRadiance::default();
            let sums = &self.terms[i * TERM_VALUES..(i + 1) * TERM_VALUES];
            for t in Term::ALL {
                let j = t.index() * 3;
                v.0[t.index()] = Spectrum::new(
                    (sums[j] as f64 / FIXED_ONE / k) as f32,
                    (sums[j + 1] as f64 / FIXED_ONE / k) as f32,
                    (sums[j + 2] as f64 / FIXED_ONE / k) as f32,
                );
            }
            film.set_pixel(i % w, i / w, &v);
            let reps = &self.replicates[i * REPLICATE_VALUES..(i + 1) * REPLICATE_VALUES];
            film.error.data[i] = replicate_error(reps, &per_rep);
        }
        film
    }

    /// The partial sum as the bytes of a `.ppart` file.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut w = Writer::default();
        let h = &self.header;
        w.u32(h.width);
        w.u32(h.height);
        w.u64(h.seed);
        w.f32(h.alpha);
        w.f32(h.initial_radius);
        w.u64(h.photons_per_pass);
        w.u32(h.total_passes);
        w.u64(h.key);
        w.u64(self.ranges.len() as u64);
        for &(a, b) in &self.ranges {
            w.u32(a);
            w.u32(b);
        }
        let t = &self.tally;
        w.u64(t.non_finite);
        w.u64(t.photons_emitted);
        w.f64(t.photon_seconds);
        w.f64(t.camera_seconds);
        w.u32(t.partials);
        w.str(&self.options);
        w.str(&serde_json::to_string(&self.maps).unwrap_or_default());
        for sums in [&self.terms, &self.replicates] {
            w.u64(sums.len() as u64);
            w.buf.reserve(sums.len() * 8);
            for v in sums.iter() {
                w.buf.extend_from_slice(&v.to_le_bytes());
            }
        }
        container::encode(&PARTIAL_FILE, &w.buf)
    }

    /// Reads the bytes of a `.ppart` file; `source` names it in errors.
    pub fn from_bytes(bytes: &[u8], source: &Path) -> Result<Partial> {
        let payload = container::decode(&PARTIAL_FILE, bytes, source)?;
        let mut r = Reader::new(payload, source, PARTIAL_FILE.what);
        let header = PartialHeader {
            width: r.u32("width")?,
            height: r.u32("height")?,
            seed: r.u64("seed")?,
            alpha: r.f32("alpha")?,
            initial_radius: r.f32("initial radius")?,
            photons_per_pass: r.u64("photons per pass")?,
            total_passes: r.u32("passes in all")?,
            key: r.u64("key")?,
        };
        let n = r.count(8, "ranges")?;
        let mut ranges = Vec::with_capacity(n);
        for _ in 0..n {
            let (a, b) = (r.u32("range")?, r.u32("range")?);
            if a >= b {
                return Err(r.corrupt(format!("empty pass range {a}..{b}")));
            }
            ranges.push((a, b));
        }
        let tally = Tally {
            non_finite: r.u64("non-finite count")?,
            photons_emitted: r.u64("photons emitted")?,
            photon_seconds: r.f64("photon seconds")?,
            camera_seconds: r.f64("camera seconds")?,
            partials: r.u32("partials")?,
        };
        let options = r.str("options")?.to_string();
        let maps_json = r.str("map stats")?;
        let maps: Vec<MapStatsIn> = serde_json::from_str(maps_json).unwrap_or_default();
        let pixels = header.width as usize * header.height as usize;
        let mut read_sums = |what: &str, per_pixel: usize| -> Result<Vec<i64>> {
            let n = r.count(8, what)?;
            if n != pixels * per_pixel {
                return Err(r.corrupt(format!(
                    "{n} {what} for {pixels} pixels (expected {})",
                    pixels * per_pixel
                )));
            }
            let bytes = r.take(n * 8, what)?;
            Ok(bytes
                .chunks_exact(8)
                .map(|c| i64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
                .collect())
        };
        let terms = read_sums("term sums", TERM_VALUES)?;
        let replicates = read_sums("replicate sums", REPLICATE_VALUES)?;
        r.finish()?;
        Ok(Partial {
            header,
            ranges,
            terms,
            replicates,
            tally,
            options,
            maps: maps.into_iter().map(MapStatsIn::into_stats).collect(),
        })
    }

    /// Writes the partial sum to `path` atomically.
    pub fn save(&self, path: &Path) -> Result<()> {
        container::write_atomic(path, &self.to_bytes())
    }

    pub fn load(path: &Path) -> Result<Partial> {
        let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
        Partial::from_bytes(&bytes, path)
    }
}

/// [`MapStats`] as read back from a partial's JSON (its `map` name owned).
#[derive(serde::Deserialize)]
struct MapStatsIn {
    map: String,
    built: bool,
    stored: u64,
    emitted: u64,
    memory_bytes: u64,
    bytes_per_photon: u64,
    max_radius: f32,
    seconds: f64,
    kdtree_seconds: f64,
    irradiance_points: u64,
    #[serde(default)]
    volume_points: u64,
    #[serde(default)]
    exitance_points: u64,
    skipped_because: Option<String>,
}

impl MapStatsIn {
    fn into_stats(self) -> MapStats {
        let map = match self.map.as_str() {
            "global" => "global",
            "caustic" => "caustic",
            _ => "volume",
        };
        MapStats {
            map,
            built: self.built,
            stored: self.stored,
            emitted: self.emitted,
            memory_bytes: self.memory_bytes,
            bytes_per_photon: self.bytes_per_photon,
            max_radius: self.max_radius,
            seconds: self.seconds,
            kdtree_seconds: self.kdtree_seconds,
            irradiance_points: self.irradiance_points,
            volume_points: self.volume_points,
            exitance_points: self.exitance_points,
            skipped_because: self.skipped_because,
        }
    }
}

/// Standard error of a pixel's mean from its replicates' sums (`sums`: RGB per replicate,
/// fixed point) and pass counts: sqrt(s² / R) over the replicate means.
fn replicate_error(sums: &[i64], counts: &[u32; REPLICATES]) -> [f32; 3] {
    let mut out = [0.0f32; 3];
    for (c, o) in out.iter_mut().enumerate() {
        let means: Vec<f64> = (0..REPLICATES)
            .filter(|&r| counts[r] > 0)
            .map(|r| sums[r * 3 + c] as f64 / FIXED_ONE / counts[r] as f64)
            .collect();
        let n = means.len();
        if n < 2 {
            continue;
        }
        let m = means.iter().sum::<f64>() / n as f64;
        let s2 = means.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1) as f64;
        *o = (s2 / n as f64).sqrt() as f32;
    }
    out
}

/// The photon terms of pass `k` at the visible points, over the disk of squared radius `r2`:
/// Φ / (π r²) per term (first-hit photons left out: direct light is estimated at the eye).
fn gather(global: &PhotonMap, vps: &[VisiblePoint], r2: f32, ctx: &EyeCtx) -> TermRadiance {
    let mut phi = TermRadiance::default();
    for vp in vps {
        global.tree.for_each_in_radius(vp.p, r2, |ph, _| {
            let Some(t) = vp.photon_term(ph.user_flags()) else {
                return;
            };
            let wi = ph.incoming();
            if wi.dot(vp.n) <= 0.0 || !ctx.settings.terms.contains(t) {
                return;
            }
            let c = vp.beta * vp.bsdf.eval_flux(vp.wo, wi) * ph.power();
            if is_finite3(c) {
                phi.add(t, c);
            }
        });
    }
    let inv = 1.0 / (PI * r2);
    for v in phi.0.iter_mut() {
        *v *= inv;
    }
    phi
}

/// Seed stream tags.
const TAG_PIXEL: u64 = 0x5050_4D5F_5049_5845;
const TAG_RADIUS: u64 = 0x5050_4D5F_5231_5F5F;

impl Renderer<'_> {
    fn pppm_eye_settings(&self) -> EyeSettings {
        let s = &self.settings;
        EyeSettings {
            terms: s.terms,
            max_specular_depth: s.max_specular_depth,
            final_gather_rays: 0,
            gather_rays_per_sample: 0,
        }
    }

    /// The global and volume maps a pass needs (no caustic map, no precomputed irradiance).
    fn pppm_need(&self) -> [bool; 3] {
        let [global, _, volume] = self.needed_maps();
        [global, false, volume]
    }

    /// r_1: the median, over the pixels of a grid (about 4096 of them), of the distance to
    /// the `initial_photons`-th nearest photon of pass 1's global map around the pixel's
    /// first visible point (the pixel centre's camera ray), at most the largest search
    /// radius; that radius where no pixel finds enough photons. Deterministic.
    pub fn pppm_initial_radius(&self) -> Result<f32> {
        let s = &self.settings;
        let (maps, _) = photons::build_with(
            self.scene,
            &s.photons,
            pass_seed(s.seed, 0),
            [true, false, false],
            self.cancel(),
            false,
        );
        if self.is_cancelled() {
            return Err(Error::Cancelled);
        }
        let max_r2 = maps.global_r2;
        let Some(global) = maps.global.as_ref() else {
            return Ok(max_r2.sqrt());
        };
        let (w, h) = (self.scene.width, self.scene.height);
        let stride = (((w * h) as f64 / 4096.0).sqrt().ceil() as usize).max(1);
        let ctx = EyeCtx {
            scene: self.scene,
            work: &self.work,
            maps: &maps,
            cache: None,
            settings: EyeSettings {
                terms: self.settings.terms.without(Term::Volume),
                ..self.pppm_eye_settings()
            },
            march: MarchSettings::for_render(s, self.scene, max_r2),
        };
        use rayon::prelude::*;
        let pixels: Vec<usize> = (0..h)
            .step_by(stride)
            .flat_map(|y| (0..w).step_by(stride).map(move |x| y * w + x))
            .collect();
        let k = s.sppm_initial_photons.max(1);
        let mut r2s: Vec<f32> = pixels
            .par_iter()
            .map_init(
                || (KnnScratch::new(), Vec::new()),
                |(scratch, vps), &i| {
                    let mut rng = Rng::derive(s.seed, TAG_RADIUS, i as u64);
                    let ray = eye::camera_ray(
                        self.scene,
                        &s.filter,
                        i % w,
                        i / w,
                        glam::Vec2::splat(0.5),
                        &mut rng,
                    );
                    vps.clear();
                    let mut record = |vp: VisiblePoint| vps.push(vp);
                    eye::trace_split(
                        &ctx,
                        ray,
                        &mut rng,
                        scratch,
                        Some(&mut record),
                        &mut NO_AOVS.sample(),
                    );
                    let vp = vps.first()?;
                    let found = global.tree.knn(vp.p, k, max_r2, scratch);
                    (found.len() >= k)
                        .then(|| found.iter().map(|nb| nb.dist2).fold(0.0f32, f32::max))
                        .filter(|r2| *r2 > 0.0 && r2.is_finite())
                },
            )
            .flatten()
            .collect();
        if r2s.is_empty() {
            return Ok(max_r2.sqrt());
        }
        let mid = r2s.len() / 2;
        let (_, m, _) = r2s.select_nth_unstable_by(mid, f32::total_cmp);
        Ok(m.min(max_r2).sqrt())
    }

    /// Renders passes `first .. first + count` of the pppm mode with first radius `r1` into a
    /// partial sum. `key` identifies the scene and settings (see [`PartialHeader::key`]).
    pub fn pppm_passes(
        &self,
        r1: f32,
        first: u32,
        count: u32,
        total: u32,
        key: u64,
    ) -> Result<Partial> {
        let s = &self.settings;
        let (w, h) = (self.scene.width, self.scene.height);
        let header = PartialHeader {
            width: w as u32,
            height: h as u32,
            seed: s.seed,
            alpha: s.sppm_alpha,
            initial_radius: r1,
            photons_per_pass: s.photons.global as u64,
            total_passes: total,
            key,
        };
        let mut out = Partial::empty(header);
        out.tally.partials = 1;
        out.options = serde_json::to_string(&super::options::RenderOptions::from_settings(s))
            .unwrap_or_default();
        let need = self.pppm_need();
        let non_finite = AtomicU64::new(0);
        let end = first
            .checked_add(count)
            .ok_or_else(|| Error::InvalidSetting {
                setting: "pass_range".into(),
                message: format!("{first} + {count} passes overflow"),
            })?;
        let start = Instant::now();
        let mut last_preview = Instant::now();
        for k in first..end {
            if let Some(b) = s.time_budget.filter(|_| k > first) {
                let per_pass = start.elapsed().as_secs_f64() / (k - first) as f64;
                if start.elapsed().as_secs_f64() + per_pass > super::budget::deadline(b) {
                    break;
                }
            }
            self.report((k - first) as f32 / count.max(1) as f32, "progressive");
            let seed = pass_seed(s.seed, k);
            let tp = Instant::now();
            let (maps, map_stats) =
                photons::build_with(self.scene, &s.photons, seed, need, self.cancel(), false);
            if self.is_cancelled() {
                return Err(Error::Cancelled);
            }
            out.tally.photons_emitted += map_stats
                .iter()
                .filter(|m| m.built && m.map == "global")
                .map(|m| m.emitted)
                .sum::<u64>();
            out.tally.photon_seconds += tp.elapsed().as_secs_f64();
            out.maps = map_stats;
            let tc = Instant::now();
            self.pppm_pass(&maps, r1, k, &mut out, &non_finite)?;
            out.tally.camera_seconds += tc.elapsed().as_secs_f64();
            match out.ranges.last_mut() {
                Some(last) if last.1 == k => last.1 = k + 1,
                _ => out.ranges.push((k, k + 1)),
            }
            if let Some(p) = &self.preview {
                let done = k + 1 - first;
                if super::driver::preview_due(done, &mut last_preview) {
                    p(&out.film(), done);
                }
            }
        }
        out.tally.non_finite = non_finite.load(Ordering::Relaxed);
        self.report(1.0, "progressive");
        Ok(out)
    }

    /// One pass over the image, added to `out`'s sums.
    fn pppm_pass(
        &self,
        maps: &photons::PhotonMaps,
        r1: f32,
        k: u32,
        out: &mut Partial,
        non_finite: &AtomicU64,
    ) -> Result<()> {
        use rayon::prelude::*;
        let s = &self.settings;
        let w = self.scene.width;
        let r2 = pass_radius2(r1, s.sppm_alpha, k);
        let seed = pass_seed(s.seed, k);
        let ctx = EyeCtx {
            scene: self.scene,
            work: &self.work,
            maps,
            cache: None,
            settings: self.pppm_eye_settings(),
            march: MarchSettings::for_render(s, self.scene, maps.global_r2),
        };
        let rep = k as usize % REPLICATES;
        let cancelled = std::sync::atomic::AtomicBool::new(false);
        out.terms
            .par_chunks_mut(w.max(1) * TERM_VALUES)
            .zip(out.replicates.par_chunks_mut(w.max(1) * REPLICATE_VALUES))
            .enumerate()
            .for_each_init(
                || (KnnScratch::new(), Vec::with_capacity(4)),
                |(scratch, vps), (y, (row, row_reps))| {
                    if self.is_cancelled() {
                        cancelled.store(true, Ordering::Relaxed);
                        return;
                    }
                    for x in 0..w {
                        let i = y * w + x;
                        let shifts = Shifts::draw(&mut Rng::new(s.seed, i as u64));
                        let mut rng = Rng::derive(seed, TAG_PIXEL, i as u64);
                        let ray =
                            eye::camera_ray(self.scene, &s.filter, x, y, shifts.point(k), &mut rng);
                        vps.clear();
                        let mut record = |vp: VisiblePoint| vps.push(vp);
                        let mut l = eye::trace_split(
                            &ctx,
                            ray,
                            &mut rng,
                            scratch,
                            Some(&mut record),
                            &mut NO_AOVS.sample(),
                        );
                        if let Some(global) = &maps.global {
                            let p = gather(global, vps, r2, &ctx);
                            for t in Term::ALL {
                                l.0[t.index()] += p.0[t.index()];
                            }
                        }
                        let sums = &mut row[x * TERM_VALUES..(x + 1) * TERM_VALUES];
                        let mut combined = [0i64; 3];
                        for t in Term::ALL {
                            let v = l.0[t.index()];
                            if !v.is_finite() {
                                non_finite.fetch_add(1, Ordering::Relaxed);
                                continue;
                            }
                            for c in 0..3 {
                                let q = quantize(v[c]);
                                let j = t.index() * 3 + c;
                                sums[j] = sums[j].wrapping_add(q);
                                combined[c] = combined[c].wrapping_add(q);
                            }
                        }
                        let reps = &mut row_reps[x * REPLICATE_VALUES..(x + 1) * REPLICATE_VALUES];
                        for c in 0..3 {
                            reps[rep * 3 + c] = reps[rep * 3 + c].wrapping_add(combined[c]);
                        }
                    }
                },
            );
        if cancelled.load(Ordering::Relaxed) || self.is_cancelled() {
            return Err(Error::Cancelled);
        }
        Ok(())
    }

    /// The pppm render: r_1 (given or computed), then passes `0..spp` (or the settings'
    /// `pass_range`, or as many as a time budget allows), as one partial sum and its image.
    pub(super) fn render_pppm(
        &self,
        threads: usize,
        estimate: MemoryEstimate,
        start: Instant,
    ) -> Result<RenderOutput> {
        let s = &self.settings;
        super::compositing::require_none(self.scene, s, "pppm's passes")?;
        let t0 = Instant::now();
        let (r1, source) = match s.pppm_initial_radius {
            Some(r) => (r, "given"),
            None => (self.pppm_initial_radius()?, "computed"),
        };
        if !(r1 > 0.0 && r1.is_finite()) {
            return Err(Error::InvalidSetting {
                setting: "initial_radius".into(),
                message: format!("must be a positive distance, got {r1}"),
            });
        }
        let radius_seconds = t0.elapsed().as_secs_f64();
        let (first, count) = match s.pass_range {
            Some((a, b)) => (a, b - a),
            None if s.time_budget.is_some() => (0, u32::MAX),
            None => (0, s.spp),
        };
        let key = self.keys.map_or(0, |k| k.render);
        let mut partial = self.pppm_passes(r1, first, count, s.spp, key)?;
        if s.pass_range.is_none() {
            // A whole render (under a time budget, of the passes that fit).
            partial.header.total_passes = partial.passes();
        }
        let mut out = self.pppm_output(&partial, threads, estimate)?;
        if let Some(p) = out.stats.pppm.as_mut() {
            p.initial_radius_source = source.into();
        }
        out.stats
            .seconds
            .insert("initial_radius".into(), radius_seconds);
        if let Some(b) = s.time_budget {
            out.stats.time_budget = Some(
                super::budget::BudgetStats {
                    passes: partial.passes(),
                    spp: partial.passes(),
                    planned_seconds: start.elapsed().as_secs_f64(),
                    seconds_per_pass: (partial.tally.photon_seconds + partial.tally.camera_seconds)
                        / partial.passes().max(1) as f64,
                    photons_global: s.photons.global,
                    photons_volume: s.photons.volume,
                    ..super::budget::BudgetStats::for_budget(b)
                }
                .finish(start.elapsed().as_secs_f64()),
            );
        }
        out.partial = Some(Box::new(partial));
        Ok(out)
    }

    /// The image and stats of a partial sum (one block, or merged blocks).
    pub fn pppm_output(
        &self,
        partial: &Partial,
        threads: usize,
        estimate: MemoryEstimate,
    ) -> Result<RenderOutput> {
        let t = &partial.tally;
        let last = partial.ranges.last().map_or(0, |r| r.1.saturating_sub(1));
        let pstats = PppmStats {
            passes: partial.passes(),
            pass_ranges: partial.ranges.clone(),
            alpha: partial.header.alpha,
            initial_radius: partial.header.initial_radius,
            initial_radius_source: "given".into(),
            final_radius: pass_radius2(partial.header.initial_radius, partial.header.alpha, last)
                .sqrt(),
            photons_per_pass: partial.header.photons_per_pass,
            photons_emitted: t.photons_emitted,
            photon_seconds: t.photon_seconds,
            camera_seconds: t.camera_seconds,
            partials: t.partials,
        };
        let mut seconds = BTreeMap::new();
        seconds.insert("photons".to_string(), t.photon_seconds);
        seconds.insert("render".to_string(), t.camera_seconds);
        let mut maps = partial.maps.clone();
        for m in maps.iter_mut().filter(|m| m.map == "caustic") {
            m.skipped_because =
                Some("progressive mode: each pass's global map holds the caustic photons".into());
        }
        let mut stats = self.stats(StatsParts {
            width: partial.header.width as usize,
            height: partial.header.height as usize,
            spp: partial.passes(),
            threads,
            seconds,
            maps,
            irradiance_cache_records: 0,
            skipped: self.skipped_terms(None),
            non_finite_samples: t.non_finite,
            estimate,
            time_budget: None,
            mode: RenderMode::Pppm,
            sppm: None,
            adaptive: None,
        });
        stats.pppm = Some(pstats);
        Ok(RenderOutput {
            film: partial.film(),
            stats,
            partial: None,
            photon_maps: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radii_follow_knaus_and_zwicker() {
        let r1 = 0.2f32;
        assert_eq!(pass_radius2(r1, 0.7, 0), r1 * r1);
        let r2 = pass_radius2(r1, 0.7, 99) as f64;
        let expect = 0.04 * 100f64.powf(-0.3);
        assert!((r2 - expect).abs() < 1e-7 * expect, "{r2} {expect}");
        assert!(pass_radius2(r1, 0.7, 10) < pass_radius2(r1, 0.7, 9));
    }

    #[test]
    fn quantisation_is_exact_on_the_fixed_point_grid_and_clamped() {
        assert_eq!(quantize(1.0), 1 << 24);
        assert_eq!(quantize(-0.5), -(1 << 23));
        assert_eq!(quantize(1e30), (MAX_PASS_VALUE * FIXED_ONE) as i64);
        assert_eq!(quantize(0.0), 0);
    }

    fn partial(ranges: &[(u32, u32)], fill: i64) -> Partial {
        let mut p = Partial::empty(PartialHeader {
            width: 2,
            height: 1,
            seed: 1,
            alpha: 0.7,
            initial_radius: 0.1,
            photons_per_pass: 10,
            total_passes: 12,
            key: 5,
        });
        p.ranges = ranges.to_vec();
        p.terms.iter_mut().for_each(|v| *v = fill);
        p.replicates.iter_mut().for_each(|v| *v = fill);
        p.tally.partials = 1;
        p
    }

    #[test]
    fn merging_checks_the_render_and_never_counts_a_pass_twice() {
        let a = partial(&[(0, 4)], 3);
        let b = partial(&[(4, 8)], i64::MAX);
        let c = partial(&[(8, 12)], 7);
        // Any order gives the same sums (wrapping addition is associative and commutative).
        let abc = Partial::merge_all(&[a.clone(), b.clone(), c.clone()]).unwrap();
        let cab = Partial::merge_all(&[c.clone(), a.clone(), b.clone()]).unwrap();
        assert_eq!(abc.terms, cab.terms);
        assert_eq!(abc.ranges, vec![(0, 12)]);
        assert_eq!(abc.check_complete().unwrap(), 12);
        let e = Partial::merge_all(&[a.clone(), a.clone()])
            .unwrap_err()
            .to_string();
        assert!(e.contains("passes 0..4 are in two partial sums"), "{e}");
        let gap = Partial::merge_all(&[a.clone(), c.clone()]).unwrap();
        let e = gap.check_complete().unwrap_err().to_string();
        assert!(
            e.contains("passes 4..8 of the render's 12 are missing"),
            "{e}"
        );
        // The first blocks alone are not the render either.
        let e = Partial::merge_all(&[a.clone(), b.clone()])
            .unwrap()
            .check_complete()
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("passes 8..12 of the render's 12 are missing"),
            "{e}"
        );
        let mut other = partial(&[(4, 8)], 1);
        other.header.seed = 2;
        let e = Partial::merge_all(&[a.clone(), other])
            .unwrap_err()
            .to_string();
        assert!(e.contains("seed 1 and 2"), "{e}");
        let mut other = partial(&[(4, 8)], 1);
        other.header.key = 6;
        assert!(Partial::merge_all(&[a, other]).is_err());
    }

    #[test]
    fn partial_files_round_trip_and_reject_damage() {
        let mut p = partial(&[(0, 3), (5, 6)], -42);
        p.options = "{\"seed\":1}".into();
        p.tally.photon_seconds = 1.5;
        let bytes = p.to_bytes();
        let q = Partial::from_bytes(&bytes, Path::new("p.ppart")).unwrap();
        assert_eq!(q.header, p.header);
        assert_eq!(
            (q.ranges, q.terms, q.replicates),
            (p.ranges, p.terms, p.replicates)
        );
        assert_eq!(q.options, p.options);
        let e = Partial::from_bytes(&bytes[..bytes.len() - 9], Path::new("p.ppart"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("p.ppart: truncated partial-sum file"), "{e}");
    }
}
