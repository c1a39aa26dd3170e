//! `photonmap._core.Job`: one `photonmap render` command split into pieces that can run in
//! other processes or on other machines (the Python package's Dask front end,
//! `photonmap.distributed`): frames, the photon maps of a frame, blocks of pppm passes and
//! their merge, and Jensen tiles. Every piece is parsed from the same command line, reads
//! its scene the way the command does, and writes its outputs atomically; the pieces of a
//! frame give the bits of the frame rendered by the command in one process.
//!
//! Every method releases the GIL while it works and turns a panic of the core into
//! `PhotonmapError`.

use super::command::usd_load_fn;
use super::scene::PyScene;
use super::{caught, to_py, PhotonmapError};
use crate::cli::{Cli, Command, RenderArgs};
use crate::command::output::{self, ImageFiles};
use crate::command::{merge, render_request, report, scene, FrameReuse, RenderRequest};
use crate::error::Error;
use crate::math::Spectrum;
use crate::render::map_file::{self, MapSet};
use crate::render::stratified::Rect;
use crate::render::tile::{self, TileOutput, TileStage};
use crate::render::{RenderOutput, RenderSettings, Renderer};
use crate::scene::Scene;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::path::Path;
use std::sync::Arc;

/// A parsed `photonmap render` command, for rendering it in pieces.
#[pyclass(module = "photonmap._core", frozen)]
pub struct Job {
    args: RenderArgs,
}

type RectTuple = (usize, usize, usize, usize);

fn rect((x, y, width, height): RectTuple) -> Rect {
    Rect {
        x,
        y,
        width,
        height,
    }
}

fn spectra(b: &[u8]) -> Vec<Spectrum> {
    b.chunks_exact(12)
        .map(|c| {
            let f = |i: usize| f32::from_le_bytes([c[i], c[i + 1], c[i + 2], c[i + 3]]);
            Spectrum::new(f(0), f(4), f(8))
        })
        .collect()
}

fn spectra_bytes<'py>(py: Python<'py>, v: &[Spectrum]) -> Bound<'py, PyBytes> {
    let mut out = Vec::with_capacity(v.len() * 12);
    for s in v {
        for c in s.to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    PyBytes::new(py, &out)
}

fn stats_json(out: &RenderOutput) -> PyResult<String> {
    Ok(report::stats_json(&out.stats, None)
        .map_err(to_py)?
        .to_string())
}

fn maps_of(bytes: Option<&[u8]>) -> Result<Option<Arc<MapSet>>, Error> {
    bytes
        .map(|b| MapSet::from_bytes(b, Path::new("the frame's photon maps")).map(Arc::new))
        .transpose()
}

impl Job {
    fn settings(&self, threads: Option<usize>) -> RenderSettings {
        let mut s = self.args.settings();
        if let Some(t) = threads {
            s.threads = t;
        }
        s
    }

    fn run<T: Send>(
        &self,
        py: Python<'_>,
        f: impl FnOnce() -> Result<T, Error> + Send,
    ) -> PyResult<T> {
        py.detach(|| caught(f)).map_err(|e| to_py(e.for_cli()))
    }
}

#[pymethods]
impl Job {
    /// Parses `argv` (`render SCENE -o OUT ...`, without the program name). A bad command
    /// line raises ValueError with clap's message.
    #[new]
    fn new(argv: Vec<String>) -> PyResult<Self> {
        let cli = Cli::parse_args(std::iter::once("photonmap".to_string()).chain(argv))
            .map_err(|e| PyValueError::new_err(e.render().to_string()))?;
        match cli.command {
            Command::Render(mut args) => {
                args.cluster = None;
                args.check().map_err(|e| to_py(e.for_cli()))?;
                Ok(Job { args })
            }
            Command::Merge(_) => Err(PyValueError::new_err(
                "a render command was expected, not merge",
            )),
        }
    }

    /// The frames to render: numbers, or `[None]` for one render at the default time.
    fn frames(&self) -> PyResult<Vec<Option<f64>>> {
        self.args.frame_list().map_err(|e| to_py(e.for_cli()))
    }

