//! What a command reports: the stats JSON, of a render or of the merged partial sums of a
//! pppm frame; and the lines printed after a command.
//!
//! A render's stats and a merge's are both a `RenderStats` (`RenderStats::of_partial` for a
//! merge) written by [`stats_json`], so they carry the same keys.

use crate::cli::{MergeArgs, RenderArgs};
use crate::error::{Error, Result};
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
