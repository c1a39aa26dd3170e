//! The Python module `photonmap._core` (feature `python`).
//!
//! - `Scene`: a validated scene IR, from JSON text, a JSON file, the embedded default, or JSON plus
//!   raw little-endian mesh buffers (`from_parts`, fed by numpy on the Python side).
//! - `render(scene, ...)`: renders with the GIL released, on a separate thread; the calling
//!   thread polls every 50 ms for Ctrl-C (`check_signals`), the cancel token and progress, and
//!   calls the Python progress callback itself (never from the rayon workers).
//! - `run_cli(argv, usd_loader)`: the `photonmap` command: the core's one clap definition parses
//!   `argv`; USD stages are read by the Python `usd_loader`.
//!
//! No panic crosses this boundary: the render runs under `catch_unwind`, as does every call
//! into the core (parsing, validation, scene loading, output writing), and a panic becomes
//! `photonmap.PhotonmapError` ("internal error: the renderer panicked: ..."), an ordinary
//! `Exception`, where pyo3 alone would raise `PanicException`, a `BaseException`.

mod job;
mod pointer;

use crate::cli::{self, Cli, Command, LoadedScene, SceneRequest};
use crate::error::Error;
use crate::io::scene_json;
use crate::render::aov::{AovSpec, Term};
use crate::render::{ProgressFn, Quality, RenderOutput, RenderSettings};
use crate::scene::desc::SceneDesc;
use clap::Parser;
use pyo3::create_exception;
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::any::Any;
use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

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

/// Parses and validates JSON scene text; parse errors are given the JSON pointer of the field.
fn parse_scene(text: &str) -> Result<SceneDesc, Error> {
    scene_json::from_str(text).map_err(|e| match e {
        Error::Json {
            line,
            column,
            message,
        } => {
            let ptr = pointer::pointer_at(text, line, column);
            let object = pointer::object_name(text, &ptr);
            Error::scene(ptr, &object, message)
        }
        other => other,
    })
}

/// A validated scene IR.
#[pyclass(module = "photonmap._core", name = "Scene", frozen)]
pub struct PyScene {
    desc: SceneDesc,
}

/// One mesh's buffers: positions (f32 x3), indices (u32 x3), normals (f32 x3), uvs (f32 x2),
/// per-triangle material ids (u32), all little-endian.
type MeshBuffers<'py> = (
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Option<Bound<'py, PyBytes>>,
    Option<Bound<'py, PyBytes>>,
    Option<Bound<'py, PyBytes>>,
);

fn f32s(b: &[u8]) -> impl Iterator<Item = f32> + '_ {
    b.chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
}
fn u32s(b: &[u8]) -> impl Iterator<Item = u32> + '_ {
    b.chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
}
fn check_len(b: &[u8], stride: usize, ptr: &str, name: &str) -> Result<(), Error> {
    if b.len() % stride == 0 {
        Ok(())
    } else {
        Err(Error::scene(
            ptr,
            name,
            format!(
                "buffer of {} bytes is not a whole number of {stride}-byte items",
                b.len()
            ),
        ))
    }
}

#[pymethods]
impl PyScene {
    /// Parses and validates scene IR JSON text.
    #[staticmethod]
    fn from_json(py: Python<'_>, text: &str) -> PyResult<Self> {
        let desc = py.detach(|| caught(|| parse_scene(text))).map_err(to_py)?;
        Ok(PyScene { desc })
    }

