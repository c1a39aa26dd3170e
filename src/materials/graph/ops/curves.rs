//! The Float Curve and RGB Curves nodes.
//!
//! | item | meaning |
//! | --- | --- |
//! | [`CurvePoint`] | a control point: `x`, `y` (RNA `location`) and [`HandleType`] (RNA `handle_type`) |
//! | [`CurveExtend`] | RNA `CurveMapping.extend`: flat or extrapolated beyond the end points |
//! | [`CurveMap`] | one curve, evaluated as Blender's `BKE_curvemap_evaluateF` (Bézier through the points, sampled into a 257-entry table) |
//! | [`FloatCurve`] | the Float Curve node: Factor, Value → Value |
//! | [`RgbCurves`] | the RGB Curves node: Fac, Color → Color; curves C (combined), R, G, B |
//!
//! Cycles bakes each node into a further 257-entry table over the points' x
//! range (for RGB Curves, each channel curve applied after the combined
//! one), which the node interpolates linearly, and extrapolates linearly
//! from the table's end slopes when the mapping extrapolates. The nodes here
//! do the same. The table range also covers the mapping's clipping rectangle
//! in x, (0, 1) unless changed ([`CurveMap::with_clip_x`]); clipping of y,
//! black/white levels and the film-like tone are not applied by Cycles
//! either. Wrapping curves (hue correction) are not supported.

mod bezier;

use super::ramp::{table_lookup, RAMP_TABLE_SIZE};
use bezier::{calc_handles, correct_bezpart, forward_diff_bezier, Knot};
use glam::{Vec2, Vec3};

/// Blender's `CM_TABLE`: intervals of a curve's evaluation table.
const CM_TABLE: usize = 256;
/// Blender's `CM_RESOL`: samples per Bézier segment.
const CM_RESOL: usize = 32;

/// Handle type of a curve point (RNA `handle_type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum HandleType {
    Auto,
    AutoClamped,
    Vector,
}

impl HandleType {
    /// From Blender's RNA identifier (`"AUTO"`, `"AUTO_CLAMPED"`, `"VECTOR"`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        match identifier {
            "AUTO" => Some(Self::Auto),
            "AUTO_CLAMPED" => Some(Self::AutoClamped),
            "VECTOR" => Some(Self::Vector),
            _ => None,
        }
    }
}

/// Extension beyond the end points (RNA `CurveMapping.extend`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CurveExtend {
    Horizontal,
    Extrapolated,
}

impl CurveExtend {
    /// From Blender's RNA identifier (`"HORIZONTAL"`, `"EXTRAPOLATED"`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        match identifier {
            "HORIZONTAL" => Some(Self::Horizontal),
            "EXTRAPOLATED" => Some(Self::Extrapolated),
            _ => None,
        }
    }
}

/// A control point of a curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvePoint {
    pub x: f32,
    pub y: f32,
    pub handle: HandleType,
}

impl CurvePoint {
    pub fn new(x: f32, y: f32, handle: HandleType) -> Self {
        Self { x, y, handle }
    }
}

/// One curve of a curve mapping, with its evaluation table.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveMap {
    points: Vec<CurvePoint>,
    extend: CurveExtend,
    mintable: f32,
    /// Inverse of the table step.
    range: f32,
    table: Vec<Vec2>,
    ext_in: Vec2,
    ext_out: Vec2,
}

impl CurveMap {
    /// A curve through `points` (any order; sorted stably by x), with the
    /// default clipping range x ∈ [0, 1].
    pub fn new(points: &[CurvePoint], extend: CurveExtend) -> Self {
        Self::with_clip_x(points, extend, 0.0, 1.0)
    }

    /// A curve whose mapping has clipping range x ∈ [`clip_min_x`, `clip_max_x`].
    pub fn with_clip_x(
        points: &[CurvePoint],
        extend: CurveExtend,
        clip_min_x: f32,
        clip_max_x: f32,
    ) -> Self {
        let mut points = points.to_vec();
        points.sort_by(|a, b| a.x.total_cmp(&b.x));
        let mut map = CurveMap {
            points,
            extend,
            mintable: clip_min_x,
            range: 0.0,
            table: Vec::new(),
            ext_in: Vec2::ZERO,
            ext_out: Vec2::ZERO,
        };
        map.make_table(clip_min_x, clip_max_x);
        map
    }

    /// The control points, sorted by x.
    pub fn points(&self) -> &[CurvePoint] {
        &self.points
    }

    fn extrapolates(&self) -> bool {
        self.extend == CurveExtend::Extrapolated
    }

