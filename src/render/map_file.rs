//! Photon maps kept and reused: across the frames of a camera animation, and in files
//! (`save_photon_maps`, `load_photon_maps`).
//!
//! **What is kept** ([`MapSet`]): Jensen's global, caustic and volume maps (with the global
//! map's precomputed irradiance and the volume map's precomputed radiance) and the irradiance
//! cache. The photon maps depend on the scene and the settings, never on the camera. The cache's records are world-space points,
//! so they are valid for any view, but where they are depends on the view it was filled for:
//! a render through another camera extends a copy of it for its own view (the fill's rounds,
//! giving records only to the points it does not cover yet) and never changes the kept one.
//! Each frame then depends only on the kept set and its own camera, so frames can render in
//! any order, on any machine, to the same bits.
//!
//! **The key** (`map_key`): a set is keyed by a hash of what its maps depend on; using a set
//! under another key is an error ([`check_key`]), never a silently wrong image;
//! `photon_maps_mismatch rebuild` builds the maps again instead.
//!
//! **The file** is a [`container`] (magic `PMAPS`, a version, a CRC-32): a truncated, corrupt
//! or other-version file is an error naming the file and what is wrong.

use super::irradiance_cache::IrradianceCache;
pub use super::map_key::{key_parts, keys, KeyParts, NOT_IN_IMAGE};
use super::map_records::{read_map, read_record, write_map, write_record, RECORD_FLOATS};
use super::photons::{MapStats, PhotonMaps};
pub use super::settings::{MapFiles, OnMismatch};
use super::settings::{RenderMode, RenderSettings};
use crate::error::{Error, Result};
use crate::io::container::{self, Kind, Reader, Writer};
use crate::photon::volume_points::{VolumePoint, VolumePointMap};
use serde::Serialize;
use std::path::Path;

/// The photon-map file (`.pmaps`): a container of this kind.
pub const MAP_FILE: Kind = Kind {
    magic: *b"PMAPS\0\r\n",
    version: super::map_key::MAP_FILE_VERSION,
    what: "photon-map file",
};

/// Jensen's photon maps and irradiance cache, as one render built them.
pub struct MapSet {
    /// The key they were built under, and its parts.
    pub key: u64,
    pub parts: KeyParts,
    pub maps: PhotonMaps,
    /// The maps' statistics when they were built.
    pub stats: Vec<MapStats>,
    /// The irradiance cache, filled for the view `cache_view`.
    pub cache: Option<IrradianceCache>,
    pub cache_view: u64,
}

/// Where a render's photon maps and irradiance cache came from, for the stats.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ReuseStats {
    /// `built`, `reused` (kept from an earlier frame of the same command) or `loaded` (from
    /// `loaded_from`).
    pub maps: String,
    /// The key, in hexadecimal.
    pub key: String,
    /// `filled` (for this view), `reused` (filled for this very view), `extended` (filled
    /// for another view and extended for this one) or `none`.
    pub cache: String,
    /// Records that came with the maps, and records this render added.
    pub cache_records_reused: u64,
    pub cache_records_added: u64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub loaded_from: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub saved_to: Option<String>,
    /// Why maps given to load were not used (`photon_maps_mismatch rebuild`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rebuilt_because: Option<String>,
    /// Seconds the maps took when they were built (the time a reuse saved, photon pass
    /// only).
    pub build_seconds: f64,
}

/// An error for maps of another key: what differs, and what to do.
pub fn check_key(set: &MapSet, expected: &KeyParts, source: &str) -> Result<()> {
    if set.key == expected.key() {
        return Ok(());
    }
    let diff = set.parts.differences(expected);
    let what = if diff.is_empty() {
        "the key".to_string()
    } else {
        diff.join(", ")
    };
    Err(Error::InvalidSetting {
        setting: "load_photon_maps".into(),
        message: format!(
            "the photon maps in {source} were built for another scene or other settings \
             ({what} differ; key {:016x}, this render's {:016x}): build them again, or set \
             photon_maps_mismatch to rebuild to rebuild them automatically",
            set.key,
            expected.key()
        ),
    })
}

