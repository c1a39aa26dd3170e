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
//! **The key.** A set is keyed by a hash (64-bit FNV-1a, [`keys`]) of the geometry (meshes,
//! instances), materials and textures, lights and environment (and light groups), media, the photon settings
//! (counts, gather, radius, final gathering and cache, bounces, power encoding, mode, terms,
//! specular depth), the seed and the version of the renderer and of the file format. Not the
//! camera nor the film. Each part's own hash is stored too, so that a mismatch says what
//! differs. Using a set under another key is an error ([`check_key`]), never a silently wrong
//! image; `photon_maps_mismatch rebuild` builds the maps again instead.
//!
//! **The file** is a [`container`] (magic `PMAPS`, a version, a CRC-32): a truncated, corrupt
//! or other-version file is an error naming the file and what is wrong.

use super::irradiance_cache::{IrradianceCache, Record};
use super::photons::{MapStats, PhotonMaps};
use super::settings::{RenderMode, RenderSettings};
use crate::error::{Error, Result};
use crate::io::container::{self, Fnv64, Kind, Reader, Writer};
use crate::math::Spectrum;
use crate::photon::irradiance::{IrradianceMap, IrradiancePoint};
use crate::photon::map::{MapKind, PhotonMap, PhotonTree};
use crate::photon::volume_points::{VolumePoint, VolumePointMap};
use crate::photon::{Photon, PhotonF32, PhotonKdTree};
use crate::scene::SceneDesc;
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The photon-map file (`.pmaps`): a container of this kind.
pub const MAP_FILE: Kind = Kind {
    magic: *b"PMAPS\0\r\n",
    version: 3,
    what: "photon-map file",
};

/// What to do when loaded photon maps do not match the render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum OnMismatch {
    /// Error: stop with an error that says what differs.
    #[default]
    Error,
    /// Rebuild: build the maps again (and save them where asked), noting why in the stats.
    Rebuild,
}

/// Photon-map files of a render (Jensen's mode).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MapFiles {
    /// Save the photon maps and the irradiance cache to this file.
    pub save: Option<PathBuf>,
    /// Load them from this file instead of building them.
    pub load: Option<PathBuf>,
    pub on_mismatch: OnMismatch,
}

/// The parts of a photon-map key, each hashed on its own (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KeyParts {
    pub version: u64,
    pub geometry: u64,
    pub materials: u64,
    pub lights: u64,
    pub media: u64,
    pub photon_settings: u64,
    pub seed: u64,
}

impl KeyParts {
    const NAMES: [&'static str; 7] = [
        "renderer version",
        "geometry",
        "materials",
        "lights",
        "media",
        "photon settings",
        "seed",
    ];

    fn array(&self) -> [u64; 7] {
        [
            self.version,
            self.geometry,
            self.materials,
            self.lights,
            self.media,
            self.photon_settings,
            self.seed,
        ]
    }

    /// The key: a hash of the parts.
    pub fn key(&self) -> u64 {
        let mut h = Fnv64::default();
        for v in self.array() {
            h.u64(v);
        }
        h.finish()
    }

    /// The names of the parts that differ from `other`'s.
    pub fn differences(&self, other: &KeyParts) -> Vec<&'static str> {
        Self::NAMES
            .iter()
            .zip(self.array().iter().zip(other.array()))
            .filter(|(_, (a, b))| **a != *b)
            .map(|(n, _)| *n)
            .collect()
    }
}

/// Hashes `v` as JSON into `h`, then a separator.
fn json(h: &mut Fnv64, v: &impl Serialize) {
    // Writing into the hasher cannot fail; a value serde cannot write hashes what it wrote.
    let _ = serde_json::to_writer(&mut *h, v);
    h.write(b"\x1e");
}

fn floats<const N: usize>(h: &mut Fnv64, v: &[[f32; N]]) {
    h.u64(v.len() as u64);
    for a in v {
        for x in a {
            h.write(&x.to_le_bytes());
        }
    }
}