    /// Blender's `curvemap_make_table` (without wrapping).
    fn make_table(&mut self, clip_min: f32, clip_max: f32) {
        let mut mintable = clip_min;
        let mut maxtable = clip_max;
        let zero = Knot {
            h1: Vec2::ZERO,
            p: Vec2::ZERO,
            h2: Vec2::ZERO,
            handle: HandleType::Auto,
        };
        let mut knots: Vec<Knot> = if self.points.len() >= 2 {
            self.points
                .iter()
                .map(|p| {
                    mintable = mintable.min(p.x);
                    maxtable = maxtable.max(p.x);
                    Knot {
                        p: Vec2::new(p.x, p.y),
                        handle: p.handle,
                        ..zero
                    }
                })
                .collect()
        } else {
            mintable = 0.0;
            maxtable = 0.0;
            vec![zero, zero]
        };
        let n = knots.len();
        let mut prev = None;
        for a in 0..n {
            let next = knots.get(a + 1).copied();
            calc_handles(&mut knots[a], prev, next);
            prev = Some(knots[a]);
        }
        // First and last auto handles point towards the closest handle.
        if n > 2 {
            if knots[0].handle == HandleType::Auto {
                let hlen = (knots[0].h2 - knots[0].p).length();
                let mut v = knots[1].h1;
                v.x = v.x.max(knots[0].p.x);
                let v = v - knots[0].p;
                let nlen = v.length();
                if nlen > f32::EPSILON {
                    let v = v * (hlen / nlen);
                    knots[0].h2 = v + knots[0].p;
                    knots[0].h1 = knots[0].p - v;
                }
            }
            let a = n - 1;
            if knots[a].handle == HandleType::Auto {
                let hlen = (knots[a].p - knots[a].h1).length();
                let mut v = knots[a - 1].h2;
                v.x = v.x.min(knots[a].p.x);
                let v = v - knots[a].p;
                let nlen = v.length();
                if nlen > f32::EPSILON {
                    let v = v * (hlen / nlen);
                    knots[a].h1 = v + knots[a].p;
                    knots[a].h2 = knots[a].p - v;
                }
            }
        }
        // Sample the Bézier segments.
        let mut xs = Vec::with_capacity((n - 1) * CM_RESOL);
        let mut ys = Vec::with_capacity((n - 1) * CM_RESOL);
        for a in 0..n - 1 {
            let (left, right) = knots.split_at_mut(a + 1);
            let (k0, k1) = (&mut left[a], &mut right[0]);
            correct_bezpart(k0.p, &mut k0.h2, &mut k1.h1, k1.p);
            forward_diff_bezier(k0.p.x, k0.h2.x, k1.h1.x, k1.p.x, CM_RESOL - 1, &mut xs);
            forward_diff_bezier(k0.p.y, k0.h2.y, k1.h1.y, k1.p.y, CM_RESOL - 1, &mut ys);
        }
        let all: Vec<Vec2> = xs
            .into_iter()
            .zip(ys)
            .map(|(x, y)| Vec2::new(x, y))
            .collect();
        // Unit-length end handles, for extrapolation.
        let ext_in = knots[0].h1 - knots[0].p;
        self.ext_in = ext_in / (ext_in.x * ext_in.x + ext_in.y * ext_in.y).sqrt();
        let ext_out = knots[n - 1].p - knots[n - 1].h2;
        self.ext_out = ext_out / (ext_out.x * ext_out.x + ext_out.y * ext_out.y).sqrt();

        let step = (1.0 / CM_TABLE as f32) * (maxtable - mintable);
        self.mintable = mintable;
        self.range = 1.0 / step;
        let first = all[0];
        let last_index = all.len() - 1;
        let last = all[last_index];
        let mut p = 0;
        self.table = (0..=CM_TABLE)
            .map(|a| {
                let cur_x = mintable + step * a as f32;
                while cur_x >= all[p].x && p != last_index {
                    p += 1;
                }
                let y = if p == 0 || (p == last_index && cur_x >= all[p].x) {
                    if (cur_x - all[p].x).abs() <= 1e-6 {
                        all[p].y
                    } else {
                        self.extend_value(cur_x, first, last)
                    }
                } else {
                    let mut fac1 = all[p].x - all[p - 1].x;
                    let fac2 = all[p].x - cur_x;
                    fac1 = if fac1 > f32::EPSILON {
                        fac2 / fac1
                    } else {
                        0.0
                    };
                    fac1 * all[p - 1].y + (1.0 - fac1) * all[p].y
                };
                Vec2::new(cur_x, y)
            })
            .collect();
    }

