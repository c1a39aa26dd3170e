//! What a render returns: its film, its stats, and what a mode keeps for later (pppm's partial
//! sums, Jensen's photon maps).

use super::film::Film;
use super::stats::RenderStats;

/// A render's result.
pub struct RenderOutput {
    pub film: Film,
    pub stats: RenderStats,
    /// pppm: the passes' partial sums, to save or merge with other blocks.
    pub partial: Option<Box<super::partial::Partial>>,
    /// Jensen's mode, when asked for ([`Renderer::keep_photon_maps`]): the photon maps and
    /// irradiance cache of the render, to reuse or save.
    pub photon_maps: Option<std::sync::Arc<super::map_file::MapSet>>,
}
