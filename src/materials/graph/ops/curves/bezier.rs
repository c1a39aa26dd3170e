//! The Bézier segments between a curve's points, as Blender computes them: the handles of
//! each knot, the correction that keeps a segment's handles from overlapping in x, and the
//! samples of a segment.

use super::HandleType;
use glam::Vec2;

/// A Bézier knot: left handle, point, right handle.
#[derive(Clone, Copy, Debug)]
pub(super) struct Knot {
    pub(super) h1: Vec2,
    pub(super) p: Vec2,
    pub(super) h2: Vec2,
    pub(super) handle: HandleType,
}

/// Blender's `calchandle_curvemap`.
pub(super) fn calc_handles(knot: &mut Knot, prev: Option<Knot>, next: Option<Knot>) {
    let p2 = knot.p;
    let (p1, p3) = match (prev, next) {
        (None, Some(n)) => (2.0 * p2 - n.p, n.p),
        (Some(pr), None) => (pr.p, 2.0 * p2 - pr.p),
        (Some(pr), Some(n)) => (pr.p, n.p),
        (None, None) => return,
    };
    let dvec_a = p2 - p1;
    let dvec_b = p3 - p2;
    let mut len_a = dvec_a.length();
    let mut len_b = dvec_b.length();
    if len_a == 0.0 {
        len_a = 1.0;
    }
    if len_b == 0.0 {
        len_b = 1.0;
    }
    let auto = matches!(knot.handle, HandleType::Auto | HandleType::AutoClamped);
    if auto {
        let tvec = dvec_b / len_b + dvec_a / len_a;
        let len = tvec.length() * 2.5614;
        if len != 0.0 {
            len_a /= len;
            knot.h1 = p2 + tvec * -len_a;
            let clamped = knot.handle == HandleType::AutoClamped;
            if let (true, Some(pr), Some(n)) = (clamped, prev, next) {
                let ydiff1 = pr.p.y - p2.y;
                let ydiff2 = n.p.y - p2.y;
                if (ydiff1 <= 0.0 && ydiff2 <= 0.0) || (ydiff1 >= 0.0 && ydiff2 >= 0.0) {
                    knot.h1.y = p2.y;
                } else if ydiff1 <= 0.0 {
                    knot.h1.y = pr.p.y.max(knot.h1.y);
                } else {
                    knot.h1.y = pr.p.y.min(knot.h1.y);
                }
            }
            len_b /= len;
            knot.h2 = p2 + tvec * len_b;
            if let (true, Some(pr), Some(n)) = (clamped, prev, next) {
                let ydiff1 = pr.p.y - p2.y;
                let ydiff2 = n.p.y - p2.y;
                if (ydiff1 <= 0.0 && ydiff2 <= 0.0) || (ydiff1 >= 0.0 && ydiff2 >= 0.0) {
                    knot.h2.y = p2.y;
                } else if ydiff1 <= 0.0 {
                    knot.h2.y = n.p.y.min(knot.h2.y);
                } else {
                    knot.h2.y = n.p.y.max(knot.h2.y);
                }
            }
        }
    }
    if knot.handle == HandleType::Vector {
        knot.h1 = p2 + dvec_a * (-1.0 / 3.0);
        knot.h2 = p2 + dvec_b * (1.0 / 3.0);
    }
}

/// Blender's `BKE_curve_correct_bezpart`: keep the handles of one segment
/// from overlapping in x.
pub(super) fn correct_bezpart(v1: Vec2, v2: &mut Vec2, v3: &mut Vec2, v4: Vec2) {
    let h1 = v1 - *v2;
    let h2 = v4 - *v3;
    let len = v4.x - v1.x;
    let len1 = h1.x.abs();
    let len2 = h2.x.abs();
    if len1 + len2 == 0.0 {
        return;
    }
    if len1 + len2 > len {
        let fac = len / (len1 + len2);
        *v2 = v1 - fac * h1;
        *v3 = v4 - fac * h2;
    }
}

/// Blender's `BKE_curve_forward_diff_bezier`: `it + 1` samples of one
/// coordinate of a cubic Bézier.
pub(super) fn forward_diff_bezier(
    q0: f32,
    q1: f32,
    q2: f32,
    q3: f32,
    it: usize,
    out: &mut Vec<f32>,
) {
    let mut f = it as f32;
    let rt0 = q0;
    let rt1 = 3.0 * (q1 - q0) / f;
    f *= f;
    let rt2 = 3.0 * (q0 - 2.0 * q1 + q2) / f;
    f *= it as f32;
    let rt3 = (q3 - q0 + 3.0 * (q1 - q2)) / f;
    let (mut a, mut b, mut c) = (rt0, rt1 + rt2 + rt3, 2.0 * rt2 + 6.0 * rt3);
    let d = 6.0 * rt3;
    for _ in 0..=it {
        out.push(a);
        a += b;
        b += c;
        c += d;
    }
}