    /// Blender's `curvemap_calc_extend`: y beyond the first or last point.
    fn extend_value(&self, x: f32, first: Vec2, last: Vec2) -> f32 {
        if x <= first.x {
            if !self.extrapolates() {
                return first.y;
            }
            if self.ext_in.x == 0.0 {
                return first.y + self.ext_in.y * 10000.0;
            }
            return first.y + self.ext_in.y * (x - first.x) / self.ext_in.x;
        }
        if x >= last.x {
            if !self.extrapolates() {
                return last.y;
            }
            if self.ext_out.x == 0.0 {
                return last.y - self.ext_out.y * 10000.0;
            }
            return last.y + self.ext_out.y * (x - last.x) / self.ext_out.x;
        }
        0.0
    }

    /// Blender's `BKE_curvemap_evaluateF`.
    pub fn evaluate(&self, x: f32) -> f32 {
        let (Some(&t0), Some(&tn)) = (self.table.first(), self.table.last()) else {
            return 0.0;
        };
        let fi = (x - self.mintable) * self.range;
        if fi < 0.0 || fi > CM_TABLE as f32 {
            return self.extend_value(x, t0, tn);
        }
        let i = fi as i32;
        if i < 0 {
            return t0.y;
        }
        let i = i as usize;
        if i >= CM_TABLE {
            return tn.y;
        }
        let f = fi - i as f32;
        match (self.table.get(i), self.table.get(i + 1)) {
            (Some(a), Some(b)) => (1.0 - f) * a.y + f * b.y,
            _ => t0.y,
        }
    }

    fn first_x(&self) -> f32 {
        self.points.first().map_or(0.0, |p| p.x)
    }

    fn last_x(&self) -> f32 {
        self.points.last().map_or(0.0, |p| p.x)
    }
}

/// Cycles' ramp lookup with optional linear extrapolation (`float_ramp_lookup`
/// / `rgb_ramp_lookup`); `table` has at least two entries.
fn lookup_extrapolated<T>(table: &[T], f: f32, extrapolate: bool) -> T
where
    T: Copy
        + Default
        + std::ops::Mul<f32, Output = T>
        + std::ops::Add<Output = T>
        + std::ops::Sub<Output = T>,
{
    let n = table.len();
    if extrapolate && n >= 2 && !(0.0..=1.0).contains(&f) {
        let (t0, dy, f) = if f < 0.0 {
            (table[0], table[0] - table[1], -f)
        } else {
            (table[n - 1], table[n - 1] - table[n - 2], f - 1.0)
        };
        return t0 + dy * f * (n - 1) as f32;
    }
    table_lookup(table, f, true)
}

/// The Float Curve node, baked as Cycles bakes it.
#[derive(Clone, Debug, PartialEq)]
pub struct FloatCurve {
    table: Vec<f32>,
    min_x: f32,
    max_x: f32,
    extrapolate: bool,
}

impl FloatCurve {
    pub fn new(curve: &CurveMap) -> Self {
        let (min_x, max_x) = (curve.first_x(), curve.last_x());
        let range = max_x - min_x;
        let table = (0..=RAMP_TABLE_SIZE)
            .map(|i| curve.evaluate(min_x + i as f32 / RAMP_TABLE_SIZE as f32 * range))
            .collect();
        Self {
            table,
            min_x,
            max_x,
            extrapolate: curve.extrapolates(),
        }
    }

    /// Factor and Value inputs → Value output.
    pub fn eval(&self, factor: f32, value: f32) -> f32 {
        let relpos = (value - self.min_x) / (self.max_x - self.min_x);
        let v = lookup_extrapolated(&self.table, relpos, self.extrapolate);
        (1.0 - factor) * value + factor * v
    }
}

/// The RGB Curves node, baked as Cycles bakes it.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbCurves {
    table: Vec<Vec3>,
    min_x: f32,
    max_x: f32,
    extrapolate: bool,
}

impl RgbCurves {
    /// From the combined (C) curve and the R, G, B curves of one mapping
    /// (the mapping's extension is taken from `combined`).
    pub fn new(combined: &CurveMap, r: &CurveMap, g: &CurveMap, b: &CurveMap) -> Self {
        let all = [r, g, b, combined];
        let min_x = all.iter().map(|c| c.first_x()).fold(f32::MAX, f32::min);
        let max_x = all.iter().map(|c| c.last_x()).fold(-f32::MAX, f32::max);
        let range = max_x - min_x;
        let table = (0..=RAMP_TABLE_SIZE)
            .map(|i| {
                let t = min_x + i as f32 / RAMP_TABLE_SIZE as f32 * range;
                let c = combined.evaluate(t);
                Vec3::new(r.evaluate(c), g.evaluate(c), b.evaluate(c))
            })
            .collect();
        Self {
            table,
            min_x,
            max_x,
            extrapolate: combined.extrapolates(),
        }
    }