/// The parts of the photon-map key of `desc` rendered with `s`.
pub fn key_parts(desc: &SceneDesc, s: &RenderSettings) -> KeyParts {
    let part = |f: &dyn Fn(&mut Fnv64)| {
        let mut h = Fnv64::default();
        f(&mut h);
        h.finish()
    };
    KeyParts {
        version: part(&|h| {
            h.write(env!("CARGO_PKG_VERSION").as_bytes());
            h.u64(MAP_FILE.version as u64);
        }),
        geometry: part(&|h| {
            h.u64(desc.meshes.len() as u64);
            for m in &desc.meshes {
                json(h, &(&m.name, m.material, &m.transform, m.interior_medium));
                floats(h, &m.positions);
                h.u64(m.indices.len() as u64);
                for t in &m.indices {
                    for i in t {
                        h.write(&i.to_le_bytes());
                    }
                }
                match &m.normals {
                    Some(n) => floats(h, n),
                    None => h.write(b"-"),
                }
                match &m.uvs {
                    Some(u) => floats(h, u),
                    None => h.write(b"-"),
                }
                match &m.material_indices {
                    Some(ids) => {
                        h.u64(ids.len() as u64);
                        for i in ids {
                            h.write(&i.to_le_bytes());
                        }
                    }
                    None => h.write(b"-"),
                }
            }
            json(h, &desc.instances);
        }),
        materials: part(&|h| {
            json(h, &desc.materials);
            h.u64(desc.textures.len() as u64);
            for t in &desc.textures {
                json(
                    h,
                    &(&t.name, t.width, t.height, t.channels, &t.wrap, &t.encoding),
                );
                h.u64(t.data.len() as u64);
                for x in &t.data {
                    h.write(&x.to_le_bytes());
                }
            }
        }),
        lights: part(&|h| {
            json(h, &desc.lights);
            json(h, &desc.environment);
            // Photons carry their light's group.
            json(h, &desc.lightgroups);
        }),
        media: part(&|h| {
            json(h, &desc.media);
            json(h, &desc.world_medium);
        }),
        photon_settings: part(&|h| {
            json(h, &s.photons);
            json(h, &(s.mode, s.terms, s.max_specular_depth));
        }),
        seed: part(&|h| h.u64(s.seed)),
    }
}

/// The settings that do not change the image, left out of the render key: the threads, the
/// memory limit, where photon maps are saved or loaded, and which block of pppm passes a
/// process renders (blocks of one render differ in it, and merge).
pub const NOT_IN_IMAGE: [&str; 4] = ["threads", "memory_limit", "photon_map_files", "pass_range"];

/// The keys of a render of `desc` with `s` (see [`super::RenderKeys`]). The render key hashes
/// every setting but [`NOT_IN_IMAGE`], as the settings serialise: a new setting is in it.
pub fn keys(desc: &SceneDesc, s: &RenderSettings) -> super::RenderKeys {
    let maps = key_parts(desc, s).key();
    let mut v = Fnv64::default();
    json(&mut v, &(&desc.camera, &desc.film));
    let view = v.finish();
    let mut r = Fnv64::default();
    r.u64(maps);
    r.u64(view);
    json(&mut r, &image_settings(s));
    super::RenderKeys {
        maps,
        view,
        render: r.finish(),
    }
}

/// The settings as JSON without [`NOT_IN_IMAGE`].
fn image_settings(s: &RenderSettings) -> serde_json::Value {
    let mut v = serde_json::to_value(s).unwrap_or_else(|e| unreachable!("settings serialise: {e}"));
    if let Some(map) = v.as_object_mut() {
        for k in NOT_IN_IMAGE {
            map.remove(k);
        }
    }
    v
}

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

fn write_map(w: &mut Writer, map: &Option<PhotonMap>) {
    let Some(m) = map else {
        w.u8(0);
        return;
    };
    w.u8(1);
    w.u8(match m.kind {
        MapKind::Global => 0,
        MapKind::Caustic => 1,
        MapKind::Volume => 2,
    });
    w.u64(m.emitted);
    w.f64(m.build_seconds);
    match &m.tree {
        PhotonTree::Rgbe(t, scale) => {
            w.u8(0);
            w.f32(*scale);
            w.u64(t.len() as u64);
            for p in t.photons() {
                w.buf.extend_from_slice(&p.to_le_bytes());
            }
        }
        PhotonTree::F32(t, scale) => {
            w.u8(1);
            w.f32(*scale);
            w.u64(t.len() as u64);
            for p in t.photons() {
                w.buf.extend_from_slice(&p.to_le_bytes());
            }
        }
    }
    write_points(w, &m.irradiance);
    write_points(w, &m.exitance);
}

/// A map's precomputed points (irradiance, or the subsurface exits' exitance), if any.
fn write_points(w: &mut Writer, points: &Option<IrradianceMap>) {
    match points {
        Some(irr) => {
            w.u8(1);
            let (points, max_r2) = irr.parts();
            w.f32(max_r2);
            w.u64(points.len() as u64);
            for p in points {
                w.buf.extend_from_slice(&p.to_le_bytes());
            }
            let (groups, fractions) = irr.group_parts();
            w.u64(groups as u64);
            write_spectra(w, fractions);
        }
        None => w.u8(0),
    }
}

