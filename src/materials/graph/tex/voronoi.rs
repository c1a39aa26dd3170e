//! The Voronoi Texture node (cellular noise), 1D to 4D, with fractal octaves.

mod point;

use super::Dimensions;
use glam::{Vec3, Vec4};
use point::Point;
use std::ops::{Add, Mul, Sub};

/// What the Voronoi texture computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum VoronoiFeature {
    /// Distance to the closest feature point (the node's default).
    #[default]
    F1,
    /// Distance to the second closest feature point.
    F2,
    /// F1 with smoothly blended cells.
    SmoothF1,
    /// Distance to the closest cell edge.
    DistanceToEdge,
    /// Radius of the largest sphere around the closest point fitting in its cell.
    NSphereRadius,
}

impl VoronoiFeature {
    /// From Blender's RNA identifier (`feature`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        Some(match identifier {
            "F1" => Self::F1,
            "F2" => Self::F2,
            "SMOOTH_F1" => Self::SmoothF1,
            "DISTANCE_TO_EDGE" => Self::DistanceToEdge,
            "N_SPHERE_RADIUS" => Self::NSphereRadius,
            _ => return None,
        })
    }
}

/// Distance metric between points (ignored in 1D).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum VoronoiMetric {
    /// Straight-line distance (the node's default).
    #[default]
    Euclidean,
    /// Sum of absolute coordinate differences.
    Manhattan,
    /// Largest absolute coordinate difference.
    Chebychev,
    /// p-norm with p = Exponent.
    Minkowski,
}

impl VoronoiMetric {
    /// From Blender's RNA identifier (`distance`).
    pub fn from_blender(identifier: &str) -> Option<Self> {
        Some(match identifier {
            "EUCLIDEAN" => Self::Euclidean,
            "MANHATTAN" => Self::Manhattan,
            "CHEBYCHEV" => Self::Chebychev,
            "MINKOWSKI" => Self::Minkowski,
            _ => return None,
        })
    }
}

/// Voronoi Texture: distances to jittered feature points on the unit lattice.
///
/// | Parameter    | Type     | Default   | Description |
/// |--------------|----------|-----------|-------------|
/// | `dimensions` | property | 3D        | `1D` uses W, `2D` Vector.xy, `3D` Vector, `4D` Vector and W |
/// | `feature`    | property | F1        | F1, F2, SMOOTH_F1, DISTANCE_TO_EDGE, N_SPHERE_RADIUS |
/// | `metric`     | property | EUCLIDEAN | EUCLIDEAN, MANHATTAN, CHEBYCHEV, MINKOWSKI (not used in 1D, nor by the last two features) |
/// | `normalize`  | property | false     | Divide Distance (and Color) by the largest possible value |
/// | Vector       | vector   | —         | Texture coordinate |
/// | W            | float    | 0         | Fourth coordinate |
/// | Scale        | float    | 5         | Multiplies Vector and W |
/// | Detail       | float    | 0         | Fractal octaves after the first, clamped to \[0, 15\] (not N_SPHERE_RADIUS) |
/// | Roughness    | float    | 0.5       | Octave amplitude gain, clamped to \[0, 1\] |
/// | Lacunarity   | float    | 2         | Octave frequency gain |
/// | Smoothness   | float    | 1         | SMOOTH_F1 blending width, clamped to \[0, 1\] |
/// | Exponent     | float    | 0.5       | MINKOWSKI exponent |
/// | Randomness   | float    | 1         | Jitter of the feature points, clamped to \[0, 1\] |
///
/// Outputs: Distance, Color (a hash of the chosen cell), Position (xyz of
/// the chosen feature point in the input space), W (its fourth coordinate)
/// and Radius (N_SPHERE_RADIUS only).  Outputs a feature does not produce
/// are zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct VoronoiTexture {
    /// Dimensions of the cell lattice.
    pub dimensions: Dimensions,
    /// Computed feature.
    pub feature: VoronoiFeature,
    /// Distance metric.
    pub metric: VoronoiMetric,
    /// Normalise Distance and Color.
    pub normalize: bool,
}

/// Socket values of the Voronoi Texture node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoronoiInputs {
    /// Texture coordinate.
    pub vector: Vec3,
    /// Fourth coordinate.
    pub w: f32,
    /// Coordinate scale.
    pub scale: f32,
    /// Fractal octaves after the first.
    pub detail: f32,
    /// Octave amplitude gain.
    pub roughness: f32,
    /// Octave frequency gain.
    pub lacunarity: f32,
    /// Smooth F1 blending width.
    pub smoothness: f32,
    /// Minkowski exponent.
    pub exponent: f32,
    /// Feature point jitter.
    pub randomness: f32,
}

