//! `render(scene, ...)`: renders with the GIL released, on a separate thread; the calling
//! thread polls every 50 ms for Ctrl-C (`check_signals`), the cancel token and progress, and
//! calls the Python progress and preview callbacks itself (never from the rayon workers).
//! The images come back as bytes (`film_dict`).

use super::scene::{CancelToken, PyScene};
use super::settings::spec_dict;
use super::{panic_message, to_py};
use crate::command::{render_request, report, RenderRequest};
use crate::error::Error;
use crate::render::aov::Term;
use crate::render::film::{Film, Image};
use crate::render::{PreviewFn, ProgressFn, RenderOutput};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

/// Why a render run from Python stopped: an error of the core (a panic among them), or a
/// Python exception (Ctrl-C, or one that a progress or preview callback raised).
pub(super) enum Stopped {
    Core(Error),
    Py(PyErr),
}

impl Stopped {
    /// The Python exception, the core's errors made one by `map`.
    pub(super) fn into_py(self, map: fn(Error) -> PyErr) -> PyErr {
        match self {
            Stopped::Core(e) => map(e),
            Stopped::Py(e) => e,
        }
    }
}

type Outcome = std::thread::Result<Result<RenderOutput, Error>>;

/// Renders `request` on a separate thread with the GIL released. Every 50 ms the calling
/// thread takes the GIL back to check for Ctrl-C (which sets the request's cancel flag) and
/// to hand the latest progress to `callback` and the latest preview of a progressive render
/// to `preview` (`preview(bytes, width, height, passes)`). The request's own progress
/// callback (the command's bar) is called from the workers.
pub(super) fn run_blocking(
    py: Python<'_>,
    request: RenderRequest<'_>,
    callback: Option<&Bound<'_, PyAny>>,
    preview: Option<&Bound<'_, PyAny>>,
) -> Result<RenderOutput, Stopped> {
    let cancel = request
        .cancel
        .clone()
        .unwrap_or_else(|| Arc::new(AtomicBool::new(false)));
    let direct = request.progress.clone();
    type Preview = (Image, u32);
    let latest_preview: Arc<Mutex<Option<Preview>>> = Arc::default();
    let preview_fn: Option<Arc<PreviewFn>> = preview.map(|_| {
        let sink = latest_preview.clone();
        let f: Arc<PreviewFn> = Arc::new(move |film, passes| {
            if let Ok(mut g) = sink.lock() {
                *g = Some((film.combined(), passes));
            }
        });
        f
    });
    let latest: Arc<Mutex<Option<(f32, String)>>> = Arc::default();
    let sink = latest.clone();
    let progress: Arc<ProgressFn> = Arc::new(move |f: f32, phase: &str| {
        if let Some(d) = &direct {
            d(f, phase);
        }
        if let Ok(mut g) = sink.lock() {
            *g = Some((f, phase.to_string()));
        }
    });
    let done: (Mutex<Option<Outcome>>, Condvar) = (Mutex::new(None), Condvar::new());
    let report = |cb: &Bound<'_, PyAny>| -> PyResult<()> {
        let last = latest.lock().ok().and_then(|mut g| g.take());
        match last {
            Some((f, phase)) => cb.call1((f, phase)).map(|_| ()),
            None => Ok(()),
        }
    };
    let show = |cb: &Bound<'_, PyAny>| -> PyResult<()> {
        let last = latest_preview.lock().ok().and_then(|mut g| g.take());
        match last {
            Some((img, passes)) => cb
                .call1((image_bytes(py, &img), img.width, img.height, passes))
                .map(|_| ()),
            None => Ok(()),
        }
    };
    std::thread::scope(|s| {
        let flag = cancel.clone();
        let done_ref = &done;
        s.spawn(move || {
            let r = catch_unwind(AssertUnwindSafe(|| {
                render_request(RenderRequest {
                    progress: Some(progress),
                    cancel: Some(flag),
                    preview: preview_fn,
                    ..request
                })
            }));
            if let Ok(mut g) = done_ref.0.lock() {
                *g = Some(r);
            }
            done_ref.1.notify_all();
        });
        let mut pending: Option<PyErr> = None;
        let outcome: Outcome = loop {
            let got = py.detach(|| {
                let g = done.0.lock().ok()?;
                let (mut g, _) = done
                    .1
                    .wait_timeout_while(g, Duration::from_millis(50), |v| v.is_none())
                    .ok()?;
                g.take()
            });
            if let Some(o) = got {
                break o;
            }
            if pending.is_none() {
                if let Err(e) = py.check_signals() {
                    cancel.store(true, Ordering::Relaxed);
                    pending = Some(e);
                } else {
                    let shown = callback
                        .map_or(Ok(()), report)
                        .and_then(|_| preview.map_or(Ok(()), show));
                    if let Err(e) = shown {
                        cancel.store(true, Ordering::Relaxed);
                        pending = Some(e);
                    }
                }
            }
        };
        if let Some(e) = pending {
            return Err(Stopped::Py(e));
        }
        match outcome {
            Ok(Ok(out)) => {
                if let Some(cb) = callback {
                    report(cb).map_err(Stopped::Py)?;
                }
                if let Some(cb) = preview {
                    show(cb).map_err(Stopped::Py)?;
                }
                Ok(out)
            }
            Ok(Err(e)) => Err(Stopped::Core(e)),
            Err(p) => Err(Stopped::Core(Error::Internal(format!(
                "the renderer panicked: {}",
                panic_message(p.as_ref())
            )))),
        }
    })
}

