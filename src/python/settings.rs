//! The render settings as Python sees them: the presets, the schema, the AOVs a render with
//! given settings writes, and the Cryptomatte EXR header.

use super::to_py;
use crate::render::aov::AovSpec;
use crate::render::{Quality, RenderSettings};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeMap;

/// The preset fields of a quality preset as JSON, named as the `render` keywords.
#[pyfunction]
pub(super) fn preset(name: &str) -> PyResult<String> {
    let q = Quality::parse(name).ok_or_else(|| {
        PyValueError::new_err(format!(
            "unknown quality `{name}` (expected draft, medium, high or final)"
        ))
    })?;
    Ok(RenderSettings::preset_json(q).to_string())
}

/// The render settings' schema as JSON (`RenderSettings::schema`).
#[pyfunction]
pub(super) fn settings_schema() -> String {
    RenderSettings::schema().to_string()
}

/// A spec of the AOV list as a dict: `name`, `pass_name`, `kind`, `channels`, `chan_id`,
/// `pass_type` (the last two as Blender's `register_pass` takes them).
pub(super) fn spec_dict<'py>(py: Python<'py>, spec: &AovSpec) -> PyResult<Bound<'py, PyDict>> {
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

/// The AOVs beside the terms that a render with `settings` (the `render` keywords as JSON)
/// writes, for a scene whose IR names the light groups `light_groups` (the `default` group
/// is added as the scene build adds it), in output order, as spec dicts (see `spec_dict`):
/// Blender registers its passes from it.
#[pyfunction]
#[pyo3(signature = (settings="{}", light_groups=Vec::new()))]
pub(super) fn aov_specs<'py>(
    py: Python<'py>,
    settings: &str,
    light_groups: Vec<String>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    RenderSettings::from_json(settings)
        .map_err(to_py)?
        .aovs()
        .aovs(&crate::render::aov::light_group_names(&light_groups))
        .iter()
        .map(|spec| spec_dict(py, spec))
        .collect()
}

/// The EXR header attributes of Cryptomatte manifests (`{type name: [names]}` as JSON), each
/// layer named `prefix` + type name: `{"cryptomatte/<key>/name": ..., ...}`.
#[pyfunction]
#[pyo3(signature = (manifests, prefix=""))]
pub(super) fn cryptomatte_header(
    manifests: &str,
    prefix: &str,
) -> PyResult<BTreeMap<String, String>> {
    let m: BTreeMap<String, Vec<String>> =
        serde_json::from_str(manifests).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(crate::render::compositing::cryptomatte_header(&m, prefix))
}
