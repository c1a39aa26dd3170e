//! Counters of the work a render did, per kind: what the scene does not need must not run,
//! and these counts show it (the stats JSON holds them under `work`).

use serde::Serialize;
use std::sync::atomic::{AtomicU64, Ordering};

/// Shared by the workers of one render; each estimator adds its work once per call.
#[derive(Debug, Default)]
pub struct WorkCounts {
    march_steps: AtomicU64,
    volume_lookups: AtomicU64,
    volume_point_reads: AtomicU64,
    caustic_lookups: AtomicU64,
    subsurface_walks: AtomicU64,
    subsurface_events: AtomicU64,
    subsurface_lost: AtomicU64,
}

/// What [`WorkCounts`] counted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct WorkStats {
    /// Ray-marching steps through participating media (camera pass).
    pub march_steps: u64,
    /// Radiance estimates read from the volume photon map.
    pub volume_lookups: u64,
    /// Of those, the ones answered by a precomputed point (isotropic media) instead of a
    /// k-nearest search.
    pub volume_point_reads: u64,
    /// Radiance estimates read from the caustic photon map.
    pub caustic_lookups: u64,
    /// Walks of camera paths below subsurface materials that found an exit.
    pub subsurface_walks: u64,
    /// Their scattering events.
    pub subsurface_events: u64,
    /// Walks that found no exit (absorbed, or lost after 256 events).
    pub subsurface_lost: u64,
}

impl WorkCounts {
    pub fn march(&self, steps: u64, volume_lookups: u64, volume_point_reads: u64) {
        if volume_point_reads > 0 {
            self.volume_point_reads
                .fetch_add(volume_point_reads, Ordering::Relaxed);
        }
        if steps > 0 {
            self.march_steps.fetch_add(steps, Ordering::Relaxed);
        }
        if volume_lookups > 0 {
            self.volume_lookups
                .fetch_add(volume_lookups, Ordering::Relaxed);
        }
    }

    /// A walk below a subsurface material that left it after `events` scattering events.
    pub fn subsurface_walk(&self, events: u64) {
        self.subsurface_walks.fetch_add(1, Ordering::Relaxed);
        self.subsurface_events.fetch_add(events, Ordering::Relaxed);
    }

    /// A walk below a subsurface material that found no exit.
    pub fn subsurface_walk_lost(&self) {
        self.subsurface_lost.fetch_add(1, Ordering::Relaxed);
    }

    pub fn caustic_lookup(&self) {
        self.caustic_lookups.fetch_add(1, Ordering::Relaxed);
    }

    pub fn stats(&self) -> WorkStats {
        WorkStats {
            march_steps: self.march_steps.load(Ordering::Relaxed),
            volume_lookups: self.volume_lookups.load(Ordering::Relaxed),
            volume_point_reads: self.volume_point_reads.load(Ordering::Relaxed),
            caustic_lookups: self.caustic_lookups.load(Ordering::Relaxed),
            subsurface_walks: self.subsurface_walks.load(Ordering::Relaxed),
            subsurface_events: self.subsurface_events.load(Ordering::Relaxed),
            subsurface_lost: self.subsurface_lost.load(Ordering::Relaxed),
        }
    }
}
