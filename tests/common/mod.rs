//! Helpers shared by the integration tests (`mod common;`).
#![allow(dead_code)]

use photonmap::io::scene_json;
use photonmap::render::aov::{Term, TermMask};
use photonmap::render::film::Image;
use photonmap::render::settings::FilterName;
use photonmap::render::{RenderOutput, RenderSettings, Renderer};
use photonmap::scene::{Scene, SceneDesc};
use std::path::PathBuf;

pub mod compare;

pub fn data(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(path)
}

pub fn load_scene(name: &str) -> SceneDesc {
    scene_json::load(data(&format!("scenes/{name}.json"))).expect("test scene loads")
}

pub fn render(desc: &SceneDesc, spp: u32, seed: u64, threads: usize) -> RenderOutput {
    render_terms(desc, spp, seed, threads, TermMask::ALL)
}

/// Renders with explicit settings.
pub fn render_settings(desc: &SceneDesc, settings: RenderSettings) -> RenderOutput {
    let scene = Scene::build(desc).expect("scene builds");
    Renderer::new(&scene)
        .settings(settings)
        .render()
        .expect("render succeeds")
}

/// relMSE of block means (block x block pixels), which keeps a path-traced reference's own
/// noise (fireflies of its caustic paths) out of a comparison of low-frequency bias.
pub fn block_rel_mse(a: &Image, b: &Image, block: usize) -> f64 {
    block_rel_mse_trimmed(a, b, block, 0)
}

/// [`block_rel_mse`] without the `drop` worst blocks: a single firefly (a rare specular path
/// to a light, seen at a few samples per pixel) can outweigh every other block.
pub fn block_rel_mse_trimmed(a: &Image, b: &Image, block: usize, drop: usize) -> f64 {
    let (bw, bh) = (a.width / block, a.height / block);
    let mut errs = Vec::with_capacity(bw * bh);
    for by in 0..bh {
        for bx in 0..bw {
            let (mut p, mut q) = ([0.0f64; 3], [0.0f64; 3]);
            for y in by * block..(by + 1) * block {
                for x in bx * block..(bx + 1) * block {
                    for c in 0..3 {
                        p[c] += a.get(x, y)[c] as f64;
                        q[c] += b.get(x, y)[c] as f64;
                    }
                }
            }
            let n = (block * block) as f64;
            let mut e = 0.0;
            for c in 0..3 {
                e += ((p[c] - q[c]) / n).powi(2) / ((q[c] / n).powi(2) + REL_EPS as f64);
            }
            errs.push(e / 3.0);
        }
    }
    errs.sort_by(f64::total_cmp);
    let kept = &errs[..errs.len().saturating_sub(drop)];
    kept.iter().sum::<f64>() / kept.len().max(1) as f64
}

/// Renders only the given terms (the others' estimators do not run at all).
pub fn render_terms(
    desc: &SceneDesc,
    spp: u32,
    seed: u64,
    threads: usize,
    terms: TermMask,
) -> RenderOutput {
    let scene = Scene::build(desc).expect("scene builds");
    let settings = RenderSettings {
        spp,
        seed,
        threads,
        terms,
        filter: FilterName::Box,
        ..Default::default()
    };
    Renderer::new(&scene)
        .settings(settings)
        .render()
        .expect("render succeeds")
}

/// Sum of the given terms.
pub fn sum_terms(out: &RenderOutput, terms: &[Term]) -> Image {
    let mut img = Image::new(out.film.width, out.film.height);
    for t in terms {
        for (a, b) in img.data.iter_mut().zip(&out.film.term(*t).data) {
            for c in 0..3 {
                a[c] += b[c];
            }
        }
    }
    img
}

/// Per-pixel mean and squared standard error of the mean over independent batches.
pub fn mean_and_var(batches: &[Image]) -> (Image, Image) {
    let k = batches.len() as f32;
    let (w, h) = (batches[0].width, batches[0].height);
    let mut mean = Image::new(w, h);
    let mut var = Image::new(w, h);
    for i in 0..w * h {
        for c in 0..3 {
            let m = batches.iter().map(|b| b.data[i][c]).sum::<f32>() / k;
            let s2 = batches
                .iter()
                .map(|b| (b.data[i][c] - m).powi(2))
                .sum::<f32>()
                / (k - 1.0);
            mean.data[i][c] = m;
            var.data[i][c] = s2 / k;
        }
    }
    (mean, var)
}

/// relMSE = mean over pixels and channels of (a - b)^2 / (b^2 + eps).
pub const REL_EPS: f32 = 1e-2;

pub fn rel_mse(a: &Image, b: &Image) -> f64 {
    let mut s = 0.0f64;
    for (p, q) in a.data.iter().zip(&b.data) {
        for c in 0..3 {
            let d = (p[c] - q[c]) as f64;
            s += d * d / ((q[c] as f64).powi(2) + REL_EPS as f64);
        }
    }
    s / (a.data.len() * 3) as f64
}

/// The relMSE that noise alone would give: mean of (var_a + var_b) / (b^2 + eps).
pub fn expected_rel_mse(var_a: &Image, var_b: &Image, b: &Image) -> f64 {
    let mut s = 0.0f64;
    for i in 0..b.data.len() {
        for c in 0..3 {
            s += (var_a.data[i][c] + var_b.data[i][c]) as f64
                / ((b.data[i][c] as f64).powi(2) + REL_EPS as f64);
        }
    }
    s / (b.data.len() * 3) as f64
}