    /// Reads a `.json` scene IR file.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let text = std::fs::read_to_string(&path)
            .map_err(|e| PhotonmapError::new_err(format!("{}: {e}", path.display())))?;
        let desc = py
            .detach(|| caught(|| parse_scene(&text)))
            .map_err(|e| match e {
                Error::InvalidScene {
                    pointer,
                    object,
                    message,
                } => Error::scene(
                    pointer,
                    &object,
                    format!("{message} (in {})", path.display()),
                ),
                other => other,
            })
            .map_err(to_py)?;
        Ok(PyScene { desc })
    }

    /// The embedded default scene (a Cornell box with a glass and a mirror sphere).
    #[staticmethod]
    fn default() -> PyResult<Self> {
        let desc = caught(|| Ok(crate::scene::default_scene())).map_err(to_py)?;
        Ok(PyScene { desc })
    }

    /// Scene IR JSON whose `meshes` entries leave `positions`/`indices` (and optionally
    /// `normals`, `uvs`, `material_indices`) to `buffers`, one tuple per mesh, in order.
    #[staticmethod]
    fn from_parts(py: Python<'_>, ir_json: &str, buffers: Vec<MeshBuffers<'_>>) -> PyResult<Self> {
        let mut desc: SceneDesc = serde_json::from_str(ir_json).map_err(|e| {
            let ptr = pointer::pointer_at(ir_json, e.line(), e.column());
            let object = pointer::object_name(ir_json, &ptr);
            to_py(Error::scene(ptr, &object, e.to_string()))
        })?;
        if buffers.len() != desc.meshes.len() {
            return Err(to_py(Error::scene(
                "/meshes",
                "",
                format!(
                    "{} meshes but {} buffer sets",
                    desc.meshes.len(),
                    buffers.len()
                ),
            )));
        }
        for (i, (m, (pos, idx, nrm, uv, mat))) in desc.meshes.iter_mut().zip(&buffers).enumerate() {
            let p = format!("/meshes/{i}");
            let (pos, idx) = (pos.as_bytes(), idx.as_bytes());
            check_len(pos, 12, &format!("{p}/positions"), &m.name).map_err(to_py)?;
            check_len(idx, 12, &format!("{p}/indices"), &m.name).map_err(to_py)?;
            let v: Vec<f32> = f32s(pos).collect();
            m.positions = v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            let v: Vec<u32> = u32s(idx).collect();
            m.indices = v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            if let Some(n) = nrm {
                check_len(n.as_bytes(), 12, &format!("{p}/normals"), &m.name).map_err(to_py)?;
                let v: Vec<f32> = f32s(n.as_bytes()).collect();
                m.normals = Some(v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect());
            }
            if let Some(t) = uv {
                check_len(t.as_bytes(), 8, &format!("{p}/uvs"), &m.name).map_err(to_py)?;
                let v: Vec<f32> = f32s(t.as_bytes()).collect();
                m.uvs = Some(v.chunks_exact(2).map(|c| [c[0], c[1]]).collect());
            }
            if let Some(t) = mat {
                check_len(t.as_bytes(), 4, &format!("{p}/material_indices"), &m.name)
                    .map_err(to_py)?;
                m.material_indices = Some(u32s(t.as_bytes()).collect());
            }
        }
        py.detach(|| caught(|| crate::scene::validate(&desc)))
            .map_err(to_py)?;
        Ok(PyScene { desc })
    }

    /// The scene IR as JSON text.
    fn to_json(&self) -> PyResult<String> {
        caught(|| Ok(scene_json::to_string(&self.desc))).map_err(to_py)
    }

    #[getter]
    fn width(&self) -> u32 {
        self.desc.film.width
    }

    #[getter]
    fn height(&self) -> u32 {
        self.desc.film.height
    }

    /// Numbers of meshes, instances, triangles, materials, lights and textures.
    fn counts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let tris: usize = self.desc.meshes.iter().map(|m| m.indices.len()).sum();
        d.set_item("meshes", self.desc.meshes.len())?;
        d.set_item("instances", self.desc.instances.len())?;
        d.set_item("triangles", tris)?;
        d.set_item("materials", self.desc.materials.len())?;
        d.set_item("lights", self.desc.lights.len())?;
        d.set_item("textures", self.desc.textures.len())?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!(
            "<photonmap.Scene {}x{}, {} meshes, {} lights>",
            self.desc.film.width,
            self.desc.film.height,
            self.desc.meshes.len(),
            self.desc.lights.len()
        )
    }
}

/// A flag that cancels the renders it is given to, from any thread.
#[pyclass(module = "photonmap._core", frozen)]
pub struct CancelToken {
    flag: Arc<AtomicBool>,
}

#[pymethods]
impl CancelToken {
    #[new]
    fn new() -> Self {
        CancelToken {
            flag: Arc::new(AtomicBool::new(false)),
        }
    }
    /// Asks every render using this token to stop; they raise `RenderCancelled` within ~50 ms.
    fn cancel(&self) {
        self.flag.store(true, Ordering::Relaxed);
    }
    fn reset(&self) {
        self.flag.store(false, Ordering::Relaxed);
    }
    #[getter]
    fn cancelled(&self) -> bool {
        self.flag.load(Ordering::Relaxed)
    }
}

