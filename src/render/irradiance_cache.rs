//! Ward's irradiance cache (Ward, Rubinstein, Clear 1988) with rotational and translational
//! gradients (Ward & Heckbert 1992), used to evaluate final gathering sparsely on every
//! surface with a diffuse component and interpolate between records.

//!
//! A record at x_i with normal n_i and harmonic mean distance R_i contributes at x (normal n)
//! with weight w_i = 1 / (|x - x_i| / R_i + sqrt(1 - n . n_i)); records with w_i > 1/a count,
//! where a is the tolerance. E(x) = sum w_i (E_i + (n_i x n) . grad_r + (x - x_i) . grad_t) / sum w_i.
//! R_i is limited by the gradient of a second, independent gather (so that a record's weight
//! does not depend on its value's noise) and by its neighbours' radii (neighbour clamping).
//!
//! The cache is filled in deterministic rounds (see `render::renderer`), then only read, so
//! images do not depend on the thread count.

use crate::math::Spectrum;
use crate::render::terms::indirect::HemisphereGather;
use glam::Vec3;
use std::collections::HashMap;

#[derive(Clone, Debug)]
pub struct Record {
    pub p: Vec3,
    pub n: Vec3,
    pub irradiance: Spectrum,
    /// Harmonic mean distance, clamped.
    pub r: f32,
    pub grad_r: [Vec3; 3],
    pub grad_t: [Vec3; 3],
}

impl Record {
    /// A record of gather `g`, its radius of influence limited by the gradient of `probe`, a
    /// second gather at the same point with its own random rays.
    ///
    /// The radius must not depend on `g`'s noise: where it does, a record whose rays met a
    /// bright spot gets a steep gradient and a short radius, one whose rays missed it a
    /// flat gradient and a long radius, so the dark records carry more weight at lookup and
    /// the interpolated irradiance leans dark. With the radius from an independent gather,
    /// a record's weight and its value are independent, and the weighted mean is unbiased.
    pub fn new(
        p: Vec3,
        n: Vec3,
        g: &HemisphereGather,
        probe: &HemisphereGather,
        r_min: f32,
        r_max: f32,
    ) -> Record {
        // Gradient limit (Křivánek et al. 2006): no record reaches farther than the distance
        // over which its translational gradient would change its irradiance by 100%.
        let lum = crate::math::luminance(probe.irradiance);
        let grad = probe.grad_t[0] * 0.2126 + probe.grad_t[1] * 0.7152 + probe.grad_t[2] * 0.0722;
        let limit = if grad.length() > 0.0 {
            lum / grad.length()
        } else {
            f32::INFINITY
        };
        let harmonic = g.harmonic_distance;
        let r = harmonic.min(limit).clamp(r_min, r_max);
        // Ward & Heckbert: limit the translational gradient where R was clamped upwards.
        let scale = if harmonic < r { harmonic / r } else { 1.0 };
        Record {
            p,
            n,
            irradiance: g.irradiance,
            r,
            grad_r: g.grad_r,
            grad_t: g.grad_t.map(|v| v * scale),
        }
    }
}

