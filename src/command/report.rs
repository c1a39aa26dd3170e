//! What a command reports: the stats JSON, of a render, of the merged partial sums of a pppm
//! frame, or of a Jensen frame assembled from tiles; and the lines printed after a command.
//!
//! A render's stats and a merge's are both a `RenderStats` (`RenderStats::of_partial` for a
//! merge) written by [`stats_json`], so they carry the same keys; a tiled frame's are its
//! tiles' stats combined by [`tile_stats`].

use crate::cli::{MergeArgs, RenderArgs};
use crate::error::{Error, Result};
use crate::render::adaptive::{Adaptive, AdaptiveStats};
use crate::render::partial::Partial;
use crate::render::{RenderOutput, RenderStats};
use serde_json::Value;

/// The stats JSON of a render: `stats` with each `f32` as its shortest decimal (0.7, not the
/// 0.699999988 of widening it), the figures it does not know (`RenderStats::unknown`) as
/// `null`, and a front end's import statistics under `import`.
pub fn stats_json(stats: &RenderStats, import: Option<&Value>) -> Result<Value> {
    // Through text, not `to_value`: that widens each `f32` to `f64`.
    let mut v: Value = serde_json::to_string(stats)
        .and_then(|t| serde_json::from_str(&t))
        .map_err(|e| Error::Internal(format!("the stats JSON: {e}")))?;
    let Some(obj) = v.as_object_mut() else {
        return Err(Error::Internal("the stats JSON is not an object".into()));
    };
    for k in stats.unknown {
        obj.insert(k.to_string(), Value::Null);
    }
    if let Some(imp) = import {
        obj.insert("import".into(), imp.clone());
    }
    Ok(v)
}

/// The stats JSON of the image of merged partial sums (`RenderStats::of_partial`), with the
/// keys of `extra` (a JSON object: a front end's own figures) added.
pub fn merged_stats(p: &Partial, extra: Option<&Value>) -> Result<Value> {
    let mut v = stats_json(&RenderStats::of_partial(p)?, None)?;
    if let (Some(obj), Some(Value::Object(e))) = (v.as_object_mut(), extra) {
        for (k, x) in e {
            obj.insert(k.clone(), x.clone());
        }
    }
    Ok(v)
}

/// The stats JSON of a Jensen frame rendered in tiles over the frame's photon maps, from its
/// tiles' stats (each as `Renderer::render_tile` gives it): the first tile's, with the sums of
/// what the tiles counted (non-finite samples, camera-pass seconds, work), and, given each
/// pixel's `rounds` of adaptive sampling (row-major over the `width` x `height` frame), its
/// figures over the frame and the camera rays they took.
pub fn tile_stats(
    tiles: &[Value],
    width: usize,
    height: usize,
    rounds: Option<&[u32]>,
) -> Result<Value> {
    let bad = |m: String| Error::Internal(format!("the tiles' stats: {m}"));
    let Some(first) = tiles.first() else {
        return Err(bad("no tiles".into()));
    };
    let int = |t: &Value, path: &[&str]| -> Result<u64> {
        let mut v = t;
        for k in path {
            v = &v[*k];
        }
        v.as_u64()
            .ok_or_else(|| bad(format!("`{}` is not a count", path.join("."))))
    };
    let mut out = first.clone();
    let non_finite = tiles
        .iter()
        .map(|t| int(t, &["non_finite_samples"]))
        .sum::<Result<u64>>()?;
    let render_seconds: f64 = tiles
        .iter()
        .map(|t| t["seconds"]["render"].as_f64().unwrap_or(0.0))
        .sum();
    let mut work = serde_json::Map::new();
    if let Some(w) = first["work"].as_object() {
        for k in w.keys() {
            let total = tiles
                .iter()
                .map(|t| int(t, &["work", k]))
                .sum::<Result<u64>>()?;
            work.insert(k.clone(), total.into());
        }
    }
    let spp = int(first, &["spp"])?;
    let mut extra = 0;
    if let (Some(r), Some(a)) = (rounds, first["adaptive"].as_object()) {
        if r.len() != width * height {
            return Err(bad(format!(
                "{} pixels' rounds for a {width}x{height} frame",
                r.len()
            )));
        }
        let stage = Adaptive {
            threshold: a["threshold"].as_f64().unwrap_or(0.0) as f32,
            max_factor: a["max_factor"].as_u64().unwrap_or(0) as u32,
        };
        extra = r.iter().map(|&n| n.saturating_sub(1) as u64 * spp).sum();
        let st = AdaptiveStats::of(stage, r, spp as u32, extra);
        let adaptive = &mut out["adaptive"];
        adaptive["pixels_refined"] = st.pixels_refined.into();
        adaptive["extra_samples"] = st.extra_samples.into();
        adaptive["mean_spp"] = st.mean_spp.into();
    }
    out["width"] = width.into();
    out["height"] = height.into();
    out["non_finite_samples"] = non_finite.into();
    out["seconds"]["render"] = render_seconds.into();
    if !work.is_empty() {
        out["work"] = Value::Object(work);
    }
    out["camera_rays"] = ((width * height) as u64 * spp + extra).into();
    Ok(out)
}