type Outcome = std::thread::Result<Result<RenderOutput, Error>>;

/// Renders on a separate thread with the GIL released. Every 50 ms the calling thread takes the
/// GIL back to check for Ctrl-C and to report progress to `callback`; `direct` progress (the
/// CLI's bar) is called from the workers.
#[allow(clippy::too_many_arguments)]
fn render_blocking(
    py: Python<'_>,
    desc: &SceneDesc,
    settings: RenderSettings,
    direct: Option<Arc<ProgressFn>>,
    callback: Option<&Bound<'_, PyAny>>,
    preview: Option<&Bound<'_, PyAny>>,
    cancel: Arc<AtomicBool>,
    map_err: fn(Error) -> PyErr,
    output_time: Option<Arc<crate::render::OutputTimeFn>>,
) -> PyResult<RenderOutput> {
    run_blocking(
        py,
        cli::RenderRequest {
            output_time,
            ..cli::RenderRequest::new(desc, settings)
        },
        direct,
        callback,
        preview,
        cancel,
        map_err,
    )
}

/// As [`render_blocking`], for a whole request (photon maps to reuse or keep).
#[allow(clippy::too_many_arguments)]
fn run_blocking(
    py: Python<'_>,
    request: cli::RenderRequest<'_>,
    direct: Option<Arc<ProgressFn>>,
    callback: Option<&Bound<'_, PyAny>>,
    preview: Option<&Bound<'_, PyAny>>,
    cancel: Arc<AtomicBool>,
    map_err: fn(Error) -> PyErr,
) -> PyResult<RenderOutput> {
    // The latest preview of a progressive render (beauty, passes), handed to `preview` by the
    // calling thread as `preview(bytes, width, height, passes)`.
    type Preview = (crate::render::film::Image, u32);
    let latest_preview: Arc<Mutex<Option<Preview>>> = Arc::default();
    let preview_fn: Option<Arc<crate::render::PreviewFn>> = preview.map(|_| {
        let sink = latest_preview.clone();
        let f: Arc<crate::render::PreviewFn> = Arc::new(move |film, passes| {
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
                cli::render_request(cli::RenderRequest {
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
            return Err(e);
        }
        match outcome {
            Ok(Ok(out)) => {
                if let Some(cb) = callback {
                    report(cb)?;
                }
                if let Some(cb) = preview {
                    show(cb)?;
                }
                Ok(out)
            }
            Ok(Err(e)) => Err(map_err(e)),
            Err(p) => Err(PhotonmapError::new_err(format!(
                "internal error: the renderer panicked: {}",
                panic_message(p.as_ref())
            ))),
        }
    })
}

/// A spec of the AOV list as a dict: `name`, `pass_name`, `kind`, `channels`, `chan_id`,
/// `pass_type` (the last two as Blender's `register_pass` takes them).
fn spec_dict<'py>(py: Python<'py>, spec: &AovSpec) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", &spec.name)?;
    d.set_item("pass_name", &spec.pass_name)?;
    d.set_item(
        "kind",
        serde_json::to_value(spec.kind)
            .ok()
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_default(),
    )?;
    d.set_item("channels", spec.channels().to_vec())?;
    d.set_item("chan_id", spec.kind.chan_id())?;
    d.set_item("pass_type", spec.kind.pass_type())?;
    Ok(d)
}

/// Every image of the film beside the terms, in the list's order: spec dicts with `data`,
/// float32 little-endian bytes, the channels of each pixel together, rows top to bottom.
fn aov_list<'py>(
    py: Python<'py>,
    film: &crate::render::film::Film,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
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

/// The AOVs beside the terms that a render with `settings` (the `render` keywords as JSON)
/// writes, for a scene whose IR names the light groups `light_groups` (the `default` group
/// is added as the scene build adds it), in output order, as spec dicts (see `spec_dict`):
/// Blender registers its passes from it.
#[pyfunction]
#[pyo3(signature = (settings="{}", light_groups=Vec::new()))]
fn aov_specs<'py>(
    py: Python<'py>,
    settings: &str,
    light_groups: Vec<String>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let options = crate::render::RenderOptions::from_json(settings).map_err(to_py)?;
    options
        .settings()
        .aovs
        .aovs(&crate::render::aov::light_group_names(&light_groups))
        .iter()
        .map(|spec| spec_dict(py, spec))
        .collect()
}