/// Rays of the gather that sets a record's radius, per ray of the record's own gather.
pub const PROBE_RAY_SHARE: u32 = 4;
/// The least rays of that gather.
pub const MIN_PROBE_RAYS: u32 = 16;

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
    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    fn key(&self, p: Vec3) -> (i32, i32, i32) {
        let q = (p / self.cell).floor();
        (q.x as i32, q.y as i32, q.z as i32)
    }

    /// Inserts `rec` after neighbour clamping (Křivánek et al. 2006): no two records whose
    /// regions of influence meet have radii that differ by more than their distance,
    /// R_i <= R_j + |x_i - x_j|. A record next to a contact shadow or a corner has a short
    /// radius; clamping keeps the longer radii of records a little farther away from
    /// reaching across it. It shortens the new record and the records already stored, in
    /// insertion order, so the cache does not depend on the thread count.
    pub fn insert(&mut self, mut rec: Record) {
        let near = self.near(rec.p, rec.r * self.tolerance);
        for &j in &near {
            let other = &self.records[j as usize];
            let d = (rec.p - other.p).length();
            rec.r = rec.r.min(other.r + d);
        }
        for &j in &near {
            let other = &mut self.records[j as usize];
            let d = (rec.p - other.p).length();
            other.r = other.r.min(rec.r + d);
        }
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

    /// Indices of the stored records whose reach covers `p`'s cell, or that lie within
    /// `reach` of `p` (each once): the pairs whose regions of influence can meet.
    fn near(&self, p: Vec3, reach: f32) -> Vec<u32> {
        let lo = self.key(p - Vec3::splat(reach));
        let hi = self.key(p + Vec3::splat(reach));
        let cells = (hi.0 - lo.0 + 1) as f64 * (hi.1 - lo.1 + 1) as f64 * (hi.2 - lo.2 + 1) as f64;
        let mut out: Vec<u32> = self.grid.get(&self.key(p)).cloned().unwrap_or_default();
        if cells > self.records.len() as f64 {
            out.extend(0..self.records.len() as u32);
        } else {
            for x in lo.0..=hi.0 {
                for y in lo.1..=hi.1 {
                    for z in lo.2..=hi.2 {
                        if let Some(list) = self.grid.get(&(x, y, z)) {
                            out.extend(list.iter().copied().filter(|&j| {
                                (self.records[j as usize].p - p).length_squared() < reach * reach
                            }));
                        }
                    }
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Interpolated irradiance at `p` with normal `n`, or None when no record is close enough.
    pub fn lookup(&self, p: Vec3, n: Vec3) -> Option<Spectrum> {
        let list = self.grid.get(&self.key(p))?;
        let min_w = 1.0 / self.tolerance;
        let mut sum = Spectrum::ZERO;
        let mut wsum = 0.0f32;
        for &i in list {
            let rec = &self.records[i as usize];
            let d = p - rec.p;
            // A record in front of the point does not see the same surroundings.
            if d.dot((n + rec.n) * 0.5) < -0.05 * rec.r {
                continue;
            }
            let cos = n.dot(rec.n);
            if cos <= 0.0 {
                continue;
            }
            let err = d.length() / rec.r + (1.0 - cos).max(0.0).sqrt();
            let w = if err > 0.0 { 1.0 / err } else { f32::INFINITY };
            if w <= min_w {
                continue;
            }
            let w = w.min(1e6);
            let rot = rec.n.cross(n);
            let mut e = rec.irradiance;
            for c in 0..3 {
                e[c] += rot.dot(rec.grad_r[c]) + d.dot(rec.grad_t[c]);
            }
            sum += e.max(Spectrum::ZERO) * w;
            wsum += w;
        }
        (wsum > 0.0).then(|| sum / wsum)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gather(e: f32, grad: f32, harmonic: f32) -> HemisphereGather {
        HemisphereGather {
            irradiance: Spectrum::splat(e),
            harmonic_distance: harmonic,
            grad_r: [Vec3::ZERO; 3],
            grad_t: [Vec3::X * grad; 3],
        }
    }

    /// The radius follows the probe's gradient, never the record's own: a record whose own
    /// rays saw a steep gradient reaches as far as one whose rays saw none.
    #[test]
    fn radius_comes_from_the_probe_not_the_records_own_gather() {
        let (p, n) = (Vec3::ZERO, Vec3::Z);
        let probe = gather(1.0, 2.0, 10.0);
        let steep = Record::new(p, n, &gather(1.0, 50.0, 10.0), &probe, 0.01, 100.0);
        let flat = Record::new(p, n, &gather(1.0, 0.0, 10.0), &probe, 0.01, 100.0);
        assert_eq!(steep.r, flat.r);
        assert!(
            (steep.r - 0.5).abs() < 1e-6,
            "r = {}, the probe's E / |grad E|",
            steep.r
        );
        // The record keeps its own value and gradient.
        assert_eq!(steep.irradiance, Spectrum::ONE);
        assert_eq!(steep.grad_t[0], Vec3::X * 50.0);
        // A flat probe leaves the harmonic distance.
        let far = Record::new(
            p,
            n,
            &gather(1.0, 50.0, 3.0),
            &gather(1.0, 0.0, 9.0),
            0.01,
            100.0,
        );
        assert_eq!(far.r, 3.0);
    }

    /// A short record shortens the long ones whose reach covers it, and a new long record
    /// is shortened by a short one within its reach; records out of reach keep their radii.
    #[test]
    fn neighbour_clamping_bounds_radii_by_distance() {
        let flat = gather(1.0, 0.0, 1.0);
        let rec = |x: f32, r: f32| {
            Record::new(
                Vec3::X * x,
                Vec3::Z,
                &gather(1.0, 0.0, r),
                &flat,
                0.01,
                100.0,
            )
        };
        // Tolerance 0.5: a record of radius 4 reaches 2.
        let mut c = IrradianceCache::new(0.5, 0.5);
        c.insert(rec(0.0, 4.0));
        c.insert(rec(10.0, 4.0));
        c.insert(rec(1.0, 0.1));
        assert!((c.records[0].r - 1.1).abs() < 1e-5, "{}", c.records[0].r);
        assert_eq!(c.records[1].r, 4.0);
        assert_eq!(c.records[2].r, 0.1);
        c.insert(rec(11.5, 6.0));
        assert!((c.records[3].r - 5.5).abs() < 1e-5, "{}", c.records[3].r);
        assert_eq!(c.records[1].r, 4.0);
        // Far from everything: unchanged.
        c.insert(rec(40.0, 3.0));
        assert_eq!(c.records[4].r, 3.0);
    }
}
