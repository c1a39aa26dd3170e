//! Ward's irradiance cache (Ward, Rubinstein, Clear 1988) with rotational and translational
//! gradients (Ward & Heckbert 1992), used to evaluate final gathering sparsely on every
//! surface with a diffuse component and interpolate between records.

//!
//! A record at x_i with normal n_i and harmonic mean distance R_i contributes at x (normal n)
//! with weight w_i = 1 / (|x - x_i| / R_i + sqrt(1 - n . n_i)); records with w_i > 1/a count,
//! where a is the tolerance. E(x) = sum w_i (E_i + (n_i x n) . grad_r + (x - x_i) . grad_t) / sum w_i.
//!
//! The cache is filled in deterministic rounds (see `render::renderer`), then only read, so
//! images do not depend on the thread count. Each record inserted clamps its neighbours' radii
//! and its own (see [`IrradianceCache::insert`]).

use crate::math::Spectrum;
use crate::render::lightgroups::Split;
use crate::render::terms::indirect::HemisphereGather;
use glam::Vec3;
use std::collections::HashMap;

/// Records whose normals agree to within this cosine limit each other's radius by the change
/// of irradiance between them (see [`IrradianceCache::insert`]).
const DIFFERENCE_COS: f32 = 0.95;

#[derive(Clone, Debug)]
pub struct Record {
    pub p: Vec3,
    pub n: Vec3,
    pub irradiance: Spectrum,
    /// Harmonic mean distance, clamped.
    pub r: f32,
    /// The least radius the record may be clamped to.
    pub r_min: f32,
    pub grad_r: [Vec3; 3],
    pub grad_t: [Vec3; 3],
    /// With light groups: each group's fraction of `irradiance`, per channel (empty
    /// without groups).
    pub groups: Vec<Spectrum>,
}

impl Record {
    pub fn new(p: Vec3, n: Vec3, g: &HemisphereGather, r_min: f32, r_max: f32) -> Record {
        // Gradient limit (Křivánek et al. 2006): no record reaches farther than the distance
        // over which its translational gradient would change its irradiance by 100%.
        let lum = crate::math::luminance(g.irradiance);
        let grad = g.grad_t[0] * 0.2126 + g.grad_t[1] * 0.7152 + g.grad_t[2] * 0.0722;
        let limit = if grad.length() > 0.0 {
            lum / grad.length()
        } else {
            f32::INFINITY
        };
        let r = g.harmonic_distance.min(limit).clamp(r_min, r_max);
        // Ward & Heckbert: limit the translational gradient where R was clamped upwards.
        let scale = if g.harmonic_distance < r {
            g.harmonic_distance / r
        } else {
            1.0
        };
        Record {
            p,
            n,
            irradiance: g.irradiance,
            r,
            r_min,
            grad_r: g.grad_r,
            grad_t: g.grad_t.map(|v| v * scale),
            groups: Vec::new(),
        }
    }
}

#[derive(Clone)]
pub struct IrradianceCache {
    pub tolerance: f32,
    records: Vec<Record>,
    cell: f32,
    grid: HashMap<(i32, i32, i32), Vec<u32>>,
}

impl IrradianceCache {
    /// `cell` should be about the largest radius of influence (a R_max).
    pub fn new(tolerance: f32, cell: f32) -> Self {
        IrradianceCache {
            tolerance,
            records: Vec::new(),
            cell: cell.max(1e-12),
            grid: HashMap::new(),
        }
    }

    pub fn len(&self) -> usize {
        self.records.len()
    }

    /// The grid's cell size.
    pub fn cell(&self) -> f32 {
        self.cell
    }

    /// The records, in the order they were inserted.
    pub fn records(&self) -> &[Record] {
        &self.records
    }
    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    fn key(&self, p: Vec3) -> (i32, i32, i32) {
        let q = (p / self.cell).floor();
        (q.x as i32, q.y as i32, q.z as i32)
    }

    /// Adds `rec` after clamping its radius and its neighbours' (the records that reach its
    /// grid cell and face the same side), both ways:
    /// - neighbour clamping (Křivánek et al. 2006): two records at distance d differ in
    ///   radius by at most d, so a record placed early, over an open view, does not reach
    ///   across the small features later records find;
    /// - the gradient limit of [`Record::new`] over the pair: where two records of nearly the
    ///   same normal differ in irradiance by dE at distance d, neither reaches farther than
    ///   the distance over which that change, E d / dE, would be 100% of its own irradiance.
    ///   A record's own gradient, from a few dozen gather rays, misses much of a smooth
    ///   change over a record's radius; the difference between records measures it.
    pub fn insert(&mut self, mut rec: Record) {
        if let Some(list) = self.grid.get(&self.key(rec.p)) {
            for &j in list {
                rec.r = clamped(&rec, &self.records[j as usize]);
            }
            for &j in list {
                let other = &mut self.records[j as usize];
                other.r = clamped(other, &rec);
            }
        }
        self.insert_stored(rec);
    }