/// The EXR header attributes of Cryptomatte manifests (`{type name: [names]}` as JSON), each
/// layer named `prefix` + type name: `{"cryptomatte/<key>/name": ..., ...}`.
#[pyfunction]
#[pyo3(signature = (manifests, prefix=""))]
fn cryptomatte_header(manifests: &str, prefix: &str) -> PyResult<BTreeMap<String, String>> {
    let m: BTreeMap<String, Vec<String>> =
        serde_json::from_str(manifests).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(crate::render::compositing::cryptomatte_header(&m, prefix))
}

fn image_bytes<'py>(py: Python<'py>, img: &crate::render::film::Image) -> Bound<'py, PyBytes> {
    let mut v = Vec::with_capacity(img.data.len() * 12);
    for p in &img.data {
        for c in p {
            v.extend_from_slice(&c.to_le_bytes());
        }
    }
    PyBytes::new(py, &v)
}

/// Renders `scene`. Returns `{"width", "height", "terms": {name: bytes}, "combined": bytes,
/// "stats": json}`, images as float32 RGB rows top to bottom. `settings` is a JSON object of
/// render settings named as the schema names them (`settings_schema`); `null` is a default.
#[pyfunction]
#[pyo3(signature = (scene, settings="{}", *, progress=None, preview=None, cancel=None, pass_range=None))]
fn render<'py>(
    py: Python<'py>,
    scene: &PyScene,
    settings: &str,
    progress: Option<Bound<'py, PyAny>>,
    preview: Option<Bound<'py, PyAny>>,
    cancel: Option<&CancelToken>,
    pass_range: Option<(u32, u32)>,
) -> PyResult<Bound<'py, PyDict>> {
    let options = crate::render::RenderOptions::from_json(settings).map_err(to_py)?;
    let flag = cancel
        .map(|c| c.flag.clone())
        .unwrap_or_else(|| Arc::new(AtomicBool::new(false)));
    let mut settings = options.settings();
    if let Some((a, b)) = pass_range {
        if settings.mode != crate::render::settings::RenderMode::Pppm || a >= b {
            return Err(PyValueError::new_err(format!(
                "invalid render setting `pass_range`: ({a}, {b}) must be passes a < b of the \
                 pppm mode (mode=\"pppm\")"
            )));
        }
        settings.pass_range = Some((a, b));
    }
    let out = render_blocking(
        py,
        &scene.desc,
        settings,
        None,
        progress.as_ref(),
        preview.as_ref(),
        flag,
        to_py,
        None,
    )?;
    let d = film_dict(py, &out.film)?;
    let stats =
        serde_json::to_string(&out.stats).map_err(|e| PhotonmapError::new_err(e.to_string()))?;
    d.set_item("stats", stats)?;
    if let Some(p) = &out.partial {
        d.set_item("partial", PyBytes::new(py, &p.to_bytes()))?;
    }
    Ok(d)
}

/// Merges partial sums of pppm passes (the bytes of partial-sum files, every block of one
/// frame; in any order) into the frame's image: the dict of `render`, with `partial` the
/// merged sums.
#[pyfunction]
fn merge_partials<'py>(py: Python<'py>, partials: Vec<Vec<u8>>) -> PyResult<Bound<'py, PyDict>> {
    use crate::render::partial::Partial;
    let merged = py
        .detach(|| {
            caught(|| {
                let parts: Vec<Partial> = partials
                    .iter()
                    .enumerate()
                    .map(|(i, b)| {
                        Partial::from_bytes(b, std::path::Path::new(&format!("partial {i}")))
                    })
                    .collect::<Result<_, Error>>()?;
                let m = Partial::merge_all(&parts)?;
                m.check_complete()?;
                Ok(m)
            })
        })
        .map_err(to_py)?;
    let d = film_dict(py, &merged.film())?;
    d.set_item("stats", cli::merged_stats(&merged).to_string())?;
    d.set_item("partial", PyBytes::new(py, &merged.to_bytes()))?;
    Ok(d)
}

