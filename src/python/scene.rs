//! `photonmap._core.Scene`, a validated scene IR (from JSON text, a JSON file, the embedded
//! default, or JSON plus raw little-endian mesh buffers), and `CancelToken`.

use super::{caught, pointer, to_py, PhotonmapError};
use crate::error::Error;
use crate::io::scene_json;
use crate::scene::desc::SceneDesc;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Parses and validates JSON scene text; parse errors are given the JSON pointer of the field.
pub(super) fn parse_scene(text: &str) -> Result<SceneDesc, Error> {
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
    pub(super) desc: SceneDesc,
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
    pub(super) flag: Arc<AtomicBool>,
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
