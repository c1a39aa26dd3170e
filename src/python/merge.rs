//! The pieces of a frame rendered apart, put together: partial sums of pppm passes merged
//! into the frame's image. The stats come from the core's reporting (`command::report`), as
//! the command's own do.

use super::render::film_dict;
use super::{caught, to_py};
use crate::command::{merge, report};
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