/// Renders `scene`. Returns `{"width", "height", "terms": {name: bytes}, "combined": bytes,
/// "stats": json}`, images as float32 RGB rows top to bottom. `settings` is a JSON object of
/// render settings named as the schema names them (`settings_schema`); `null` is a default.
#[pyfunction]
#[pyo3(signature = (scene, settings="{}", *, progress=None, preview=None, cancel=None, pass_range=None))]
pub(super) fn render<'py>(
    py: Python<'py>,
    scene: &PyScene,
    settings: &str,
    progress: Option<Bound<'py, PyAny>>,
    preview: Option<Bound<'py, PyAny>>,
    cancel: Option<&CancelToken>,
    pass_range: Option<(u32, u32)>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut settings = crate::render::RenderSettings::from_json(settings).map_err(to_py)?;
    let flag = cancel
        .map(|c| c.flag.clone())
        .unwrap_or_else(|| Arc::new(AtomicBool::new(false)));
    if let Some((a, b)) = pass_range {
        if settings.mode != crate::render::settings::RenderMode::Pppm || a >= b {
            return Err(PyValueError::new_err(format!(
                "invalid render setting `pass_range`: ({a}, {b}) must be passes a < b of the \
                 pppm mode (mode=\"pppm\")"
            )));
        }
        settings.pass_range = Some((a, b));
    }
    let request = RenderRequest {
        cancel: Some(flag),
        ..RenderRequest::new(&scene.desc, settings)
    };
    let out = run_blocking(py, request, progress.as_ref(), preview.as_ref())
        .map_err(|s| s.into_py(to_py))?;
    let d = film_dict(py, &out.film)?;
    let stats = report::stats_json(&out.stats, None).map_err(to_py)?;
    d.set_item("stats", stats.to_string())?;
    if let Some(p) = &out.partial {
        d.set_item("partial", PyBytes::new(py, &p.to_bytes()))?;
    }
    Ok(d)
}

/// `{"width", "height", "terms": {name: bytes}, "error": bytes, "alpha": bytes (one float
/// per pixel), "aovs": [...], "cryptomatte": json, "combined": bytes}`.
pub(super) fn film_dict<'py>(py: Python<'py>, film: &Film) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("width", film.width)?;
    d.set_item("height", film.height)?;
    let terms = PyDict::new(py);
    for t in Term::ALL {
        terms.set_item(t.name(), image_bytes(py, film.term(t)))?;
    }
    d.set_item("terms", terms)?;
    d.set_item(crate::render::aov::ERROR_AOV, image_bytes(py, &film.error))?;
    let alpha: Vec<u8> = film.alpha.iter().flat_map(|a| a.to_le_bytes()).collect();
    d.set_item("alpha", PyBytes::new(py, &alpha))?;
    d.set_item("aovs", aov_list(py, film)?)?;
    d.set_item(
        "cryptomatte",
        serde_json::to_string(&film.cryptomatte)
            .map_err(|e| super::PhotonmapError::new_err(e.to_string()))?,
    )?;
    d.set_item("combined", image_bytes(py, &film.combined()))?;
    Ok(d)
}

/// Every image of the film beside the terms, in the list's order: spec dicts with `data`,
/// float32 little-endian bytes, the channels of each pixel together, rows top to bottom.
fn aov_list<'py>(py: Python<'py>, film: &Film) -> PyResult<Vec<Bound<'py, PyDict>>> {
    film.extra_images()
        .iter()
        .map(|(spec, data)| {
            let d = spec_dict(py, spec)?;
            let mut v = Vec::with_capacity(data.len() * 4);
            for x in data.iter() {
                v.extend_from_slice(&x.to_le_bytes());
            }
            d.set_item("data", PyBytes::new(py, &v))?;
            Ok(d)
        })
        .collect()
}

/// An RGB image as float32 little-endian bytes, rows top to bottom.
pub(super) fn image_bytes<'py>(py: Python<'py>, img: &Image) -> Bound<'py, PyBytes> {
    let mut v = Vec::with_capacity(img.data.len() * 12);
    for p in &img.data {
        for c in p {
            v.extend_from_slice(&c.to_le_bytes());
        }
    }
    PyBytes::new(py, &v)
}
