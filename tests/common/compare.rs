//! The reference comparisons of the suite, with their tolerances, shared by the tests that
//! make the claims (`reference_mitsuba.rs`, `media_reference.rs`, `photon_terms.rs`) and by
//! `sensitivity.rs`, which renders each with a small error put in and asserts that the same
//! comparison, at the same tolerance, fails.
//!
//! Every render here can scale its terms (`Scale`): the sensitivity tests use it to put in a
//! term-level error (the volume term x 0.95, the caustic term dropped); the claims render with
//! no scaling.

use super::*;
use photonmap::command::exr::read_rgb_layers;
use photonmap::render::aov::{Term, TermMask};
use photonmap::render::film::Image;
use photonmap::render::settings::FilterName;
use photonmap::render::{RenderOutput, RenderSettings};
use photonmap::scene::SceneDesc;

/// Per-term factors applied when summing a render's terms (none: every term x 1).
pub type Scale<'a> = &'a [(Term, f32)];

/// Sum of `terms` of `out`, each times its factor in `scale`.
pub fn scaled_sum(out: &RenderOutput, terms: &[Term], scale: Scale) -> Image {
    let mut img = Image::new(out.film.width, out.film.height);
    for t in terms {
        let k = scale.iter().find(|(s, _)| s == t).map_or(1.0, |(_, k)| *k);
        for (a, b) in img.data.iter_mut().zip(&out.film.term(*t).data) {
            for c in 0..3 {
                a[c] += k * b[c];
            }
        }
    }
    img
}

/// A Mitsuba reference (`tests/data/references/<name>.exr`) and its per-pixel variance (from
/// `<name>.stderr.exr`).
pub fn reference(name: &str) -> (Image, Image) {
    let mean = read_rgb_layers(data(&format!("references/{name}.exr")))
        .expect("reference EXR")
        .0[""]
        .clone();
    let mut var = read_rgb_layers(data(&format!("references/{name}.stderr.exr")))
        .expect("reference stderr EXR")
        .0[""]
        .clone();
    for p in var.data.iter_mut() {
        for c in p.iter_mut() {
            *c *= *c;
        }
    }
    (mean, var)
}

// -- per pixel: relMSE against the noise floors ----------------------------------------------

/// relMSE / the relMSE noise alone gives may reach this (with 128x128x3 pixel channels its
/// sampling spread is a few percent).
pub const PIXEL_RATIO_MAX: f64 = 1.3;
/// Each channel's image mean within this relative difference (4 standard errors of the
/// combined means are well under 0.5%).
pub const PIXEL_MEAN_MAX: f32 = 0.01;

/// The outcome of a per-pixel comparison.
#[derive(Debug, Clone, Copy)]
pub struct PixelResult {
    pub ratio: f64,
    pub mean_err: [f32; 3],
}

impl PixelResult {
    pub fn passed(&self) -> bool {
        self.ratio < PIXEL_RATIO_MAX && self.mean_err.iter().all(|e| *e < PIXEL_MEAN_MAX)
    }
}

/// Per-pixel comparison of independent batches of ours with reference `name`.
pub fn pixel_compare(label: &str, batches: &[Image], name: &str) -> PixelResult {
    let (ours, var_ours) = mean_and_var(batches);
    let (refm, var_ref) = reference(name);
    assert_eq!((ours.width, ours.height), (refm.width, refm.height));
    let measured = rel_mse(&ours, &refm);
    let ratio = measured / expected_rel_mse(&var_ours, &var_ref, &refm);
    let (mo, mr) = (ours.mean(), refm.mean());
    eprintln!(
        "{label} vs {name}: relMSE {measured:.3e}, {ratio:.3}x the noise floor; mean ours {mo:?} ref {mr:?}"
    );
    PixelResult {
        ratio,
        mean_err: [0, 1, 2].map(|c| (mo[c] / mr[c] - 1.0).abs()),
    }
}

/// The surface references: only `terms` run (with the photon terms off nothing else reaches
/// `specular`), four batches of `spp`, seeds 1000..1003.
pub fn surface_batches(desc: &SceneDesc, terms: &[Term], spp: u32, scale: Scale) -> Vec<Image> {
    let mask = terms.iter().fold(TermMask::NONE, |m, t| m.with(*t));
    (0..4)
        .map(|seed| scaled_sum(&render_terms(desc, spp, 1000 + seed, 0, mask), terms, scale))
        .collect()
}

