//! The Python module `photonmap._core` (feature `python`):
//!
//! - `scene`: `Scene`, a validated scene IR, and `CancelToken`;
//! - `render`: `render(scene, ...)`, with the GIL released;
//! - `merge`: `merge_partials`, `add_partials` and `tile_stats`, the pieces of a frame
//!   rendered apart put together;
//! - `command`: `run_cli(argv, usd_loader, denoiser)`, the `photonmap` command;
//! - `job`: `Job`, a command split into pieces for other processes (`photonmap.distributed`);
//! - `settings`: the presets, the settings' schema, the AOV list, the Cryptomatte header.
//!
//! No panic crosses this boundary: the render runs under `catch_unwind`, as does every call
//! into the core (parsing, validation, scene loading, output writing), and a panic becomes
//! `photonmap.PhotonmapError` ("internal error: the renderer panicked: ..."), an ordinary
//! `Exception`, where pyo3 alone would raise `PanicException`, a `BaseException`.

mod command;
mod job;
mod merge;
mod pointer;
mod render;
mod scene;
mod settings;

use crate::error::Error;
use crate::render::aov::Term;
use crate::render::Quality;
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::any::Any;
use std::panic::{catch_unwind, AssertUnwindSafe};

create_exception!(
    photonmap,
    PhotonmapError,
    PyRuntimeError,
    "An error of the renderer (not of the scene): I/O, internal errors."
);
create_exception!(
    photonmap,
    SceneError,
    PyValueError,
    "The scene is invalid; the message names the field (a JSON pointer) and the object."
);
create_exception!(
    photonmap,
    RenderCancelled,
    PhotonmapError,
    "The render was cancelled (cancel token or Ctrl-C)."
);

fn to_py(e: Error) -> PyErr {
    match e {
        Error::InvalidScene { .. } | Error::Json { .. } => SceneError::new_err(e.to_string()),
        Error::InvalidSetting { .. } => PyValueError::new_err(e.to_string()),
        Error::UnknownSetting { .. } => pyo3::exceptions::PyTypeError::new_err(e.to_string()),
        Error::Cancelled => RenderCancelled::new_err(e.to_string()),
        _ => PhotonmapError::new_err(e.to_string()),
    }
}

fn panic_message(p: &(dyn Any + Send)) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".to_string()
    }
}

/// Runs a call into the core, turning a panic into `Error::Internal` (so `PhotonmapError`).
fn caught<T>(f: impl FnOnce() -> Result<T, Error>) -> Result<T, Error> {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|p| {
        Err(Error::Internal(format!(
            "the renderer panicked: {}",
            panic_message(p.as_ref())
        )))
    })
}

/// Panics inside the guarded boundary, to test that a panic becomes an exception.
#[pyfunction]
fn _panic_for_test(py: Python<'_>) -> PyResult<()> {
    let r = py.detach(|| catch_unwind(|| panic!("test panic")));
    match r {
        Ok(()) => Ok(()),
        Err(p) => Err(PhotonmapError::new_err(format!(
            "internal error: the renderer panicked: {}",
            panic_message(p.as_ref())
        ))),
    }
}

#[pymodule]
#[pyo3(name = "_core")]
fn core_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add(
        "TERMS",
        Term::ALL.iter().map(|t| t.name()).collect::<Vec<_>>(),
    )?;
    m.add(
        "PASS_NAMES",
        Term::ALL.iter().map(|t| t.pass_name()).collect::<Vec<_>>(),
    )?;
    m.add("ERROR_AOV", crate::render::aov::ERROR_AOV)?;
    m.add("ERROR_PASS", crate::render::aov::ERROR_PASS)?;
    m.add(
        "QUALITIES",
        Quality::ALL.iter().map(|q| q.name()).collect::<Vec<_>>(),
    )?;
    m.add("DEFAULT_SCENE_JSON", crate::scene::DEFAULT_SCENE_JSON)?;
    m.add(
        "GRAPH_NODES",
        crate::materials::graph::compile::node_specs().to_string(),
    )?;
    m.add("PhotonmapError", py.get_type::<PhotonmapError>())?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("RenderCancelled", py.get_type::<RenderCancelled>())?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<scene::CancelToken>()?;
    m.add_class::<job::Job>()?;
    m.add_function(wrap_pyfunction!(merge::merge_partials, m)?)?;
    m.add_function(wrap_pyfunction!(merge::add_partials, m)?)?;
    m.add_function(wrap_pyfunction!(merge::tile_stats, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(command::run_cli, m)?)?;
    m.add_function(wrap_pyfunction!(settings::preset, m)?)?;
    m.add_function(wrap_pyfunction!(settings::settings_schema, m)?)?;
    m.add_function(wrap_pyfunction!(settings::aov_specs, m)?)?;
    m.add_function(wrap_pyfunction!(settings::cryptomatte_header, m)?)?;
    m.add(
        "DENOISED_TERMS",
        crate::render::aov::DENOISED_TERMS
            .map(|t| t.name())
            .to_vec(),
    )?;
    m.add("NOISY_SUFFIX", crate::render::aov::NOISY_SUFFIX)?;
    m.add_function(wrap_pyfunction!(_panic_for_test, m)?)?;
    Ok(())
}