    /// What the distributed front end needs to know, as JSON: the mode, passes, whether
    /// frames reuse the first frame's maps, whether tiles take two stages, tiles and blocks
    /// asked for, the outputs.
    fn info(&self) -> PyResult<String> {
        let s = self.args.settings();
        let frames = self.frames()?.len();
        let reuse = FrameReuse::new(&self.args, frames).enabled();
        Ok(serde_json::json!({
            "mode": s.mode,
            "spp": s.spp,
            "threads": s.threads,
            "time_budget": s.time_budget,
            "progressive": s.progressive,
            "frame_maps_reused": reuse,
            "two_stage_tiles": tile::two_stages(&s),
            "tiles": self.args.tiles,
            "block_passes": self.args.block_passes,
            "initial_radius": s.initial_radius,
            "output": self.args.output,
            "stats": self.args.stats,
            "png": self.args.png,
            "quiet": self.args.quiet,
        })
        .to_string())
    }

    /// Reads the scene of `frame` as the command does (USD stages through `usd_loader`);
    /// returns it with its import statistics (JSON or None).
    #[pyo3(signature = (frame, usd_loader=None))]
    fn scene(
        &self,
        frame: Option<f64>,
        usd_loader: Option<Bound<'_, PyAny>>,
    ) -> PyResult<(PyScene, Option<String>)> {
        let py_err: std::cell::RefCell<Option<PyErr>> = Default::default();
        let mut load = usd_load_fn(usd_loader.as_ref(), &py_err);
        let loaded = caught(|| scene::load(&self.args, frame, Some(&mut load)));
        drop(load);
        match loaded {
            Ok(l) => Ok((
                PyScene { desc: l.desc },
                l.import_stats.map(|v| v.to_string()),
            )),
            Err(e) => match py_err.into_inner() {
                Some(pe) => Err(pe),
                None => Err(to_py(e.for_cli())),
            },
        }
    }

    /// Renders `frame` of `scene` and writes its outputs (atomically), with `maps` (a
    /// photon-map file's bytes) reused when their key is this frame's. Returns the stats.
    #[pyo3(signature = (scene, frame, import_stats=None, maps=None, threads=None))]
    fn render_frame(
        &self,
        py: Python<'_>,
        scene: &PyScene,
        frame: Option<f64>,
        import_stats: Option<String>,
        maps: Option<Vec<u8>>,
        threads: Option<usize>,
    ) -> PyResult<String> {
        let a = self.args.for_frame(frame);
        let settings = self.settings(threads);
        let out = self.run(py, || {
            let reuse = maps_of(maps.as_deref())?;
            let out = render_request(RenderRequest {
                reuse,
                ..RenderRequest::new(&scene.desc, settings)
            })?;
            let imp = import_stats.and_then(|s| serde_json::from_str(&s).ok());
            output::write_outputs(&a, &out, imp.as_ref())?;
            Ok(out)
        })?;
        stats_json(&out)
    }