impl Default for VoronoiInputs {
    fn default() -> Self {
        Self {
            vector: Vec3::ZERO,
            w: 0.0,
            scale: 5.0,
            detail: 0.0,
            roughness: 0.5,
            lacunarity: 2.0,
            smoothness: 1.0,
            exponent: 0.5,
            randomness: 1.0,
        }
    }
}

/// Outputs of the Voronoi Texture node.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct VoronoiOutput {
    /// Distance (F1, F2, SMOOTH_F1, DISTANCE_TO_EDGE).
    pub distance: f32,
    /// Cell colour (F1, F2, SMOOTH_F1).
    pub color: Vec3,
    /// Feature point position, xyz (F1, F2, SMOOTH_F1; zero in 1D).
    pub position: Vec3,
    /// Feature point position, w (F1, F2, SMOOTH_F1 in 1D and 4D).
    pub w: f32,
    /// N-sphere radius (N_SPHERE_RADIUS).
    pub radius: f32,
}

/// Clamped evaluation parameters.
#[derive(Clone, Copy)]
struct Params {
    scale: f32,
    detail: f32,
    roughness: f32,
    lacunarity: f32,
    smoothness: f32,
    exponent: f32,
    randomness: f32,
    max_distance: f32,
    normalize: bool,
    feature: VoronoiFeature,
    metric: VoronoiMetric,
}

/// One octave's result.
#[derive(Clone, Copy, Default)]
struct Octave {
    distance: f32,
    color: Vec3,
    /// Position as (x, y, z, w), unused components zero.
    position: Vec4,
}

#[inline]
fn mix(a: f32, b: f32, t: f32) -> f32 {
    a + t * (b - a)
}

#[inline]
fn smoothstep01(x: f32) -> f32 {
    if x < 0.0 {
        0.0
    } else if x >= 1.0 {
        1.0
    } else {
        (3.0 - 2.0 * x) * (x * x)
    }
}

/// Vector `a + (b - a) * t`, Cycles' `mix`.
#[inline]
fn vmix<V: Copy + Add<Output = V> + Sub<Output = V> + Mul<f32, Output = V>>(
    a: V,
    b: V,
    t: f32,
) -> V {
    a + (b - a) * t
}

fn f1<P: Point>(p: &Params, coord: P) -> Octave {
    let cell_position = coord.floor();
    let local = coord - cell_position;
    let mut min_distance = f32::MAX;
    let mut target_offset = P::splat(0.0);
    let mut target_position = P::splat(0.0);
    for i in 0..P::cells(1) {
        let off = P::cell(i, 1);
        let point = off + P::hash_point(cell_position, off) * p.randomness;
        let d = point.metric_bound(local, p.metric, p.exponent);
        if d < min_distance {
            target_offset = off;
            min_distance = d;
            target_position = point;
        }
    }
    Octave {
        distance: target_position.metric_distance(local, p.metric, p.exponent),
        color: P::hash_color(cell_position, target_offset),
        position: (target_position + cell_position).position(),
    }
}

fn smooth_f1<P: Point>(p: &Params, coord: P) -> Octave {
    let cell_position = coord.floor();
    let local = coord - cell_position;
    let mut smooth_distance = 0.0;
    let mut smooth_color = Vec3::ZERO;
    let mut smooth_position = P::splat(0.0);
    let mut h = -1.0;
    for i in 0..P::cells(2) {
        let off = P::cell(i, 2);
        let point = off + P::hash_point(cell_position, off) * p.randomness;
        let d = point.metric_distance(local, p.metric, p.exponent);
        h = if h == -1.0 {
            1.0
        } else {
            smoothstep01(0.5 + 0.5 * (smooth_distance - d) / p.smoothness)
        };
        let mut correction = p.smoothness * h * (1.0 - h);
        smooth_distance = mix(smooth_distance, d, h) - correction;
        correction /= 1.0 + 3.0 * p.smoothness;
        let cell_color = P::hash_color(cell_position, off);
        smooth_color = vmix(smooth_color, cell_color, h) - correction;
        smooth_position = vmix(smooth_position, point, h) - correction;
    }
    Octave {
        distance: smooth_distance,
        color: smooth_color,
        position: (cell_position + smooth_position).position(),
    }
}

fn f2<P: Point>(p: &Params, coord: P) -> Octave {
    let cell_position = coord.floor();
    let local = coord - cell_position;
    let (mut d1, mut d2) = (f32::MAX, f32::MAX);
    let zero = P::splat(0.0);
    let (mut off1, mut pos1, mut off2, mut pos2) = (zero, zero, zero, zero);
    for i in 0..P::cells(1) {
        let off = P::cell(i, 1);
        let point = off + P::hash_point(cell_position, off) * p.randomness;
        let d = point.metric_distance(local, p.metric, p.exponent);
        if d < d1 {
            d2 = d1;
            d1 = d;
            off2 = off1;
            off1 = off;
            pos2 = pos1;
            pos1 = point;
        } else if d < d2 {
            d2 = d;
            off2 = off;
            pos2 = point;
        }
    }
    Octave {
        distance: d2,
        color: P::hash_color(cell_position, off2),
        position: (pos2 + cell_position).position(),
    }
}