    /// Fac and Color inputs → Color output.
    pub fn eval(&self, fac: f32, color: Vec3) -> Vec3 {
        let range = self.max_x - self.min_x;
        let rel = (color - Vec3::splat(self.min_x)) / range;
        let mapped = Vec3::new(
            lookup_extrapolated(&self.table, rel.x, self.extrapolate).x,
            lookup_extrapolated(&self.table, rel.y, self.extrapolate).y,
            lookup_extrapolated(&self.table, rel.z, self.extrapolate).z,
        );
        (1.0 - fac) * color + fac * mapped
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::graph::ops::testutil::*;

    fn points(v: &serde_json::Value) -> Vec<CurvePoint> {
        v.as_array()
            .expect("points")
            .iter()
            .map(|p| CurvePoint {
                x: p["x"].as_f64().expect("x") as f32,
                y: p["y"].as_f64().expect("y") as f32,
                handle: HandleType::from_blender(p["handle"].as_str().expect("h")).expect("h"),
            })
            .collect()
    }

    fn extend(case: &serde_json::Value) -> CurveExtend {
        CurveExtend::from_blender(case["extend"].as_str().expect("extend")).expect("extend")
    }

    #[test]
    fn float_curve_matches_blender_and_cycles() {
        let data = parse(include_str!("testdata/curves.json"));
        let x = floats(&data["inputs"]["value"]);
        let fac = floats(&data["inputs"]["factor"]);
        let mut bad = Vec::new();
        for (n, case) in data["float_curves"]
            .as_array()
            .expect("cases")
            .iter()
            .enumerate()
        {
            let map = CurveMap::new(&points(&case["points"]), extend(case));
            let node = FloatCurve::new(&map);
            let exact = f32s(&case["exact"]);
            let cycles = f32s(&case["cycles"]);
            for i in 0..x.len() {
                let ours = map.evaluate(x[i]);
                if !close(ours, exact[i]) {
                    bad.push(format!(
                        "curve {n} exact at {}: {ours} vs {:?}",
                        x[i], exact[i]
                    ));
                }
                let ours = node.eval(fac[i], x[i]);
                if !close(ours, cycles[i]) {
                    bad.push(format!(
                        "curve {n} cycles at {} fac {}: {ours} vs {:?}",
                        x[i], fac[i], cycles[i]
                    ));
                }
            }
        }
        assert!(
            bad.is_empty(),
            "{} mismatches:\n{}",
            bad.len(),
            bad.join("\n")
        );
    }

    #[test]
    fn rgb_curves_match_blender_and_cycles() {
        let data = parse(include_str!("testdata/curves.json"));
        let x = floats(&data["inputs"]["value"]);
        let fac = floats(&data["inputs"]["factor"]);
        let color = vectors(&data["inputs"]["color"]);
        let mut bad = Vec::new();
        for (n, case) in data["rgb_curves"]
            .as_array()
            .expect("cases")
            .iter()
            .enumerate()
        {
            let ext = extend(case);
            let map = |k: &str| CurveMap::new(&points(&case["curves"][k]["points"]), ext);
            let (c, r, g, b) = (map("C"), map("R"), map("G"), map("B"));
            for (k, m) in [("C", &c), ("R", &r), ("G", &g), ("B", &b)] {
                let exact = f32s(&case["curves"][k]["exact"]);
                for i in 0..x.len() {
                    let ours = m.evaluate(x[i]);
                    if !close(ours, exact[i]) {
                        bad.push(format!(
                            "rgb {n} {k} exact at {}: {ours} vs {:?}",
                            x[i], exact[i]
                        ));
                    }
                }
            }
            let node = RgbCurves::new(&c, &r, &g, &b);
            for (i, rf) in vec3s(&case["cycles"]).into_iter().enumerate() {
                let ours = node.eval(fac[i], color[i]);
                if !close3(ours, rf) {
                    bad.push(format!(
                        "rgb {n} cycles at {} fac {}: {ours} vs {rf:?}",
                        color[i], fac[i]
                    ));
                }
            }
        }
        assert!(
            bad.is_empty(),
            "{} mismatches:\n{}",
            bad.len(),
            bad.join("\n")
        );
    }

    #[test]
    fn degenerate_curves_do_not_panic() {
        let nan = CurvePoint::new(f32::NAN, f32::NAN, HandleType::Auto);
        for pts in [vec![], vec![nan], vec![nan, nan, nan]] {
            for ext in [CurveExtend::Horizontal, CurveExtend::Extrapolated] {
                let m = CurveMap::new(&pts, ext);
                let f = FloatCurve::new(&m);
                let c = RgbCurves::new(&m, &m, &m, &m);
                for x in [f32::NAN, f32::INFINITY, -1.0, 0.5] {
                    let _ = m.evaluate(x);
                    let _ = f.eval(1.0, x);
                    let _ = c.eval(x, Vec3::splat(x));
                }
            }
        }
    }
}
