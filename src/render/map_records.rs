//! The binary records of a photon-map file (`map_file`): photon maps with their kd-trees,
//! their precomputed points, and irradiance-cache records.

use super::irradiance_cache::Record;
use crate::error::Result;
use crate::io::container::{Reader, Writer};
use crate::math::Spectrum;
use crate::photon::irradiance::{IrradianceMap, IrradiancePoint};
use crate::photon::map::{MapKind, PhotonMap, PhotonTree};
use crate::photon::{Photon, PhotonF32, PhotonKdTree};
use glam::Vec3;

pub(super) fn write_map(w: &mut Writer, map: &Option<PhotonMap>) {
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
pub(super) fn write_points(w: &mut Writer, points: &Option<IrradianceMap>) {
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
pub(super) fn read_points(r: &mut Reader) -> Result<Option<IrradianceMap>> {
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

pub(super) fn read_map(r: &mut Reader) -> Result<Option<PhotonMap>> {
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
pub(super) const RECORD_FLOATS: usize = 3 + 3 + 3 + 1 + 9 + 9;

pub(super) fn write_record(w: &mut Writer, rec: &Record) {
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
pub(super) fn write_spectra(w: &mut Writer, v: &[Spectrum]) {
    w.u64(v.len() as u64);
    for s in v {
        w.f32(s.x);
        w.f32(s.y);
        w.f32(s.z);
    }
}

pub(super) fn read_spectra(r: &mut Reader, field: &str) -> Result<Vec<Spectrum>> {
    let n = r.count(12, field)?;
    let b = r.take(n * 12, field)?;
    let f = |c: &[u8]| f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
    Ok(b.chunks_exact(12)
        .map(|c| Spectrum::new(f(&c[0..4]), f(&c[4..8]), f(&c[8..12])))
        .collect())
}

pub(super) fn read_record(r: &mut Reader) -> Result<Record> {
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