fn render_media(
    desc: &SceneDesc,
    spp: u32,
    photons: RenderSettings,
    terms: TermMask,
    seed: u64,
) -> RenderOutput {
    render_settings(
        desc,
        RenderSettings {
            spp,
            seed,
            terms,
            filter: FilterName::Box,
            ..photons
        },
    )
}

/// fog_spot's direct light and single scattering (no volume photons): direct + volume +
/// emission, four batches of 16 spp, seeds 50..53.
pub fn single_scattering_batches(desc: &SceneDesc, scale: Scale) -> Vec<Image> {
    let terms = [Term::Direct, Term::Volume, Term::Emission];
    let mask = terms.iter().fold(TermMask::NONE, |m, t| m.with(*t));
    let photons = RenderSettings {
        volume_photons: 0,
        ..Default::default()
    };
    (0..4)
        .map(|s| {
            scaled_sum(
                &render_media(desc, 16, photons.clone(), mask, 50 + s),
                &terms,
                scale,
            )
        })
        .collect()
}

// -- 8x8 blocks: full images with media -------------------------------------------------------

/// (largest 8x8-block relMSE, largest |mean ratio - 1|) of a full media scene against its
/// `<scene>_full` reference, about twice the measured figures. Measured (seed 7, 2x10^5
/// photons per map): fog_spot block relMSE 5.7e-5, mean ratio 1.012; thick_sphere 2.6e-4,
/// 1.002; fog_glass 2.0e-3, 0.994 (its reference's own block noise floor is 1.45e-4, and its
/// glass is clear inside while ours lets the fog continue into glass that has no interior
/// medium, as Cycles does). fog_spot's mean sits 1-2% above Mitsuba's with any number of
/// volume photons (1.011 at 2x10^5 and at 2x10^6 in a gaussian-filtered render), a spot-in-fog
/// difference not found yet, so its mean tolerance stays at 2% and the volume-term check of
/// the sensitivity suite runs on fog_glass.
pub fn media_limits(scene: &str) -> (f64, f64) {
    match scene {
        "fog_spot" => (4e-4, 0.02),
        "thick_sphere" => (1e-3, 0.015),
        "fog_glass" => (4e-3, 0.015),
        _ => panic!("no limits for {scene}"),
    }
}

/// Reference pixels brighter than this (in any channel) are left out of a media scene's mean
/// ratio: there the reference shows a light's image through glass, smaller than a pixel,
/// which 8 camera samples hit only by chance. fog_glass's lamp seen through its sphere covers
/// 3 pixels at 1.0-2.3 (its other pixels are below 0.8 but for 5 of the floor caustic's
/// focus, at 1.0-1.5); a render at seed 7 that misses it has its mean 1.2% lower, one that
/// hits it once (18.7 in one pixel) 3% higher, while the mean of the other pixels stays
/// within 0.8% of Mitsuba's at seeds 7-12. The 8x8 blocks still judge these pixels.
const SPOT_PIXEL: f32 = 1.0;

/// Red-channel mean of `ours` over that of `refm`, over the pixels where `refm` is at most
/// `limit` in every channel.
fn mean_ratio_below(ours: &Image, refm: &Image, limit: f32) -> f64 {
    let (mut a, mut b) = (0.0f64, 0.0f64);
    for (o, r) in ours.data.iter().zip(&refm.data) {
        if r.iter().all(|&c| c <= limit) {
            a += o[0] as f64;
            b += r[0] as f64;
        }
    }
    a / b
}

/// The outcome of a full media comparison.
#[derive(Debug, Clone, Copy)]
pub struct MediaResult {
    pub block: f64,
    pub mean_ratio: f64,
    pub limits: (f64, f64),
}

impl MediaResult {
    pub fn passed(&self) -> bool {
        self.block < self.limits.0 && (self.mean_ratio - 1.0).abs() < self.limits.1
    }
}

pub fn media_full(label: &str, desc: &SceneDesc, scene: &str, scale: Scale) -> MediaResult {
    media_full_each(label, desc, scene, &[scale])[0]
}