fn n_sphere_radius<P: Point>(p: &Params, coord: P) -> f32 {
    let cell_position = coord.floor();
    let local = coord - cell_position;
    let mut closest = P::splat(0.0);
    let mut closest_offset = P::splat(0.0);
    let mut min_distance = f32::MAX;
    for i in 0..P::cells(1) {
        let off = P::cell(i, 1);
        let point = off + P::hash_point(cell_position, off) * p.randomness;
        let d = point.euclidean_bound(local);
        if d < min_distance {
            min_distance = d;
            closest = point;
            closest_offset = off;
        }
    }
    let center = P::cells(1) / 2;
    let mut min_distance = f32::MAX;
    let mut closest_to_closest = P::splat(0.0);
    for i in (0..P::cells(1)).filter(|&i| i != center) {
        let off = P::cell(i, 1) + closest_offset;
        let point = off + P::hash_point(cell_position, off) * p.randomness;
        let d = closest.euclidean_bound(point);
        if d < min_distance {
            min_distance = d;
            closest_to_closest = point;
        }
    }
    closest_to_closest.euclidean(closest) / 2.0
}

/// Octaves of F1/F2/smooth F1, summed like fBm with lerps for positions.
fn fractal<P: Point>(p: &Params, coord: P) -> Octave {
    let mut amplitude = 1.0;
    let mut max_amplitude = 0.0;
    let mut scale = 1.0;
    let mut out = Octave::default();
    let zero_input = p.detail == 0.0 || p.roughness == 0.0;
    let last = p.detail.ceil();
    let mut i = 0;
    while (i as f32) <= last {
        let c = coord * scale;
        let octave = match p.feature {
            VoronoiFeature::F2 => f2(p, c),
            VoronoiFeature::SmoothF1 if p.smoothness != 0.0 => smooth_f1(p, c),
            _ => f1(p, c),
        };
        if zero_input {
            max_amplitude = 1.0;
            out = octave;
            break;
        }
        if i as f32 <= p.detail {
            max_amplitude += amplitude;
            out.distance += octave.distance * amplitude;
            out.color += octave.color * amplitude;
            out.position = vmix(out.position, octave.position / scale, amplitude);
            scale *= p.lacunarity;
            amplitude *= p.roughness;
        } else {
            let remainder = p.detail - p.detail.floor();
            if remainder != 0.0 {
                max_amplitude = mix(max_amplitude, max_amplitude + amplitude, remainder);
                out.distance = mix(
                    out.distance,
                    out.distance + octave.distance * amplitude,
                    remainder,
                );
                out.color = vmix(out.color, out.color + octave.color * amplitude, remainder);
                let lerped = vmix(out.position, octave.position / scale, amplitude);
                out.position = vmix(out.position, lerped, remainder);
            }
        }
        i += 1;
    }
    if p.normalize {
        out.distance /= max_amplitude * p.max_distance;
        out.color /= max_amplitude;
    }
    out.position = if p.scale != 0.0 {
        out.position / p.scale
    } else {
        Vec4::ZERO
    };
    out
}

/// Octaves of the distance to edge, combined with a running minimum.
fn fractal_distance_to_edge<P: Point>(p: &Params, coord: P) -> f32 {
    let mut amplitude = 1.0;
    let mut max_amplitude = p.max_distance;
    let mut scale = 1.0;
    let mut distance = 8.0f32;
    let zero_input = p.detail == 0.0 || p.roughness == 0.0;
    let last = p.detail.ceil();
    let mut i = 0;
    while (i as f32) <= last {
        let octave = P::distance_to_edge(p, coord * scale);
        if zero_input {
            distance = octave;
            break;
        }
        if i as f32 <= p.detail {
            max_amplitude = mix(max_amplitude, p.max_distance / scale, amplitude);
            distance = mix(distance, distance.min(octave / scale), amplitude);
            scale *= p.lacunarity;
            amplitude *= p.roughness;
        } else {
            let remainder = p.detail - p.detail.floor();
            if remainder != 0.0 {
                let lerp_amplitude = mix(max_amplitude, p.max_distance / scale, amplitude);
                max_amplitude = mix(max_amplitude, lerp_amplitude, remainder);
                let lerp_distance = mix(distance, distance.min(octave / scale), amplitude);
                distance = mix(distance, distance.min(lerp_distance), remainder);
            }
        }
        i += 1;
    }
    if p.normalize {
        distance /= max_amplitude;
    }
    distance
}