/// The points of [`write_points`].
fn read_points(r: &mut Reader) -> Result<Option<IrradianceMap>> {
    if r.u8("points present")? == 0 {
        return Ok(None);
    }
    let max_r2 = r.f32("points' radius")?;
    let n = r.count(20, "precomputed points")?;
    let b = r.take(n * 20, "precomputed points")?;
    let points: Vec<IrradiancePoint> = b
        .chunks_exact(20)
        .map(IrradiancePoint::from_le_bytes)
        .collect();
    let groups = r.u64("points' light groups")? as usize;
    let fractions = read_spectra(r, "points' light-group fractions")?;
    if fractions.len() != points.len().saturating_mul(groups) {
        return Err(r.corrupt("the points' light-group fractions do not match"));
    }
    Ok(Some(IrradianceMap::from_parts(
        points, max_r2, groups, fractions,
    )))
}

fn read_map(r: &mut Reader) -> Result<Option<PhotonMap>> {
    if r.u8("map present")? == 0 {
        return Ok(None);
    }
    let kind = match r.u8("map kind")? {
        0 => MapKind::Global,
        1 => MapKind::Caustic,
        2 => MapKind::Volume,
        k => return Err(r.corrupt(format!("unknown map kind {k}"))),
    };
    let emitted = r.u64("photons emitted")?;
    let build_seconds = r.f64("build seconds")?;
    let tree = match r.u8("photon record")? {
        0 => {
            let scale = r.f32("power scale")?;
            let n = r.count(Photon::BYTES, "photons")?;
            let b = r.take(n * Photon::BYTES, "photons")?;
            PhotonTree::Rgbe(
                PhotonKdTree::from_heap(
                    b.chunks_exact(Photon::BYTES)
                        .map(Photon::from_le_bytes)
                        .collect(),
                ),
                scale,
            )
        }
        1 => {
            let scale = r.f32("power scale")?;
            let n = r.count(PhotonF32::BYTES, "photons")?;
            let b = r.take(n * PhotonF32::BYTES, "photons")?;
            PhotonTree::F32(
                PhotonKdTree::from_heap(
                    b.chunks_exact(PhotonF32::BYTES)
                        .map(PhotonF32::from_le_bytes)
                        .collect(),
                ),
                scale,
            )
        }
        k => return Err(r.corrupt(format!("unknown photon record {k}"))),
    };
    let irradiance = read_points(r)?;
    let exitance = read_points(r)?;
    Ok(Some(PhotonMap {
        kind,
        tree,
        irradiance,
        exitance,
        emitted,
        build_seconds,
    }))
}

/// Floats per irradiance-cache record: position, normal, irradiance, radius, gradients
/// (then its light groups' fractions, counted).
const RECORD_FLOATS: usize = 3 + 3 + 3 + 1 + 9 + 9;

fn write_record(w: &mut Writer, rec: &Record) {
    let v3 = |w: &mut Writer, v: Vec3| {
        w.f32(v.x);
        w.f32(v.y);
        w.f32(v.z);
    };
    v3(w, rec.p);
    v3(w, rec.n);
    v3(w, rec.irradiance);
    w.f32(rec.r);
    for g in rec.grad_r.iter().chain(&rec.grad_t) {
        v3(w, *g);
    }
    write_spectra(w, &rec.groups);
}

/// A count, then RGB `f32`s.
fn write_spectra(w: &mut Writer, v: &[Spectrum]) {
    w.u64(v.len() as u64);
    for s in v {
        w.f32(s.x);
        w.f32(s.y);
        w.f32(s.z);
    }
}

fn read_spectra(r: &mut Reader, field: &str) -> Result<Vec<Spectrum>> {
    let n = r.count(12, field)?;
    let b = r.take(n * 12, field)?;
    let f = |c: &[u8]| f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
    Ok(b.chunks_exact(12)
        .map(|c| Spectrum::new(f(&c[0..4]), f(&c[4..8]), f(&c[8..12])))
        .collect())
}

