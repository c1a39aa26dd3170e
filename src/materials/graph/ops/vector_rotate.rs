//! The Vector Rotate node (Cycles `svm_node_vector_rotate`).

use glam::Vec3;

/// How the node rotates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RotateType {
    /// About the Axis input by Angle.
    AxisAngle,
    X,
    Y,
    Z,
    /// By the Rotation input, XYZ Euler angles.
    EulerXyz,
}

impl RotateType {
    pub const ALL: [RotateType; 5] = [
        RotateType::AxisAngle,
        RotateType::X,
        RotateType::Y,
        RotateType::Z,
        RotateType::EulerXyz,
    ];

    pub fn from_blender(identifier: &str) -> Option<Self> {
        Some(match identifier {
            "AXIS_ANGLE" => RotateType::AxisAngle,
            "X_AXIS" => RotateType::X,
            "Y_AXIS" => RotateType::Y,
            "Z_AXIS" => RotateType::Z,
            "EULER_XYZ" => RotateType::EulerXyz,
            _ => return None,
        })
    }
}

/// Rodrigues' rotation of `p` about the unit `axis` by `angle` (Cycles'
/// `rotate_around_axis`, term for term).
fn rotate_around_axis(p: Vec3, axis: Vec3, angle: f32) -> Vec3 {
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    let a = axis;
    Vec3::new(
        (c + t * a.x * a.x) * p.x
            + (t * a.x * a.y - a.z * s) * p.y
            + (t * a.x * a.z + a.y * s) * p.z,
        (t * a.x * a.y + a.z * s) * p.x
            + (c + t * a.y * a.y) * p.y
            + (t * a.y * a.z - a.x * s) * p.z,
        (t * a.x * a.z - a.y * s) * p.x
            + (t * a.y * a.z + a.x * s) * p.y
            + (c + t * a.z * a.z) * p.z,
    )
}

/// The rows of the XYZ Euler rotation (Rz · Ry · Rx, Cycles' `euler_to_transform`).
fn euler_rows(e: Vec3) -> [Vec3; 3] {
    let (sx, cx) = e.x.sin_cos();
    let (sy, cy) = e.y.sin_cos();
    let (sz, cz) = e.z.sin_cos();
    [
        Vec3::new(cy * cz, sy * sx * cz - cx * sz, sy * cx * cz + sx * sz),
        Vec3::new(cy * sz, sy * sx * sz + cx * cz, sy * cx * sz - sx * cz),
        Vec3::new(-sy, cy * sx, cy * cx),
    ]
}

/// The node: `vector` rotated about `center`; `invert` rotates the other way.
pub fn vector_rotate(
    kind: RotateType,
    invert: bool,
    vector: Vec3,
    center: Vec3,
    axis: Vec3,
    angle: f32,
    rotation: Vec3,
) -> Vec3 {
    let p = vector - center;
    if kind == RotateType::EulerXyz {
        let r = euler_rows(rotation);
        let q = if invert {
            r[0] * p.x + r[1] * p.y + r[2] * p.z
        } else {
            Vec3::new(r[0].dot(p), r[1].dot(p), r[2].dot(p))
        };
        return q + center;
    }
    let (axis, length) = match kind {
        RotateType::X => (Vec3::X, 1.0),
        RotateType::Y => (Vec3::Y, 1.0),
        RotateType::Z => (Vec3::Z, 1.0),
        _ => (axis, axis.length()),
    };
    let angle = if invert { -angle } else { angle };
    if length != 0.0 {
        rotate_around_axis(p, axis / length, angle) + center
    } else {
        vector
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::graph::ops::testutil::*;

    #[test]
    fn matches_cycles() {
        let data = parse(include_str!("testdata/vector_rotate.json"));
        let inp = &data["inputs"];
        let (v, c, a) = (
            vectors(&inp["vector"]),
            vectors(&inp["center"]),
            vectors(&inp["axis"]),
        );
        let (f, r) = (floats(&inp["angle"]), vectors(&inp["rotation"]));
        let mut bad = Vec::new();
        let mut kinds = Vec::new();
        for case in data["cases"].as_array().expect("cases") {
            let name = case["rotation_type"].as_str().expect("type");
            let kind = RotateType::from_blender(name).expect("known type");
            let invert = case["invert"].as_bool().expect("invert");
            kinds.push(kind);
            for (i, want) in vec3s(&case["vector"]).into_iter().enumerate() {
                let ours = vector_rotate(kind, invert, v[i], c[i], a[i], f[i], r[i]);
                if !close3(ours, want) {
                    bad.push(format!("{name} invert {invert} #{i}: {ours} vs {want:?}"));
                }
            }
        }
        assert!(RotateType::ALL.iter().all(|k| kinds.contains(k)));
        assert!(
            bad.is_empty(),
            "{} mismatches:\n{}",
            bad.len(),
            bad.join("\n")
        );
    }

    #[test]
    fn inverting_undoes_the_rotation() {
        let (v, c, a, r) = (
            Vec3::new(1.0, -2.0, 0.5),
            Vec3::new(0.3, 0.1, -1.0),
            Vec3::new(1.0, 2.0, -0.5),
            Vec3::new(0.4, -1.1, 2.0),
        );
        for kind in RotateType::ALL {
            let w = vector_rotate(kind, false, v, c, a, 0.7, r);
            let back = vector_rotate(kind, true, w, c, a, 0.7, r);
            assert!((back - v).length() < 1e-5, "{kind:?}: {back}");
        }
        let q = vector_rotate(RotateType::Z, false, Vec3::X, Vec3::ZERO, a, 1.0, r);
        assert!((q - Vec3::new(1f32.cos(), 1f32.sin(), 0.0)).length() < 1e-6);
        let n = Vec3::splat(f32::NAN);
        for kind in RotateType::ALL {
            let _ = vector_rotate(kind, true, n, n, n, f32::INFINITY, n);
        }
    }
}