/// The lines printed after a render: what was written, and which terms are zero and why.
pub fn summary(args: &RenderArgs, out: &RenderOutput) -> String {
    let secs: f64 = out.stats.seconds.values().sum();
    if args.photon_maps_only {
        return format!(
            "wrote {} (photon maps: {}; {} irradiance-cache records; {secs:.2} s)",
            args.output.display(),
            out.stats
                .photons_stored
                .iter()
                .map(|(k, v)| format!("{k} {v}"))
                .collect::<Vec<_>>()
                .join(", "),
            out.stats.irradiance_cache_records
        );
    }
    let mut s = format!(
        "wrote {} ({}x{}, {} spp, {:.2} s)",
        args.output.display(),
        out.stats.width,
        out.stats.height,
        out.stats.spp,
        secs
    );
    for t in &out.stats.skipped {
        s.push_str(&format!("\n  {} is zero: {}", t.term, t.reason));
    }
    for w in &out.stats.warnings {
        s.push_str(&format!("\n  warning: {w}"));
    }
    s
}

/// The line printed after a merge.
pub fn merge_summary(args: &MergeArgs, merged: &Partial) -> String {
    format!(
        "wrote {} ({} passes from {} partial sums)",
        args.output.display(),
        merged.passes(),
        args.partials.len()
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn a_tiled_frame_sums_what_its_tiles_counted() {
        let tile = |non_finite: u64, render: f64, steps: u64| {
            json!({
                "spp": 2, "width": 4, "height": 2, "camera_rays": 0,
                "non_finite_samples": non_finite,
                "seconds": {"photons": 1.0, "render": render},
                "work": {"march_steps": steps, "caustic_lookups": 1},
                "adaptive": {"threshold": 0.5, "max_factor": 4, "pixels_refined": 0,
                             "extra_samples": 0, "mean_spp": 2.0},
            })
        };
        let tiles = [tile(1, 0.5, 10), tile(2, 0.25, 5)];
        let rounds = [1, 1, 2, 4, 1, 1, 1, 1];
        let st = tile_stats(&tiles, 4, 2, Some(&rounds)).unwrap();
        assert_eq!(st["non_finite_samples"], 3);
        assert_eq!(st["seconds"], json!({"photons": 1.0, "render": 0.75}));
        assert_eq!(st["work"], json!({"march_steps": 15, "caustic_lookups": 2}));
        // Two pixels refined: (2 - 1) + (4 - 1) further rounds of 2 samples.
        assert_eq!(st["adaptive"]["pixels_refined"], 2);
        assert_eq!(st["adaptive"]["extra_samples"], 8);
        assert_eq!(st["adaptive"]["mean_spp"], 3.0);
        assert_eq!(st["adaptive"]["threshold"], 0.5);
        assert_eq!(st["camera_rays"], 4 * 2 * 2 + 8);
        // Without adaptive sampling's rounds, its figures stay the first tile's.
        let st = tile_stats(&tiles, 4, 2, None).unwrap();
        assert_eq!(st["adaptive"], tiles[0]["adaptive"]);
        assert_eq!(st["camera_rays"], 16);
        assert!(tile_stats(&tiles, 4, 2, Some(&rounds[..3])).is_err());
        assert!(tile_stats(&[], 4, 2, None).is_err());
    }
}