/// [`media_full`] of one render with each of `scales` applied to its terms.
pub fn media_full_each(
    label: &str,
    desc: &SceneDesc,
    scene: &str,
    scales: &[Scale],
) -> Vec<MediaResult> {
    let photons = RenderSettings {
        photons: 200_000,
        volume_photons: 200_000,
        caustic_photons: 200_000,
        final_gather_rays: 256,
        ..Default::default()
    };
    let out = render_media(desc, 8, photons, TermMask::ALL, 7);
    let refm = reference_mean(&format!("{scene}_full"));
    scales
        .iter()
        .map(|scale| {
            let ours = scaled_sum(&out, &Term::ALL, scale);
            let block = block_rel_mse(&ours, &refm, 8);
            let mean_ratio = mean_ratio_below(&ours, &refm, SPOT_PIXEL);
            eprintln!(
                "{label} {scale:?} vs {scene}_full: 8x8-block relMSE {block:.3e}, mean ratio \
                 {mean_ratio:.4}"
            );
            MediaResult {
                block,
                mean_ratio,
                limits: media_limits(scene),
            }
        })
        .collect()
}

// -- 8x8 blocks by t-tests: full images with media ------------------------------------------

/// Independent renders (seeds) of a full media scene for its comparison. Our noise is taken
/// from their spread: in Jensen's mode the `error` AOV measures only the camera samples'
/// noise, while here the volume map's dominates (the seeds' block variance is a median 100x
/// the AOV's in the fog scenes, 5x in thick_sphere).
pub const MEDIA_SEEDS: u64 = 8;

/// Family-wise false-alarm rate of the per-block tests of one comparison (Bonferroni over its
/// blocks).
pub const BLOCK_FWER: f64 = 1e-3;

/// |mean ratio - 1| a full media scene may reach, about twice the measured figures (the mean
/// of the seeds, against the reference). Measured (seeds 7..14, 2x10^5 photons per map):
/// fog_spot 1.011, thick_sphere 1.002, fog_glass 0.994. fog_spot's mean sits 1-2% above
/// Mitsuba's with any number of volume photons (1.011 at 2x10^5 and at 2x10^6 in a
/// gaussian-filtered render), a spot-in-fog difference not found yet, so its mean tolerance
/// stays at 2% and the volume-term check of the sensitivity suite runs on fog_glass.
pub fn media_mean_limit(scene: &str) -> f64 {
    match scene {
        "fog_spot" => 0.02,
        "thick_sphere" => 0.015,
        "fog_glass" => 0.015,
        _ => panic!("no limits for {scene}"),
    }
}

/// The scene as its reference was made: Mitsuba's glass with no interior medium is clear
/// inside, ours lets the surrounding fog continue into it (as Cycles does), so a clear medium
/// is put inside every transmitting mesh that sits in a medium and has none of its own.
pub fn as_referenced(desc: &SceneDesc) -> SceneDesc {
    let mut d = desc.clone();
    if d.media.is_empty() {
        return d;
    }
    let transmits: Vec<bool> = d
        .materials
        .iter()
        .map(|m| matches!(m, photonmap::scene::desc::MaterialDesc::Dielectric { .. }))
        .collect();
    let clear = d.media.len() as u32;
    let mut used = false;
    for m in d.meshes.iter_mut() {
        if m.interior_medium.is_none() && transmits.get(m.material as usize) == Some(&true) {
            m.interior_medium = Some(clear);
            used = true;
        }
    }
    if used {
        d.media.push(photonmap::scene::desc::MediumDesc {
            name: "clear".into(),
            sigma_a: [0.0; 3],
            sigma_s: [0.0; 3],
            g: 0.0,
            density: None,
        });
    }
    d
}

/// Block means of an estimate (the channels averaged), the variance of each, and the degrees
/// of freedom of that variance.
#[derive(Clone, Debug)]
pub struct Blocks {
    pub width: usize,
    pub mean: Vec<f64>,
    pub var: Vec<f64>,
    pub dof: f64,
}

fn block_means(img: &Image, block: usize) -> Vec<f64> {
    let (bw, bh) = (img.width / block, img.height / block);
    let n = (block * block * 3) as f64;
    let mut out = Vec::with_capacity(bw * bh);
    for by in 0..bh {
        for bx in 0..bw {
            let mut s = 0.0f64;
            for y in by * block..(by + 1) * block {
                for x in bx * block..(bx + 1) * block {
                    let p = img.get(x, y);
                    s += (p[0] + p[1] + p[2]) as f64;
                }
            }
            out.push(s / n);
        }
    }
    out
}

