//! Merging the partial sums of blocks of pppm passes (`render --pass-range`, or the blocks of a
//! distributed render) into the frame's image: the same bits as the frame rendered in one
//! piece, whatever the blocks and the order they are summed in.

use super::output::{self, ImageFiles};
use super::report;
use crate::cli::MergeArgs;
use crate::error::Result;
use crate::render::partial::Partial;
use std::path::Path;

/// Partial sums from the bytes of partial-sum files; `what` names them in errors (`partial 2`).
pub fn from_bytes(partials: &[Vec<u8>], what: impl Fn(usize) -> String) -> Result<Vec<Partial>> {
    partials
        .iter()
        .enumerate()
        .map(|(i, b)| Partial::from_bytes(b, Path::new(&what(i))))
        .collect()
}

/// The sum of partial sums (in any order: the image and the stats are the same), without
/// checking that every pass is there: a step of a tree reduction.
pub fn sum(parts: Vec<Partial>) -> Result<Partial> {
    Partial::merge_all(&parts)
}

/// The sum of every block of a frame: errors, naming the passes, when one is missing.
pub fn complete(parts: Vec<Partial>) -> Result<Partial> {
    let merged = sum(parts)?;
    merged.check_complete()?;
    Ok(merged)
}

/// `photonmap merge`: reads the partial-sum files, merges them and writes the image, the PNG
/// and the stats. Returns the merged sums.
pub fn run_merge(args: &MergeArgs) -> Result<Partial> {
    let parts = args
        .partials
        .iter()
        .map(|p| Partial::load(p))
        .collect::<Result<Vec<_>>>()?;
    let merged = complete(parts)?;
    let files = ImageFiles {
        exr: &args.output,
        png: args.png.as_deref(),
        stats: args.stats.as_deref(),
    };
    output::write_image(files, &merged.film(), &report::merged_stats(&merged, None)?)?;
    Ok(merged)
}
