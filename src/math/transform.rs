use glam::{Mat3, Mat4, Vec3};

/// Affine object-to-world transform with its inverse and normal matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub m: Mat4,
    pub inv: Mat4,
    /// Inverse transpose of the linear part, for normals.
    pub normal: Mat3,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    pub const IDENTITY: Transform = Transform {
        m: Mat4::IDENTITY,
        inv: Mat4::IDENTITY,
        normal: Mat3::IDENTITY,
    };

    /// Returns `None` when the matrix is singular or not finite.
    pub fn new(m: Mat4) -> Option<Self> {
        let det = m.determinant();
        if !det.is_finite() || det.abs() < 1e-30 {
            return None;
        }
        let inv = m.inverse();
        if !inv.is_finite() {
            return None;
        }
        let normal = Mat3::from_mat4(inv).transpose();
        Some(Transform { m, inv, normal })
    }

    /// From row-major rows (column-vector convention: translation in the last column).
    pub fn from_rows(rows: &[[f32; 4]; 4]) -> Option<Self> {
        Self::new(Mat4::from_cols_array_2d(rows).transpose())
    }

    #[inline]
    pub fn point(&self, p: Vec3) -> Vec3 {
        self.m.transform_point3(p)
    }
    #[inline]
    pub fn vector(&self, v: Vec3) -> Vec3 {
        self.m.transform_vector3(v)
    }
    #[inline]
    pub fn normal(&self, n: Vec3) -> Vec3 {
        (self.normal * n).normalize_or_zero()
    }
    #[inline]
    pub fn inv_point(&self, p: Vec3) -> Vec3 {
        self.inv.transform_point3(p)
    }
    #[inline]
    pub fn inv_vector(&self, v: Vec3) -> Vec3 {
        self.inv.transform_vector3(v)
    }
    /// Whether the transform flips handedness (negative determinant).
    pub fn swaps_handedness(&self) -> bool {
        Mat3::from_mat4(self.m).determinant() < 0.0
    }
    pub fn then(&self, outer: &Transform) -> Transform {
        Transform::new(outer.m * self.m).unwrap_or(*outer)
    }
}
