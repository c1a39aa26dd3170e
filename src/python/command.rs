//! `run_cli(argv, usd_loader, denoiser)`: the `photonmap` command. The core's one clap
//! definition parses `argv`, and the core's command runs it (`command::run_render`,
//! `command::run_merge`), with what Python brings: USD stages read by `usd_loader`, renders
//! run with the GIL released while Ctrl-C is watched for, and Open Image Denoise.

use super::render::{image_bytes, run_blocking, Stopped};
use super::scene::parse_scene;
use super::{caught, panic_message, PhotonmapError};
use crate::cli::{Cli, Command, MergeArgs};
use crate::command::{self, report, Denoiser, Failure, Frontend, LoadedScene, SceneRequest};
use crate::error::Error;
use crate::render::RenderOutput;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// The `photonmap` command: parses `argv` (without the program name) with the core's clap
/// definition, reads USD stages through `usd_loader(path, frame, camera, purposes, strict)`
/// (which returns `(ir_json, import_stats_json)`), renders each frame with the progress bar on
/// stderr, and writes the EXR, PNG and stats. With `--denoise`, `denoiser.check()` runs first
/// (it raises when the denoiser is missing), and after each render `denoiser(width, height,
/// {term: bytes}, albedo, normal)` returns the denoised terms (`{term: bytes}`) and what
/// denoised them (`{key: text}`, into the stats and the EXR metadata). Returns the exit
/// status; errors of the loader, and Ctrl-C, are raised as they are.
#[pyfunction]
#[pyo3(signature = (argv, usd_loader=None, denoiser=None))]
pub(super) fn run_cli(
    py: Python<'_>,
    argv: Vec<String>,
    usd_loader: Option<Bound<'_, PyAny>>,
    denoiser: Option<Bound<'_, PyAny>>,
) -> PyResult<i32> {
    let cli = match Cli::parse_args(std::iter::once("photonmap".to_string()).chain(argv)) {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return Ok(e.exit_code());
        }
    };
    let args = match cli.command {
        Command::Render(args) => args,
        Command::Merge(m) => return Ok(merge(py, &m)),
    };
    // A Python exception met on the way (the loader's, Ctrl-C), raised as it is.
    let py_err: RefCell<Option<PyErr>> = Default::default();
    let keep = |e: PyErr| {
        *py_err.borrow_mut() = Some(e);
        Error::Cancelled
    };
    let frontend = Frontend {
        scene_loader: Some(Box::new(usd_load_fn(usd_loader.as_ref(), &py_err))),
        runner: Some(Box::new(|req| {
            run_blocking(py, req, None, None).map_err(|s| match s {
                Stopped::Core(e) => e,
                Stopped::Py(e) => keep(e),
            })
        })),
        denoiser: Some(Box::new(CliDenoiser {
            py,
            denoiser: denoiser.as_ref(),
        })),
        cancel: Some(Arc::new(AtomicBool::new(false))),
    };
    let result = catch_unwind(AssertUnwindSafe(|| command::run_render(&args, frontend)))
        .unwrap_or_else(|p| {
            Err(Failure {
                message: format!(
                    "internal error: the renderer panicked: {}",
                    panic_message(p.as_ref())
                ),
                status: 1,
            })
        });
    if let Some(e) = py_err.into_inner() {
        return Err(e);
    }
    match result {
        Ok(()) => Ok(0),
        Err(f) => {
            eprintln!("photonmap: error: {f}");
            Ok(f.status)
        }
    }
}

/// `photonmap merge`, with the GIL released; returns the exit status.
fn merge(py: Python<'_>, m: &MergeArgs) -> i32 {
    match py.detach(|| caught(|| command::run_merge(m))) {
        Ok(p) => {
            if !m.quiet {
                eprintln!("{}", report::merge_summary(m, &p));
            }
            0
        }
        Err(e) => {
            eprintln!("photonmap: error: {}", e.for_cli());
            1
        }
    }
}