/// The sum of partial sums (bytes of partial-sum files, in any order) as the bytes of one,
/// without checking that every pass is there: a step of a tree reduction.
#[pyfunction]
fn add_partials<'py>(py: Python<'py>, partials: Vec<Vec<u8>>) -> PyResult<Bound<'py, PyBytes>> {
    use crate::render::partial::Partial;
    let bytes = py
        .detach(|| {
            caught(|| {
                let parts: Vec<Partial> = partials
                    .iter()
                    .enumerate()
                    .map(|(i, b)| {
                        Partial::from_bytes(b, std::path::Path::new(&format!("partial {i}")))
                    })
                    .collect::<Result<_, Error>>()?;
                Ok(Partial::merge_all(&parts)?.to_bytes())
            })
        })
        .map_err(to_py)?;
    Ok(PyBytes::new(py, &bytes))
}

/// `{"width", "height", "terms": {name: bytes}, "error": bytes, "aovs": [...],
/// "cryptomatte": json, "combined": bytes}`.
fn film_dict<'py>(
    py: Python<'py>,
    film: &crate::render::film::Film,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("width", film.width)?;
    d.set_item("height", film.height)?;
    let terms = PyDict::new(py);
    for t in Term::ALL {
        terms.set_item(t.name(), image_bytes(py, film.term(t)))?;
    }
    d.set_item("terms", terms)?;
    d.set_item(crate::render::aov::ERROR_AOV, image_bytes(py, &film.error))?;
    d.set_item("aovs", aov_list(py, film)?)?;
    d.set_item(
        "cryptomatte",
        serde_json::to_string(&film.cryptomatte)
            .map_err(|e| PhotonmapError::new_err(e.to_string()))?,
    )?;
    d.set_item("combined", image_bytes(py, &film.combined()))?;
    Ok(d)
}

/// Denoises a render's terms through the Python `denoiser` (see `run_cli`): the terms it
/// returns replace the film's, and what it reports goes into the stats.
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