impl Blocks {
    /// The mean of independent renders (seeds), its variance from their spread: K - 1 degrees
    /// of freedom, whatever the noise is made of (camera samples, photon maps).
    pub fn of_seeds(imgs: &[Image], block: usize) -> Blocks {
        let k = imgs.len() as f64;
        let each: Vec<Vec<f64>> = imgs.iter().map(|i| block_means(i, block)).collect();
        let nb = each[0].len();
        let mut mean = vec![0.0; nb];
        let mut var = vec![0.0; nb];
        for b in 0..nb {
            let m = each.iter().map(|e| e[b]).sum::<f64>() / k;
            let s2 = each.iter().map(|e| (e[b] - m).powi(2)).sum::<f64>() / (k - 1.0);
            mean[b] = m;
            var[b] = s2 / k;
        }
        Blocks {
            width: imgs[0].width / block,
            mean,
            var,
            dof: k - 1.0,
        }
    }

    /// A reference: its mean image and per-pixel variance of the mean (pixels independent,
    /// from `batches` batches), so a block's variance is the sum of its pixels' over n²
    /// (channels averaged: over 9n² for the three channels' variances summed).
    pub fn of_reference(mean: &Image, var: &Image, block: usize, batches: f64) -> Blocks {
        let (bw, bh) = (mean.width / block, mean.height / block);
        let n = (block * block) as f64;
        let mut v = Vec::with_capacity(bw * bh);
        for by in 0..bh {
            for bx in 0..bw {
                let mut s = 0.0f64;
                for y in by * block..(by + 1) * block {
                    for x in bx * block..(bx + 1) * block {
                        let p = var.get(x, y);
                        s += (p[0] + p[1] + p[2]) as f64;
                    }
                }
                v.push(s / (9.0 * n * n));
            }
        }
        Blocks {
            width: bw,
            mean: block_means(mean, block),
            var: v,
            // Each pixel's variance has batches - 1 degrees of freedom; a block pools n.
            dof: (batches - 1.0) * n,
        }
    }
}

/// Student's t survival function P(T > t), `dof` degrees of freedom: half the regularised
/// incomplete beta function I_x(dof/2, 1/2) at x = dof / (dof + t²) (Numerical Recipes'
/// continued fraction).
pub fn t_survival(t: f64, dof: f64) -> f64 {
    fn ln_gamma(x: f64) -> f64 {
        // Lanczos (g = 7, n = 9).
        const C: [f64; 9] = [
            0.999_999_999_999_809_9,
            676.520_368_121_885_1,
            -1_259.139_216_722_402_8,
            771.323_428_777_653_1,
            -176.615_029_162_140_6,
            12.507_343_278_686_905,
            -0.138_571_095_265_720_12,
            9.984_369_578_019_572e-6,
            1.505_632_735_149_311_6e-7,
        ];
        let x = x - 1.0;
        let mut a = C[0];
        let t = x + 7.5;
        for (i, c) in C.iter().enumerate().skip(1) {
            a += c / (x + i as f64);
        }
        0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
    }
    fn beta_cf(a: f64, b: f64, x: f64) -> f64 {
        let tiny = 1e-300;
        let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
        let mut c = 1.0;
        let mut d = 1.0 - qab * x / qap;
        d = 1.0 / if d.abs() < tiny { tiny } else { d };
        let mut h = d;
        for m in 1..500 {
            let m = m as f64;
            let m2 = 2.0 * m;
            for aa in [
                m * (b - m) * x / ((qam + m2) * (a + m2)),
                -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2)),
            ] {
                d = 1.0 + aa * d;
                d = 1.0 / if d.abs() < tiny { tiny } else { d };
                c = 1.0 + aa / c;
                c = if c.abs() < tiny { tiny } else { c };
                h *= d * c;
            }
            if (d * c - 1.0).abs() < 1e-15 {
                break;
            }
        }
        h
    }
    let t = t.abs();
    let (a, b, x) = (0.5 * dof, 0.5, dof / (dof + t * t));
    let front =
        (ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln()).exp();
    let i = if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_cf(a, b, x) / a
    } else {
        1.0 - front * beta_cf(b, a, 1.0 - x) / b
    };
    0.5 * i
}