impl VoronoiTexture {
    fn eval_at<P: Point>(&self, p: &mut Params, coord: P) -> VoronoiOutput {
        match self.feature {
            VoronoiFeature::DistanceToEdge => {
                p.max_distance = 0.5 + 0.5 * p.randomness;
                VoronoiOutput {
                    distance: fractal_distance_to_edge(p, coord),
                    ..Default::default()
                }
            }
            VoronoiFeature::NSphereRadius => VoronoiOutput {
                radius: n_sphere_radius(p, coord),
                ..Default::default()
            },
            _ => {
                let f2_factor = if self.feature == VoronoiFeature::F2 {
                    2.0
                } else {
                    1.0
                };
                let corner = P::splat(0.5 + 0.5 * p.randomness);
                p.max_distance =
                    P::splat(0.0).metric_distance(corner, p.metric, p.exponent) * f2_factor;
                let o = fractal(p, coord);
                VoronoiOutput {
                    distance: o.distance,
                    color: o.color,
                    position: o.position.truncate(),
                    w: o.position.w,
                    radius: 0.0,
                }
            }
        }
    }

    /// Evaluates the node.
    pub fn eval(&self, inputs: &VoronoiInputs) -> VoronoiOutput {
        let mut p = Params {
            scale: inputs.scale,
            detail: inputs.detail.clamp(0.0, 15.0),
            roughness: inputs.roughness.clamp(0.0, 1.0),
            lacunarity: inputs.lacunarity,
            smoothness: (inputs.smoothness / 2.0).clamp(0.0, 0.5),
            exponent: inputs.exponent,
            randomness: inputs.randomness.clamp(0.0, 1.0),
            max_distance: 0.0,
            normalize: self.normalize,
            feature: self.feature,
            metric: self.metric,
        };
        let v = inputs.vector * inputs.scale;
        let w = inputs.w * inputs.scale;
        match self.dimensions {
            Dimensions::D1 => self.eval_at(&mut p, w),
            Dimensions::D2 => self.eval_at(&mut p, v.truncate()),
            Dimensions::D3 => self.eval_at(&mut p, v),
            Dimensions::D4 => self.eval_at(&mut p, v.extend(w)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::reference::{check_case, Reference};
    use super::*;

    #[test]
    fn matches_blender() {
        let r = Reference::load(include_str!("testdata/voronoi.json"));
        for case in &r.cases {
            let tex = VoronoiTexture {
                dimensions: Dimensions::from_blender(case.prop_str("voronoi_dimensions"))
                    .expect("dimensions"),
                feature: VoronoiFeature::from_blender(case.prop_str("feature")).expect("feature"),
                metric: VoronoiMetric::from_blender(case.prop_str("distance")).expect("metric"),
                normalize: case.prop_bool("normalize"),
            };
            check_case(&r, case, |p| {
                let o = tex.eval(&VoronoiInputs {
                    vector: p.truncate(),
                    w: p.w,
                    scale: case.input("Scale"),
                    detail: case.input("Detail"),
                    roughness: case.input("Roughness"),
                    lacunarity: case.input("Lacunarity"),
                    smoothness: case.input("Smoothness"),
                    exponent: case.input("Exponent"),
                    randomness: case.input("Randomness"),
                });
                vec![
                    ("Distance", vec![o.distance]),
                    ("Color", o.color.to_array().to_vec()),
                    ("Position", o.position.to_array().to_vec()),
                    ("W", vec![o.w]),
                    ("Radius", vec![o.radius]),
                ]
            });
        }
    }

    #[test]
    fn non_finite_inputs_do_not_panic() {
        for v in [f32::NAN, f32::INFINITY, -f32::INFINITY, 0.0] {
            for f in [
                "F1",
                "F2",
                "SMOOTH_F1",
                "DISTANCE_TO_EDGE",
                "N_SPHERE_RADIUS",
            ] {
                for d in ["1D", "2D", "3D", "4D"] {
                    let tex = VoronoiTexture {
                        dimensions: Dimensions::from_blender(d).expect("dimensions"),
                        feature: VoronoiFeature::from_blender(f).expect("feature"),
                        metric: VoronoiMetric::Minkowski,
                        normalize: true,
                    };
                    let i = VoronoiInputs {
                        vector: Vec3::splat(v),
                        w: v,
                        scale: v,
                        detail: v,
                        roughness: v,
                        lacunarity: v,
                        smoothness: v,
                        exponent: v,
                        randomness: v,
                    };
                    let _ = tex.eval(&i);
                }
            }
        }
    }
}