impl MapSet {
    /// The set as the bytes of a photon-map file.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut w = Writer::default();
        let info = serde_json::json!({
            "renderer": env!("CARGO_PKG_VERSION"),
            "key": format!("{:016x}", self.key),
            "maps": self.stats.iter().filter(|m| m.built)
                .map(|m| (m.map, m.stored)).collect::<std::collections::BTreeMap<_, _>>(),
            "cache_records": self.cache.as_ref().map_or(0, |c| c.len()),
        });
        w.str(&info.to_string());
        w.u64(self.key);
        for v in self.parts.array() {
            w.u64(v);
        }
        w.u64(self.cache_view);
        w.u64(self.maps.gather as u64);
        w.f32(self.maps.global_r2);
        w.f32(self.maps.caustic_r2);
        write_map(&mut w, &self.maps.global);
        write_map(&mut w, &self.maps.caustic);
        write_map(&mut w, &self.maps.volume);
        match &self.maps.volume_points {
            Some(vp) => {
                w.u8(1);
                let (points, max_r) = vp.parts();
                w.f32(max_r);
                w.u64(points.len() as u64);
                for p in points {
                    w.buf.extend_from_slice(&p.to_le_bytes());
                }
            }
            None => w.u8(0),
        }
        w.str(&serde_json::to_string(&self.stats).unwrap_or_default());
        match &self.cache {
            Some(c) => {
                w.u8(1);
                w.f32(c.tolerance);
                w.f32(c.cell());
                w.u64(c.len() as u64);
                for rec in c.records() {
                    write_record(&mut w, rec);
                }
            }
            None => w.u8(0),
        }
        container::encode(&MAP_FILE, &w.buf)
    }

    /// Reads the bytes of a photon-map file; `source` names it in errors.
    pub fn from_bytes(bytes: &[u8], source: &Path) -> Result<MapSet> {
        let payload = container::decode(&MAP_FILE, bytes, source)?;
        let mut r = Reader::new(payload, source, MAP_FILE.what);
        let _info = r.str("header")?;
        let key = r.u64("key")?;
        let mut a = [0u64; 7];
        for v in a.iter_mut() {
            *v = r.u64("key parts")?;
        }
        let parts = KeyParts {
            version: a[0],
            geometry: a[1],
            materials: a[2],
            lights: a[3],
            media: a[4],
            photon_settings: a[5],
            seed: a[6],
        };
        if parts.key() != key {
            return Err(r.corrupt("the key does not match its parts"));
        }
        let cache_view = r.u64("cache view")?;
        let gather = r.u64("gather")? as usize;
        let global_r2 = r.f32("global radius")?;
        let caustic_r2 = r.f32("caustic radius")?;
        let global = read_map(&mut r)?;
        let caustic = read_map(&mut r)?;
        let volume = read_map(&mut r)?;
        let volume_points = if r.u8("volume points present")? != 0 {
            let max_r = r.f32("volume points radius")?;
            let n = r.count(VolumePoint::BYTES, "volume points")?;
            let b = r.take(n * VolumePoint::BYTES, "volume points")?;
            Some(VolumePointMap::from_parts(
                b.chunks_exact(VolumePoint::BYTES)
                    .map(VolumePoint::from_le_bytes)
                    .collect(),
                max_r,
            ))
        } else {
            None
        };
        let stats_json = r.str("map stats")?;
        let stats = super::photons::parse_map_stats(stats_json).map_err(|e| r.corrupt(e))?;
        let cache = if r.u8("cache present")? != 0 {
            let tolerance = r.f32("cache tolerance")?;
            let cell = r.f32("cache cell")?;
            let n = r.count(RECORD_FLOATS * 4, "cache records")?;
            let mut c = IrradianceCache::new(tolerance, cell);
            for _ in 0..n {
                c.insert_stored(read_record(&mut r)?);
            }
            Some(c)
        } else {
            None
        };
        r.finish()?;
        Ok(MapSet {
            key,
            parts,
            maps: PhotonMaps {
                global,
                caustic,
                volume,
                volume_points,
                gather,
                global_r2,
                caustic_r2,
            },
            stats,
            cache,
            cache_view,
        })
    }

    /// Writes the set to `path` atomically.
    pub fn save(&self, path: &Path) -> Result<()> {
        container::write_atomic(path, &self.to_bytes())
    }

    /// Reads a photon-map file and checks its key against `expected`.
    pub fn load(path: &Path, expected: &KeyParts) -> Result<MapSet> {
        let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
        let set = MapSet::from_bytes(&bytes, path)?;
        check_key(&set, expected, &path.display().to_string())?;
        Ok(set)
    }
}

/// Checks that `s` can save or load photon maps: Jensen's mode (the progressive modes trace
/// a fresh map every pass) and no time budget when loading (the budget plans the photon
/// counts, so the key, from this machine's speed).
pub fn check_settings(s: &RenderSettings) -> Result<()> {
    let f = &s.photon_map_files();
    let setting = if f.load.is_some() {
        "load_photon_maps"
    } else if f.save.is_some() {
        "save_photon_maps"
    } else {
        return Ok(());
    };
    if s.mode != RenderMode::Jensen {
        return Err(Error::InvalidSetting {
            setting: setting.into(),
            message: format!(
                "photon maps are saved and loaded in the jensen mode only; the {} mode traces \
                 a fresh map every pass",
                match s.mode {
                    RenderMode::Sppm => "sppm",
                    _ => "pppm",
                }
            ),
        });
    }
    if f.load.is_some() && s.budget_seconds().is_some() {
        return Err(Error::InvalidSetting {
            setting: "load_photon_maps".into(),
            message: "cannot be combined with time_budget, which plans the photon counts \
                      (and so the maps' key) from this machine's speed"
                .into(),
        });
    }
    Ok(())
}