fn read_record(r: &mut Reader) -> Result<Record> {
    let v3 = |r: &mut Reader| -> Result<Vec3> {
        Ok(Vec3::new(
            r.f32("cache record")?,
            r.f32("cache record")?,
            r.f32("cache record")?,
        ))
    };
    let p = v3(r)?;
    let n = v3(r)?;
    let irradiance: Spectrum = v3(r)?;
    let radius = r.f32("cache record")?;
    let mut g = [Vec3::ZERO; 6];
    for x in g.iter_mut() {
        *x = v3(r)?;
    }
    Ok(Record {
        p,
        n,
        irradiance,
        r: radius,
        // A stored record was clamped by its neighbours when its cache was filled (it is read
        // back unclamped); extending the cache for another view may shrink it by distance to
        // new records, not by their irradiance.
        r_min: radius,
        grad_r: [g[0], g[1], g[2]],
        grad_t: [g[3], g[4], g[5]],
        groups: read_spectra(r, "cache record light groups")?,
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
        let stats = parse_map_stats(stats_json).map_err(|e| r.corrupt(e))?;
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

/// [`MapStats`] read back from JSON (the map names are the three static ones).
fn parse_map_stats(text: &str) -> std::result::Result<Vec<MapStats>, String> {
    #[derive(Deserialize)]
    struct In {
        map: String,
        built: bool,
        stored: u64,
        emitted: u64,
        memory_bytes: u64,
        bytes_per_photon: u64,
        max_radius: f32,
        seconds: f64,
        kdtree_seconds: f64,
        irradiance_points: u64,
        #[serde(default)]
        volume_points: u64,
        #[serde(default)]
        exitance_points: u64,
        skipped_because: Option<String>,
    }
    let v: Vec<In> = serde_json::from_str(text).map_err(|e| format!("map stats: {e}"))?;
    v.into_iter()
        .map(|m| {
            let map = match m.map.as_str() {
                "global" => "global",
                "caustic" => "caustic",
                "volume" => "volume",
                other => return Err(format!("map stats: unknown map `{other}`")),
            };
            Ok(MapStats {
                map,
                built: m.built,
                stored: m.stored,
                emitted: m.emitted,
                memory_bytes: m.memory_bytes,
                bytes_per_photon: m.bytes_per_photon,
                max_radius: m.max_radius,
                seconds: m.seconds,
                kdtree_seconds: m.kdtree_seconds,
                irradiance_points: m.irradiance_points,
                volume_points: m.volume_points,
                exitance_points: m.exitance_points,
                skipped_because: m.skipped_because,
            })
        })
        .collect()
}

/// Checks that `s` can save or load photon maps: Jensen's mode (the progressive modes trace
/// a fresh map every pass) and no time budget when loading (the budget plans the photon
/// counts, so the key, from this machine's speed).
pub fn check_settings(s: &RenderSettings) -> Result<()> {
    let f = &s.photon_map_files;
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
    if f.load.is_some() && s.time_budget.is_some() {
        return Err(Error::InvalidSetting {
            setting: "load_photon_maps".into(),
            message: "cannot be combined with time_budget, which plans the photon counts \
                      (and so the maps' key) from this machine's speed"
                .into(),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every setting that changes the image changes the render key; the threads, the memory
    /// limit, the map files and the block of passes do not.
    #[test]
    fn the_render_key_covers_every_setting_that_changes_the_image() {
        let desc = crate::scene::default_scene();
        let base = RenderSettings::default();
        let key = |s: &RenderSettings| keys(&desc, s).render;
        let k0 = key(&base);
        let all = serde_json::to_value(&base).unwrap();
        for k in NOT_IN_IMAGE {
            assert!(all.get(k).is_some(), "{k} is a setting");
        }
        let changed: Vec<(&str, RenderSettings)> = vec![
            (
                "spp",
                RenderSettings {
                    spp: 9,
                    ..base.clone()
                },
            ),
            (
                "noise_threshold",
                RenderSettings {
                    noise_threshold: 0.3,
                    ..base.clone()
                },
            ),
            (
                "sppm_initial_photons",
                RenderSettings {
                    sppm_initial_photons: 7,
                    ..base.clone()
                },
            ),
            (
                "pppm_initial_radius",
                RenderSettings {
                    pppm_initial_radius: Some(0.1),
                    ..base.clone()
                },
            ),
            (
                "gather_rays_per_sample",
                RenderSettings {
                    gather_rays_per_sample: Some(3),
                    ..base.clone()
                },
            ),
            (
                "progressive",
                RenderSettings {
                    progressive: true,
                    ..base.clone()
                },
            ),
        ];
        for (what, s) in &changed {
            assert_ne!(key(s), k0, "{what}");
        }
        let mut photons = base.clone();
        photons.photons.volume_points = false;
        assert_ne!(key(&photons), k0, "photons.volume_points");
        let same = RenderSettings {
            threads: 3,
            memory_limit: Some(1 << 30),
            pass_range: Some((2, 5)),
            ..base.clone()
        };
        assert_eq!(key(&same), k0);
    }
}