/// The |t| above which a two-sided test at level `alpha` rejects (bisection on
/// [`t_survival`]).
pub fn t_critical(alpha: f64, dof: f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 1e4f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if t_survival(mid, dof) > 0.5 * alpha {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// One block of a comparison: (bx, by, t, ours / reference, critical |t|).
pub type BlockT = (usize, usize, f64, f64, f64);

/// Per-block Welch t-tests of `a` against `b`: t = (mean_a - mean_b) / sqrt(var_a + var_b),
/// with Welch-Satterthwaite's degrees of freedom, each at level `fwer / blocks` (Bonferroni).
/// Returns every block, the farthest off (in |t| over its critical value) first.
pub fn block_t_tests(a: &Blocks, b: &Blocks, fwer: f64) -> Vec<BlockT> {
    let alpha = fwer / a.mean.len() as f64;
    let mut out: Vec<BlockT> = (0..a.mean.len())
        .map(|i| {
            let (va, vb) = (a.var[i], b.var[i]);
            let v = (va + vb).max(1e-30);
            let dof = v * v / (va * va / a.dof + vb * vb / b.dof).max(1e-300);
            let t = (a.mean[i] - b.mean[i]) / v.sqrt();
            (
                i % a.width,
                i / a.width,
                t,
                a.mean[i] / b.mean[i],
                t_critical(alpha, dof.max(1.0)),
            )
        })
        .collect();
    out.sort_by(|x, y| (y.2.abs() / y.4).total_cmp(&(x.2.abs() / x.4)));
    out
}

/// The outcome of a full media comparison by blocks: the block farthest off (its t over its critical
/// value, `worst.2 / worst.4`, must stay under 1) and the mean ratio.
#[derive(Debug, Clone, Copy)]
pub struct MediaBlocks {
    pub worst: BlockT,
    pub blocks_over: usize,
    pub mean_ratio: f64,
    pub mean_limit: f64,
}

impl MediaBlocks {
    pub fn passed(&self) -> bool {
        self.blocks_over == 0 && (self.mean_ratio - 1.0).abs() < self.mean_limit
    }
}

pub fn media_blocks(label: &str, desc: &SceneDesc, scene: &str, scale: Scale) -> MediaBlocks {
    media_blocks_each(label, desc, scene, &[scale])[0]
}

/// [`media_blocks`] of one set of renders with each of `scales` applied to their terms. Every
/// 8x8 block of the mean of `MEDIA_SEEDS` renders (seeds 7, 8, ...) is t-tested against the
/// `<scene>_full` reference (its standard error from its stderr EXR, 16 batches), at a
/// family-wise false-alarm rate of `BLOCK_FWER`; and the image mean (pixels of the lamp seen
/// through glass aside) within `media_limits`.
pub fn media_blocks_each(
    label: &str,
    desc: &SceneDesc,
    scene: &str,
    scales: &[Scale],
) -> Vec<MediaBlocks> {
    let photons = RenderSettings {
        photons: 200_000,
        volume_photons: 200_000,
        caustic_photons: 200_000,
        final_gather_rays: 256,
        ..Default::default()
    };
    let desc = as_referenced(desc);
    let outs: Vec<RenderOutput> = (0..MEDIA_SEEDS)
        .map(|s| render_media(&desc, 8, photons.clone(), TermMask::ALL, 7 + s))
        .collect();
    let (refm, ref_var) = reference(&format!("{scene}_full"));
    let ref_blocks = Blocks::of_reference(&refm, &ref_var, 8, 16.0);
    scales
        .iter()
        .map(|scale| {
            let imgs: Vec<Image> = outs
                .iter()
                .map(|o| scaled_sum(o, &Term::ALL, scale))
                .collect();
            let ours = Blocks::of_seeds(&imgs, 8);
            let tests = block_t_tests(&ours, &ref_blocks, BLOCK_FWER);
            let mut mean = Image::new(refm.width, refm.height);
            for img in &imgs {
                for (a, b) in mean.data.iter_mut().zip(&img.data) {
                    for c in 0..3 {
                        a[c] += b[c] / imgs.len() as f32;
                    }
                }
            }
            let mean_ratio = mean_ratio_below(&mean, &refm, SPOT_PIXEL);
            let blocks_over = tests.iter().filter(|t| t.2.abs() > t.4).count();
            eprintln!(
                "{label} {scale:?} vs {scene}_full: {blocks_over} of {} 8x8 blocks off, mean \
                 ratio {mean_ratio:.4}; farthest (bx, by, t, ours/ref, critical |t|): {:?}",
                tests.len(),
                &tests[..4]
            );
            MediaBlocks {
                worst: tests[0],
                blocks_over,
                mean_ratio,
                mean_limit: media_mean_limit(scene),
            }
        })
        .collect()
}

// -- 8x8 blocks: full global illumination ---------------------------------------------------

/// The 8x8-block relMSE (over all 256 blocks) with 10^6 photons may reach: a 2x margin over
/// the figures measured with the worst 2 blocks left out (seed 11; 6.6e-5 and 1.3e-4 with
/// every block); a 2% brightness error alone adds 4e-4.
pub fn full_gi_limit(reference: &str) -> f64 {
    match reference {
        "cornell_diffuse_full" => 1.2e-4,
        "cornell_spheres_full" => 2e-4,
        _ => panic!("no limit for {reference}"),
    }
}

/// (relMSE, 8x8-block relMSE) of a full render with `n` global and caustic photons. Prints the
/// blocks farthest off in standard errors (ours from the `error` AOV, which leaves out the
/// photon maps' and the irradiance cache's errors, shared by every sample; the reference's
/// from its stderr EXR).
pub fn full_gi(desc: &SceneDesc, reference: &str, n: usize, scale: Scale) -> (f64, f64) {
    let photons = RenderSettings {
        photons: n,
        caustic_photons: n,
        final_gather_rays: 1024,
        cache_tolerance: 0.1,
        ..Default::default()
    };
    let out = render_settings(
        desc,
        RenderSettings {
            spp: 16,
            seed: 11,
            filter: FilterName::Box,
            ..photons
        },
    );
    let ours = scaled_sum(&out, &Term::ALL, scale);
    let (refm, ref_var) = super::compare::reference(reference);
    // Every block counts: a block far off is what the comparison is for.
    let (e, eb) = (rel_mse(&ours, &refm), block_rel_mse(&ours, &refm, 8));
    let mut our_var = out.film.error.clone();
    for p in our_var.data.iter_mut() {
        for c in p.iter_mut() {
            *c *= *c;
        }
    }
    let z = block_z(&ours, &refm, &our_var, &ref_var, 8);
    let mut worst: Vec<_> = z.iter().collect();
    worst.sort_by(|a, b| b.2.abs().total_cmp(&a.2.abs()));
    eprintln!(
        "{reference} with {n} photons: relMSE {e:.3e}, 8x8-block relMSE {eb:.3e}, mean {:?} vs \
         {:?}; largest block z (bx, by, z, ours/ref): {:?}",
        ours.mean(),
        refm.mean(),
        &worst[..4]
    );
    (e, eb)
}

pub fn reference_mean(name: &str) -> Image {
    read_rgb_layers(data(&format!("references/{name}.exr")))
        .expect("reference EXR")
        .0[""]
        .clone()
}

/// Per block x block block: (bx, by, z, ours/ref) of the channel with the largest |z|, z the
/// difference of the block means over the standard error of that difference from the
/// per-pixel variances `var_a` and `var_b` (pixels independent: a box filter).
pub fn block_z(
    a: &Image,
    b: &Image,
    var_a: &Image,
    var_b: &Image,
    block: usize,
) -> Vec<(usize, usize, f64, f64)> {
    let (bw, bh) = (b.width / block, b.height / block);
    let n = (block * block) as f64;
    let mut out = Vec::with_capacity(bw * bh);
    for by in 0..bh {
        for bx in 0..bw {
            let (mut p, mut q, mut v) = ([0.0f64; 3], [0.0f64; 3], [0.0f64; 3]);
            for y in by * block..(by + 1) * block {
                for x in bx * block..(bx + 1) * block {
                    for c in 0..3 {
                        p[c] += a.get(x, y)[c] as f64 / n;
                        q[c] += b.get(x, y)[c] as f64 / n;
                        v[c] += (var_a.get(x, y)[c] + var_b.get(x, y)[c]) as f64 / (n * n);
                    }
                }
            }
            let c = (0..3)
                .max_by(|&i, &j| {
                    let z = |c: usize| ((p[c] - q[c]) / v[c].sqrt().max(1e-12)).abs();
                    z(i).total_cmp(&z(j))
                })
                .unwrap();
            let z = (p[c] - q[c]) / v[c].sqrt().max(1e-12);
            out.push((bx, by, z, p[c] / q[c]));
        }
    }
    out
}
