//! The partial sums of pppm (`.ppart`): a block of passes of one render, as per-pixel
//! fixed-point sums (`accumulate::FixedSums`), and their merge. Sums of passes 0..N are the
//! same bits whatever blocks they were rendered in, on whatever machines, and in whatever
//! order the blocks are merged: N workers x K passes give the image of one process rendering
//! N·K passes. A pixel's image is exact while its sum over the passes stays below 2^39
//! (5.5e11) in absolute value.

use super::accumulate::{
    fixed_alpha, fixed_means, replicate_error, FixedSums, REPLICATE_VALUES, TERM_VALUES,
};
use super::error_aov::REPLICATES;
use super::film::Film;
use super::photons::MapStats;
use crate::error::{Error, Result};
use crate::io::container::{self, Kind, Reader, Writer};
use std::path::Path;

/// The squared radius of pass `k` (0-based): r_1² · (k+1)^(α−1) (K&Z 2011, eq. 15), in f64
/// and rounded once, so that it is the same number on every machine.
pub fn pass_radius2(r1: f32, alpha: f32, k: u32) -> f32 {
    let i = k as f64 + 1.0;
    ((r1 as f64) * (r1 as f64) * i.powf(alpha as f64 - 1.0)) as f32
}

/// The partial-sum file (`.ppart`): a container of this kind.
pub const PARTIAL_FILE: Kind = Kind {
    magic: *b"PMPART\0\n",
    version: 2,
    what: "partial-sum file",
};

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
    /// Per pixel: the sum of the passes' fixed-point transparency (the alpha).
    pub transparent: Vec<i64>,
    pub tally: Tally,
    /// The render options (JSON) of the render, for the stats of the merged image.
    pub options: String,
    /// The photon maps of the last pass rendered, for the stats.
    pub maps: Vec<MapStats>,
}

impl Partial {
    /// No passes yet.
    pub fn empty(header: PartialHeader) -> Partial {
        let n = header.width as usize * header.height as usize;
        Partial {
            header,
            ranges: Vec::new(),
            terms: vec![0; n * TERM_VALUES],
            replicates: vec![0; n * REPLICATE_VALUES],
            transparent: vec![0; n],
            tally: Tally::default(),
            options: String::new(),
            maps: Vec::new(),
        }
    }

    /// The sums of passes `first..first + passes` of every pixel (row-major), as the camera-pass
    /// driver accumulated them.
    pub fn of_pixels<'a>(
        header: PartialHeader,
        pixels: impl Iterator<Item = &'a FixedSums>,
        first: u32,
        passes: u32,
    ) -> Partial {
        let mut p = Partial::empty(header);
        for (i, px) in pixels.enumerate() {
            p.terms[i * TERM_VALUES..(i + 1) * TERM_VALUES].copy_from_slice(&px.terms);
            p.replicates[i * REPLICATE_VALUES..(i + 1) * REPLICATE_VALUES]
                .copy_from_slice(&px.replicates);
            p.transparent[i] = px.transparent;
        }
        if passes > 0 {
            p.ranges.push((first, first + passes));
        }
        p
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
        for (x, y) in self.transparent.iter_mut().zip(&other.transparent) {
            *x = x.wrapping_add(*y);
        }
        // The photon maps' stats as one render of all the passes reports them: emitted paths
        // and seconds summed, the stored photons and memory of the block whose passes end
        // last (whatever the order of the merge).
        let ends = |p: &[(u32, u32)]| p.last().map_or(0, |r| r.1);
        let other_ends_later = ends(&other.ranges) > ends(&self.ranges);
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
        } else {
            for (m, o) in self.maps.iter_mut().zip(&other.maps) {
                m.emitted += o.emitted;
                m.seconds += o.seconds;
                if other_ends_later {
                    m.stored = o.stored;
                    m.memory_bytes = o.memory_bytes;
                }
            }
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
        let passes = self.passes();
        let mut per_rep = [0u32; REPLICATES];
        for &(a, b) in &self.ranges {
            for p in a..b {
                per_rep[p as usize % REPLICATES] += 1;
            }
        }
        for i in 0..w * h {
            let sums = &self.terms[i * TERM_VALUES..(i + 1) * TERM_VALUES];
            film.set_pixel(i % w, i / w, &fixed_means(sums, passes));
            let reps = &self.replicates[i * REPLICATE_VALUES..(i + 1) * REPLICATE_VALUES];
            film.error.data[i] = replicate_error(reps, &per_rep);
            film.alpha[i] = fixed_alpha(self.transparent[i], passes);
        }
        film
    }

    /// The partial sum as the bytes of a `.ppart` file.
    pub fn to_bytes(&self) -> Vec<u8> {
        self.encode(&serde_json::to_string(&self.maps).unwrap_or_default())
    }

    /// The file's bytes, with the photon-map stats written as `maps_json`.
    fn encode(&self, maps_json: &str) -> Vec<u8> {
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
        w.str(maps_json);
        for sums in [&self.terms, &self.replicates, &self.transparent] {
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
        let maps = super::photons::parse_map_stats(maps_json).map_err(|e| r.corrupt(e))?;
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
        let transparent = read_sums("transparency sums", 1)?;
        r.finish()?;
        Ok(Partial {
            header,
            ranges,
            terms,
            replicates,
            transparent,
            tally,
            options,
            maps,
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

#[cfg(test)]
mod tests {
    use super::*;

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

    /// The merged photon-map stats are those of one render of all the passes, in any order:
    /// emitted paths summed, the stored photons of the block that ends last.
    #[test]
    fn merged_map_stats_do_not_depend_on_the_order() {
        let with_map = |ranges: &[(u32, u32)], stored: u64, emitted: u64| {
            let mut p = partial(ranges, 1);
            p.maps = vec![MapStats {
                map: "global",
                built: true,
                stored,
                emitted,
                memory_bytes: stored * 20,
                bytes_per_photon: 20,
                max_radius: 0.1,
                seconds: 1.0,
                kdtree_seconds: 0.0,
                irradiance_points: 0,
                volume_points: 0,
                exitance_points: 0,
                skipped_because: None,
            }];
            p
        };
        let (a, b) = (with_map(&[(0, 4)], 10, 100), with_map(&[(4, 8)], 11, 200));
        for parts in [[a.clone(), b.clone()], [b, a]] {
            let m = &Partial::merge_all(&parts).unwrap().maps[0];
            assert_eq!((m.stored, m.emitted, m.memory_bytes), (11, 300, 220));
        }
    }

    #[test]
    fn partial_files_round_trip_and_reject_damage() {
        let mut p = partial(&[(0, 3), (5, 6)], -42);
        p.options = "{\"seed\":1}".into();
        p.tally.photon_seconds = 1.5;
        let bytes = p.to_bytes();
        // Map stats that do not read (a file written by something else, checksum and all)
        // are a corrupt file, named, not a panic or stats made up.
        let bad = p.encode(r#"[{"map": 3}]"#);
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
        let e = Partial::from_bytes(&bad, Path::new("p.ppart"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("p.ppart: corrupt partial-sum file"), "{e}");
    }
}