    /// Jensen: the photon maps and the irradiance cache of `scene`'s view, as the bytes of a
    /// photon-map file.
    #[pyo3(signature = (scene, threads=None))]
    fn build_maps<'py>(
        &self,
        py: Python<'py>,
        scene: &PyScene,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let settings = self.settings(threads);
        let bytes = self.run(py, || {
            let out = render_request(RenderRequest {
                maps_only: true,
                ..RenderRequest::new(&scene.desc, settings)
            })?;
            let set = out
                .photon_maps
                .ok_or_else(|| Error::Internal("no photon maps were built".into()))?;
            Ok(set.to_bytes())
        })?;
        Ok(PyBytes::new(py, &bytes))
    }

    /// pppm: the first pass's radius r_1 (the settings' `initial_radius`, or computed).
    #[pyo3(signature = (scene, threads=None))]
    fn pppm_radius(
        &self,
        py: Python<'_>,
        scene: &PyScene,
        threads: Option<usize>,
    ) -> PyResult<f32> {
        let settings = self.settings(threads);
        if let Some(r) = settings.initial_radius {
            return Ok(r);
        }
        self.run(py, || {
            let sc = Scene::build(&scene.desc)?;
            let threads = settings.threads;
            let r = Renderer::new(&sc).settings(settings);
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|e| Error::Internal(format!("thread pool: {e}")))?;
            pool.install(|| r.pppm_initial_radius())
        })
    }

    /// pppm: passes `first..end` with first radius `r1`, as the bytes of a partial-sum file.
    #[pyo3(signature = (scene, first, end, r1, threads=None))]
    fn render_passes<'py>(
        &self,
        py: Python<'py>,
        scene: &PyScene,
        first: u32,
        end: u32,
        r1: f32,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let mut settings = self.settings(threads);
        settings.pass_range = Some((first, end));
        settings.initial_radius = Some(r1);
        let bytes = self.run(py, || {
            let out = render_request(RenderRequest::new(&scene.desc, settings))?;
            let p = out
                .partial
                .ok_or_else(|| Error::Internal("no partial sums".into()))?;
            Ok(p.to_bytes())
        })?;
        Ok(PyBytes::new(py, &bytes))
    }

    /// pppm: merges partial sums (bytes of partial-sum files; every block of `frame`) and
    /// writes the frame's outputs, with the keys of `extra` (a JSON object) added to its
    /// stats. Returns the merged stats.
    #[pyo3(signature = (frame, partials, extra=None))]
    fn write_merged(
        &self,
        py: Python<'_>,
        frame: Option<f64>,
        partials: Vec<Vec<u8>>,
        extra: Option<String>,
    ) -> PyResult<String> {
        let a = self.args.for_frame(frame);
        let st = self.run(py, || {
            let parts = merge::from_bytes(&partials, |i| format!("block {i}'s partial sums"))?;
            let merged = merge::complete(parts)?;
            let extra: Option<serde_json::Value> = extra
                .map(|e| serde_json::from_str(&e))
                .transpose()
                .map_err(|e| Error::Internal(format!("extra stats: {e}")))?;
            let st = report::merged_stats(&merged, extra.as_ref())?;
            output::write_image(ImageFiles::of(&a), &merged.film(), &st)?;
            Ok(st)
        })?;
        Ok(st.to_string())
    }

    /// Jensen: the first stage of tile `rect` (x, y, width, height) over `maps`: each pixel's
    /// mean and standard error after the first round (little-endian f32 RGB), and the
    /// pixels' state.
    #[pyo3(signature = (scene, maps, rect, threads=None))]
    fn tile_first<'py>(
        &self,
        py: Python<'py>,
        scene: &PyScene,
        maps: Vec<u8>,
        rect: RectTuple,
        threads: Option<usize>,
    ) -> PyResult<(
        Bound<'py, PyBytes>,
        Bound<'py, PyBytes>,
        Bound<'py, PyBytes>,
    )> {
        let settings = self.settings(threads);
        let out = self.run(py, || {
            render_tile(
                &scene.desc,
                settings,
                &maps,
                self::rect(rect),
                TileStage::First,
            )
        })?;
        match out {
            TileOutput::First {
                means,
                errors,
                state,
            } => Ok((
                spectra_bytes(py, &means),
                spectra_bytes(py, &errors),
                PyBytes::new(py, &state),
            )),
            TileOutput::Finished { .. } => Err(PhotonmapError::new_err("unexpected tile stage")),
        }
    }

    /// Jensen with adaptive sampling: the rounds per pixel (little-endian u32, row-major)
    /// decided from the whole image's first round (means and errors as `tile_first` gives
    /// them, placed row-major over the image); None without adaptive sampling.
    fn adaptive_rounds<'py>(
        &self,
        py: Python<'py>,
        means: Vec<u8>,
        errors: Vec<u8>,
        width: usize,
        height: usize,
    ) -> PyResult<Option<Bound<'py, PyBytes>>> {
        let s = self.args.settings();
        let rounds = caught(|| {
            tile::adaptive_rounds(&s, &spectra(&means), &spectra(&errors), width, height)
        })
        .map_err(to_py)?;
        Ok(rounds.map(|r| {
            let b: Vec<u8> = r.iter().flat_map(|v| v.to_le_bytes()).collect();
            PyBytes::new(py, &b)
        }))
    }

    /// Jensen: tile `rect` over `maps`, from the first stage's `state` and the tile's
    /// `rounds` (row-major in the tile) with adaptive sampling, or from scratch without.
    /// Returns the tile's film (see `tile::film_to_bytes`) and its stats.
    #[pyo3(signature = (scene, maps, rect, rounds=None, state=None, threads=None))]
    #[allow(clippy::too_many_arguments)]
    fn tile_finish<'py>(
        &self,
        py: Python<'py>,
        scene: &PyScene,
        maps: Vec<u8>,
        rect: RectTuple,
        rounds: Option<Vec<u8>>,
        state: Option<Vec<u8>>,
        threads: Option<usize>,
    ) -> PyResult<(Bound<'py, PyBytes>, String)> {
        let settings = self.settings(threads);
        let rounds = rounds.map(|b| {
            b.chunks_exact(4)
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect()
        });
        let out = self.run(py, || {
            render_tile(
                &scene.desc,
                settings,
                &maps,
                self::rect(rect),
                TileStage::Finish { rounds, state },
            )
        })?;
        match out {
            TileOutput::Finished { film, stats } => Ok((
                PyBytes::new(py, &tile::film_to_bytes(&film)),
                report::stats_json(&stats, None).map_err(to_py)?.to_string(),
            )),
            TileOutput::First { .. } => Err(PhotonmapError::new_err("unexpected tile stage")),
        }
    }

    /// Jensen: assembles the tiles of `frame` (each `(rect, film bytes)`) into the
    /// `width`-by-`height` image and writes the frame's outputs, with `stats` (JSON: the
    /// tiles' stats combined by `tile_stats`) as its stats.
    fn write_tiles(
        &self,
        py: Python<'_>,
        frame: Option<f64>,
        width: usize,
        height: usize,
        tiles: Vec<(RectTuple, Vec<u8>)>,
        stats: String,
    ) -> PyResult<()> {
        let a = self.args.for_frame(frame);
        self.run(py, || {
            let mut film = crate::render::film::Film::new(width, height);
            let mut covered = vec![false; width * height];
            for (r, bytes) in &tiles {
                let r = self::rect(*r);
                let t = tile::film_from_bytes(bytes, r.width, r.height)?;
                tile::place(&mut film, r, &t)?;
                for y in r.y..r.y + r.height {
                    for c in &mut covered[y * width + r.x..y * width + r.x + r.width] {
                        if *c {
                            return Err(Error::Internal(format!("tile {r:?} overlaps another")));
                        }
                        *c = true;
                    }
                }
            }
            if covered.iter().any(|c| !c) {
                return Err(Error::Internal("the tiles leave pixels out".into()));
            }
            let st: serde_json::Value = serde_json::from_str(&stats)
                .map_err(|e| Error::Internal(format!("tile stats: {e}")))?;
            output::write_image(ImageFiles::of(&a), &film, &st)
        })
    }

    /// The photon-map key of `scene` under this command's settings (hexadecimal).
    fn maps_key(&self, scene: &PyScene) -> String {
        format!(
            "{:016x}",
            map_file::keys(&scene.desc, &self.args.settings()).maps
        )
    }
}

/// One stage of a tile over the frame's maps (the bytes of a photon-map file).
fn render_tile(
    desc: &crate::scene::SceneDesc,
    settings: RenderSettings,
    maps: &[u8],
    rect: Rect,
    stage: TileStage,
) -> Result<TileOutput, Error> {
    let set = Arc::new(MapSet::from_bytes(
        maps,
        Path::new("the frame's photon maps"),
    )?);
    let keys = map_file::keys(desc, &settings);
    if set.key != keys.maps {
        return Err(Error::Internal(
            "a tile was given the photon maps of another scene or other settings".into(),
        ));
    }
    let scene = Scene::build(desc)?;
    Renderer::new(&scene)
        .settings(settings)
        .keys(keys)
        .reuse_photon_maps(set)
        .render_tile(rect, stage)
}
