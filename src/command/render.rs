//! A render of a scene IR with everything a front end may ask of it: photon maps to reuse,
//! keep or only build, maps loaded from and saved to files (their keys checked), progress,
//! cancellation, previews, and the time a time budget leaves for writing the outputs.

use crate::error::Result;
use crate::render::map_file::{self, MapSet};
use crate::render::settings::RenderMode;
use crate::render::{OutputTimeFn, PreviewFn, ProgressFn, RenderOutput, RenderSettings, Renderer};
use crate::scene::{Scene, SceneDesc};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// A render of a scene IR, with everything a front end may ask of it.
pub struct RenderRequest<'a> {
    pub desc: &'a SceneDesc,
    pub settings: RenderSettings,
    pub progress: Option<Arc<ProgressFn>>,
    pub cancel: Option<Arc<AtomicBool>>,
    pub preview: Option<Arc<PreviewFn>>,
    pub output_time: Option<Arc<OutputTimeFn>>,
    /// Jensen: photon maps to use (an earlier frame's, or a set built for this frame); used
    /// only when their key is this render's.
    pub reuse: Option<Arc<MapSet>>,
    /// Jensen: keep the maps in the output (`RenderOutput::photon_maps`).
    pub keep_maps: bool,
    /// Jensen: build the maps and the cache only.
    pub maps_only: bool,
}

impl<'a> RenderRequest<'a> {
    pub fn new(desc: &'a SceneDesc, settings: RenderSettings) -> Self {
        RenderRequest {
            desc,
            settings,
            progress: None,
            cancel: None,
            preview: None,
            output_time: None,
            reuse: None,
            keep_maps: false,
            maps_only: false,
        }
    }
}

/// Renders a request: builds the scene, loads the photon maps it names (checking their key),
/// renders, and saves the maps where it says. The scene build's time goes into the stats
/// and, under a time budget, comes out of it.
pub fn render_request(req: RenderRequest) -> Result<RenderOutput> {
    let t0 = std::time::Instant::now();
    let RenderRequest {
        desc,
        mut settings,
        progress,
        cancel,
        preview,
        output_time,
        mut reuse,
        keep_maps,
        maps_only,
    } = req;
    map_file::check_settings(&settings)?;
    let files = settings.photon_map_files();
    // Keys hash the whole scene: computed only where they are used.
    let keyed = match settings.mode {
        RenderMode::Pppm => true,
        RenderMode::Sppm => false,
        RenderMode::Jensen => {
            reuse.is_some() || keep_maps || maps_only || files != Default::default()
        }
    };
    let (keys, parts) = if keyed {
        (
            Some(map_file::keys(desc, &settings)),
            Some(map_file::key_parts(desc, &settings)),
        )
    } else {
        (None, None)
    };
    if let (Some(set), Some(k)) = (&reuse, keys) {
        if set.key != k.maps {
            reuse = None;
        }
    }
    let mut rebuilt_because = None;
    let mut loaded_from = None;
    if let (Some(path), Some(parts)) = (&files.load, &parts) {
        match MapSet::load(path, parts) {
            Ok(set) => {
                reuse = Some(Arc::new(set));
                loaded_from = Some(path.display().to_string());
            }
            Err(e) if files.on_mismatch == map_file::OnMismatch::Rebuild => {
                rebuilt_because = Some(e.to_string());
            }
            Err(e) => return Err(e),
        }
    }
    let scene = Scene::build_cancellable(desc, cancel.as_deref())?;
    let build_s = t0.elapsed().as_secs_f64();
    if let Some(b) = settings.budget_seconds() {
        settings.time_budget = Some((b - build_s).max(1e-3));
    }
    let save = files
        .save
        .clone()
        .filter(|p| Some(p) != files.load.as_ref() || reuse.is_none());
    let mut r = Renderer::new(&scene)
        .settings(settings)
        .keep_photon_maps(keep_maps || save.is_some())
        .maps_only(maps_only);
    if let (Some(k), Some(p)) = (keys, parts) {
        r = r.keys(k).key_parts(p);
    }
    if let Some(set) = reuse {
        r = r.reuse_photon_maps(set);
    }
    if let Some(p) = progress {
        r = r.progress(p);
    }
    if let Some(c) = cancel {
        r = r.cancel_flag(c);
    }
    if let Some(p) = preview {
        r = r.preview(p);
    }
    if let Some(o) = output_time {
        r = r.output_time(o);
    }
    let mut out = r.render()?;
    out.stats.seconds.insert("scene_build".into(), build_s);
    if let Some(st) = out.stats.photon_map_reuse.as_mut() {
        if loaded_from.is_some() {
            st.maps = "loaded".into();
        }
        st.loaded_from = loaded_from;
        st.rebuilt_because = rebuilt_because;
    }
    if let (Some(path), Some(set)) = (&save, &out.photon_maps) {
        set.save(path)?;
        if let Some(st) = out.stats.photon_map_reuse.as_mut() {
            st.saved_to = Some(path.display().to_string());
        }
    }
    Ok(out)
}