    /// Ends a fill: each record's radius as clamped becomes its least radius, and the grid
    /// holds each record where its final radius reaches. The cache is then in the state it
    /// is read back in from a map file ([`IrradianceCache::insert_stored`] of its records in
    /// order), so that extending it for another view gives the same records either way.
    pub fn settle(&mut self) {
        let records = std::mem::take(&mut self.records);
        self.grid.clear();
        for mut rec in records {
            rec.r_min = rec.r;
            self.insert_stored(rec);
        }
    }

    /// Adds `rec` as it is, without clamping: a record read back from a cache that was
    /// filled (and clamped) before, so that the cache answers as it did.
    pub fn insert_stored(&mut self, rec: Record) {
        let idx = self.records.len() as u32;
        let reach = rec.r * self.tolerance;
        let lo = self.key(rec.p - Vec3::splat(reach));
        let hi = self.key(rec.p + Vec3::splat(reach));
        for x in lo.0..=hi.0 {
            for y in lo.1..=hi.1 {
                for z in lo.2..=hi.2 {
                    self.grid.entry((x, y, z)).or_default().push(idx);
                }
            }
        }
        self.records.push(rec);
    }

    /// The weight of record `rec` at `p` with normal `n` (Ward's 1 / error, capped at 1e6),
    /// or None when it does not apply there.
    #[inline]
    fn weight(&self, rec: &Record, p: Vec3, n: Vec3) -> Option<f32> {
        let d = p - rec.p;
        // A record in front of the point does not see the same surroundings.
        if d.dot((n + rec.n) * 0.5) < -0.05 * rec.r {
            return None;
        }
        let cos = n.dot(rec.n);
        if cos <= 0.0 {
            return None;
        }
        let err = d.length() / rec.r + (1.0 - cos).max(0.0).sqrt();
        let w = if err > 0.0 { 1.0 / err } else { f32::INFINITY };
        (w > 1.0 / self.tolerance).then(|| w.min(1e6))
    }

    /// Interpolated irradiance at `p` with normal `n`, or None when no record is close
    /// enough. With `split`, each light group's share goes to it: the irradiance split by
    /// the records' group fractions, interpolated with the same weights.
    pub fn lookup(&self, p: Vec3, n: Vec3, split: Option<&mut Split>) -> Option<Spectrum> {
        let list = self.grid.get(&self.key(p))?;
        let mut sum = Spectrum::ZERO;
        let mut wsum = 0.0f32;
        for &i in list {
            let rec = &self.records[i as usize];
            let Some(w) = self.weight(rec, p, n) else {
                continue;
            };
            let d = p - rec.p;
            let rot = rec.n.cross(n);
            let mut e = rec.irradiance;
            for c in 0..3 {
                e[c] += rot.dot(rec.grad_r[c]) + d.dot(rec.grad_t[c]);
            }
            sum += e.max(Spectrum::ZERO) * w;
            wsum += w;
        }
        if !(wsum > 0.0) {
            return None;
        }
        let e = sum / wsum;
        if let Some(sp) = split {
            for &i in list {
                let rec = &self.records[i as usize];
                if let Some(w) = self.weight(rec, p, n) {
                    sp.add_fractions(e * (w / wsum), &rec.groups);
                }
            }
        }
        Some(e)
    }
}

/// The radius of `rec` clamped by its neighbour `other` (see [`IrradianceCache::insert`]).
fn clamped(rec: &Record, other: &Record) -> f32 {
    let cos = other.n.dot(rec.n);
    if cos <= 0.0 {
        return rec.r;
    }
    let d = (other.p - rec.p).length();
    let mut r = rec.r.min(other.r + d);
    if cos > DIFFERENCE_COS {
        let lum = crate::math::luminance(rec.irradiance);
        let diff = (crate::math::luminance(other.irradiance) - lum).abs();
        if diff > 0.0 {
            r = r.min((lum * d / diff).max(rec.r_min));
        }
    }
    r
}