/// The scene reader of the command: USD stages through the Python `usd_loader(path, frame,
/// camera, purposes, strict)`, which returns `(ir_json, import_stats_json)`. An exception of
/// the loader is kept in `py_err`, to be raised as it is.
pub(super) fn usd_load_fn<'a, 'py>(
    usd_loader: Option<&'a Bound<'py, PyAny>>,
    py_err: &'a RefCell<Option<PyErr>>,
) -> impl FnMut(&SceneRequest) -> Result<LoadedScene, Error> + 'a {
    move |req: &SceneRequest| -> Result<LoadedScene, Error> {
        let Some(loader) = usd_loader else {
            return Err(Error::io(req.path, "no USD reader available"));
        };
        let r = loader
            .call1((
                req.path.to_path_buf(),
                req.frame,
                req.camera,
                req.purposes.clone(),
                req.strict,
            ))
            .and_then(|v| v.extract::<(String, Option<String>)>());
        match r {
            Ok((ir, stats)) => {
                let desc = parse_scene(&ir)?;
                let import_stats = stats.and_then(|s| serde_json::from_str(&s).ok());
                Ok(LoadedScene { desc, import_stats })
            }
            Err(e) => {
                let msg = e.to_string();
                *py_err.borrow_mut() = Some(e);
                Err(Error::io(req.path, msg))
            }
        }
    }
}

/// The command's denoiser: the Python `denoiser` (see `run_cli`).
struct CliDenoiser<'a, 'py> {
    py: Python<'py>,
    denoiser: Option<&'a Bound<'py, PyAny>>,
}

impl Denoiser for CliDenoiser<'_, '_> {
    fn check(&mut self) -> Result<(), String> {
        match self.denoiser {
            Some(d) => d
                .call_method0("check")
                .map(|_| ())
                .map_err(|e| e.value(self.py).to_string()),
            None => Err("no denoiser available".into()),
        }
    }

    fn denoise(&mut self, out: &mut RenderOutput) -> Result<(), String> {
        let Some(d) = self.denoiser else {
            return Err("no denoiser available".into());
        };
        denoise_film(self.py, d, out).map_err(|e| e.value(self.py).to_string())
    }
}

/// Denoises a render's terms through the Python `denoiser`: the terms it returns replace the
/// film's, and what it reports goes into the stats.
fn denoise_film(
    py: Python<'_>,
    denoiser: &Bound<'_, PyAny>,
    out: &mut RenderOutput,
) -> PyResult<()> {
    let film = &mut out.film;
    let (Some(albedo), Some(normal)) = (
        film.aov(crate::render::aov::ALBEDO_AOV),
        film.aov(crate::render::aov::NORMAL_AOV),
    ) else {
        return Err(PhotonmapError::new_err(
            "internal error: denoising without the albedo and normal guides",
        ));
    };
    let floats = |v: &[f32]| {
        let mut b = Vec::with_capacity(v.len() * 4);
        for x in v {
            b.extend_from_slice(&x.to_le_bytes());
        }
        PyBytes::new(py, &b)
    };
    let terms = PyDict::new(py);
    for t in crate::render::aov::DENOISED_TERMS {
        terms.set_item(t.name(), image_bytes(py, film.term(t)))?;
    }
    let (albedo, normal) = (floats(&albedo.data), floats(&normal.data));
    let (den, info): (BTreeMap<String, Vec<u8>>, BTreeMap<String, String>) = denoiser
        .call1((film.width, film.height, terms, albedo, normal))?
        .extract()?;
    for t in crate::render::aov::DENOISED_TERMS {
        let Some(b) = den.get(t.name()) else {
            return Err(PhotonmapError::new_err(format!(
                "the denoiser returned no `{}`",
                t.name()
            )));
        };
        let img = &mut film.terms[t.index()];
        if b.len() != img.data.len() * 12 {
            return Err(PhotonmapError::new_err(format!(
                "the denoiser returned {} bytes for `{}`, expected {}",
                b.len(),
                t.name(),
                img.data.len() * 12
            )));
        }
        for (px, c) in img.data.iter_mut().zip(b.chunks_exact(12)) {
            for k in 0..3 {
                px[k] = f32::from_le_bytes([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]]);
            }
        }
    }
    out.stats.denoise = serde_json::to_value(info).ok();
    Ok(())
}
