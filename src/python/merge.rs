//! The pieces of a frame rendered apart, put together: partial sums of pppm passes merged
//! into the frame's image, and the stats of a Jensen frame rendered in tiles. The stats come
//! from the core's reporting (`command::report`), as the command's own do.

use super::render::film_dict;
use super::{caught, to_py};
use crate::command::{merge, report};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

fn partial_name(i: usize) -> String {
    format!("partial {i}")
}

/// Merges partial sums of pppm passes (the bytes of partial-sum files, every block of one
/// frame; in any order) into the frame's image: the dict of `render`, with `partial` the
/// merged sums.
#[pyfunction]
pub(super) fn merge_partials<'py>(
    py: Python<'py>,
    partials: Vec<Vec<u8>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (merged, stats) = py
        .detach(|| {
            caught(|| {
                let merged = merge::complete(merge::from_bytes(&partials, partial_name)?)?;
                let stats = report::merged_stats(&merged, None)?;
                Ok((merged, stats))
            })
        })
        .map_err(to_py)?;
    let d = film_dict(py, &merged.film())?;
    d.set_item("stats", stats.to_string())?;
    d.set_item("partial", PyBytes::new(py, &merged.to_bytes()))?;
    Ok(d)
}

/// The sum of partial sums (bytes of partial-sum files, in any order) as the bytes of one,
/// without checking that every pass is there: a step of a tree reduction.
#[pyfunction]
pub(super) fn add_partials<'py>(
    py: Python<'py>,
    partials: Vec<Vec<u8>>,
) -> PyResult<Bound<'py, PyBytes>> {
    let bytes = py
        .detach(|| {
            caught(|| Ok(merge::sum(merge::from_bytes(&partials, partial_name)?)?.to_bytes()))
        })
        .map_err(to_py)?;
    Ok(PyBytes::new(py, &bytes))
}

/// The stats JSON of a Jensen frame of `width` x `height` rendered in tiles, from the tiles'
/// stats (JSON, as `Job.tile_finish` returns them) and, with adaptive sampling, each pixel's
/// rounds (little-endian u32, row-major over the frame, as `Job.adaptive_rounds` returns
/// them): see `command::report::tile_stats`.
#[pyfunction]
#[pyo3(signature = (tiles, width, height, rounds=None))]
pub(super) fn tile_stats(
    tiles: Vec<String>,
    width: usize,
    height: usize,
    rounds: Option<Vec<u8>>,
) -> PyResult<String> {
    let tiles = tiles
        .iter()
        .enumerate()
        .map(|(i, t)| {
            serde_json::from_str(t)
                .map_err(|e| PyValueError::new_err(format!("the stats of tile {i}: {e}")))
        })
        .collect::<PyResult<Vec<serde_json::Value>>>()?;
    if rounds.as_ref().is_some_and(|b| b.len() % 4 != 0) {
        return Err(PyValueError::new_err(
            "rounds: not a whole number of little-endian u32",
        ));
    }
    let rounds: Option<Vec<u32>> = rounds.map(|b| {
        b.chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    });
    let st =
        caught(|| report::tile_stats(&tiles, width, height, rounds.as_deref())).map_err(to_py)?;
    Ok(st.to_string())
}