/// The `photonmap` command: parses `argv` (without the program name) with the core's clap
/// definition, reads USD stages through `usd_loader(path, frame, camera, purposes, strict)`
/// (which returns `(ir_json, import_stats_json)`), renders each frame with the progress bar on
/// stderr, and writes the EXR, PNG and stats. With `--denoise`, `denoiser.check()` runs first
/// (it raises when the denoiser is missing), and after each render `denoiser(width, height,
/// {term: bytes}, albedo, normal)` returns the denoised terms (`{term: bytes}`) and what
/// denoised them (`{key: text}`, into the stats and the EXR metadata). Returns the exit
/// status; errors of the loader are raised as they are.
#[pyfunction]
#[pyo3(signature = (argv, usd_loader=None, denoiser=None))]
fn run_cli(
    py: Python<'_>,
    argv: Vec<String>,
    usd_loader: Option<Bound<'_, PyAny>>,
    denoiser: Option<Bound<'_, PyAny>>,
) -> PyResult<i32> {
    let cli = match Cli::try_parse_from(std::iter::once("photonmap".to_string()).chain(argv)) {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return Ok(e.exit_code());
        }
    };
    let args = match cli.command {
        Command::Render(args) => args,
        Command::Merge(m) => {
            return match py.detach(|| caught(|| cli::run_merge(&m))) {
                Ok(p) => {
                    if !m.quiet {
                        eprintln!(
                            "wrote {} ({} passes from {} partial sums)",
                            m.output.display(),
                            p.passes(),
                            m.partials.len()
                        );
                    }
                    Ok(0)
                }
                Err(e) => {
                    eprintln!("photonmap: error: {}", e.for_cli());
                    Ok(1)
                }
            };
        }
    };
    // Under --time-budget the command's wall clock runs from here: the USD import, the
    // scene build, the render and the writing of every frame all count.
    let clock = args.wall_clock();
    let fail = |e: Error| {
        let e = e.for_cli();
        eprintln!("photonmap: error: {e}");
        Ok(if matches!(e, Error::InvalidSetting { .. }) {
            2
        } else {
            1
        })
    };
    if let Err(e) = args.check() {
        return fail(e);
    }
    if args.options.denoise {
        let ready = match &denoiser {
            Some(d) => d.call_method0("check").map(|_| ()),
            None => Err(PyValueError::new_err("no denoiser available")),
        };
        if let Err(e) = ready {
            eprintln!("photonmap: error: --denoise: {}", e.value(py));
            return Ok(2);
        }
    }
    let frames = match args.frame_list() {
        Ok(f) => f,
        Err(e) => return fail(e),
    };
    let py_err: std::cell::RefCell<Option<PyErr>> = Default::default();
    let mut load = usd_load_fn(usd_loader.as_ref(), &py_err);
    let frame_count = frames.len();
    let mut reuse = cli::FrameReuse::new(&args, frame_count);
    for (i, frame) in frames.into_iter().enumerate() {
        let a = args.for_frame(frame);
        let loaded = match caught(|| a.load_scene_with(frame, Some(&mut load))) {
            Ok(l) => l,
            Err(e) => match py_err.borrow_mut().take() {
                Some(pe) => return Err(pe),
                None => return fail(e),
            },
        };
        let (bar, bar_fn) = cli::progress_bar(a.quiet);
        let cancel = Arc::new(AtomicBool::new(false));
        let settings = a.settings_within(clock.as_ref(), frame_count - i);
        let output = clock.map(|_| a.output_time());
        let request = reuse.request(
            i,
            cli::RenderRequest {
                output_time: output,
                maps_only: a.photon_maps_only,
                ..cli::RenderRequest::new(&loaded.desc, settings)
            },
        );
        let out = run_blocking(py, request, Some(bar_fn), None, None, cancel, |e| {
            to_py(e.for_cli())
        });
        let mut out = match out {
            Ok(o) => o,
            Err(e) => {
                bar.abandon();
                if e.is_instance_of::<PyKeyboardInterrupt>(py) {
                    return Err(e);
                }
                eprintln!("photonmap: error: {}", e.value(py));
                return Ok(1);
            }
        };
        bar.finish_and_clear();
        if let (true, Some(d)) = (a.options.denoise && !a.photon_maps_only, &denoiser) {
            if let Err(e) = denoise_film(py, d, &mut out) {
                eprintln!("photonmap: error: --denoise: {}", e.value(py));
                return Ok(1);
            }
        }
        if let Err(e) = caught(|| cli::write_outputs_with(&a, &out, loaded.import_stats.as_ref())) {
            return fail(e);
        }
        reuse.rendered(i, &mut out);
        if !a.quiet {
            eprintln!("{}", cli::summary(&a, &out));
        }
        if a.photon_maps_only {
            // The maps of the first frame's view; later frames load them.
            break;
        }
    }
    Ok(0)
}

/// The scene reader of the command: USD stages through the Python `usd_loader(path, frame,
/// camera, purposes, strict)`, which returns `(ir_json, import_stats_json)`. An exception of
/// the loader is kept in `py_err`, to be raised as it is.
fn usd_load_fn<'a, 'py>(
    usd_loader: Option<&'a Bound<'py, PyAny>>,
    py_err: &'a std::cell::RefCell<Option<PyErr>>,
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

/// The preset fields of a quality preset as JSON, named as the `render` keywords.
#[pyfunction]
fn preset(name: &str) -> PyResult<String> {
    let q = Quality::parse(name).ok_or_else(|| {
        pyo3::exceptions::PyValueError::new_err(format!(
            "unknown quality `{name}` (expected draft, medium, high or final)"
        ))
    })?;
    Ok(crate::render::RenderOptions::preset_json(q).to_string())
}

/// The render settings' schema as JSON (`RenderOptions::schema`).
#[pyfunction]
fn settings_schema() -> String {
    crate::render::RenderOptions::schema().to_string()
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
    m.add_class::<PyScene>()?;
    m.add_class::<CancelToken>()?;
    m.add_class::<job::Job>()?;
    m.add_function(wrap_pyfunction!(merge_partials, m)?)?;
    m.add_function(wrap_pyfunction!(add_partials, m)?)?;
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(run_cli, m)?)?;
    m.add_function(wrap_pyfunction!(preset, m)?)?;
    m.add_function(wrap_pyfunction!(settings_schema, m)?)?;
    m.add_function(wrap_pyfunction!(aov_specs, m)?)?;
    m.add_function(wrap_pyfunction!(cryptomatte_header, m)?)?;
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
