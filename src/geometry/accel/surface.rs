//! From a hit to the surface there: the interaction (position with its error bound,
//! normals, UVs, dp/du), the mesh's named attributes, and dp/dv.

use super::{Accel, Hit, IdentityFlag};
use crate::geometry::float::gamma;
use crate::geometry::interaction::{transform_point_error, RayPath, SurfaceInteraction};
use crate::geometry::mesh::{AttributeValues, MAX_ATTRIBUTES};
use crate::geometry::ray::Ray;
use crate::geometry::triangle::face_normal;
use crate::math::Frame;
use glam::{Vec2, Vec3};

impl Accel {
    /// Surface geometry at `hit`, which must come from [`Accel::intersect`] with `ray`.
    /// An out-of-range hit gives an interaction at the origin with default normals.
    pub fn interaction(&self, ray: &Ray, hit: &Hit) -> SurfaceInteraction {
        let inst = self.instances.get(hit.instance as usize);
        let id = self.inst.get(hit.instance as usize);
        let mesh = inst.and_then(|i| self.meshes.get(i.mesh as usize));
        let (p, uvs, nrm) = match mesh {
            Some(m) => (
                m.triangle(hit.prim),
                tri_attr(m.uvs.as_deref(), m.indices.get(hit.prim as usize)),
                tri_attr(m.normals.as_deref(), m.indices.get(hit.prim as usize)),
            ),
            None => ([Vec3::ZERO; 3], None, None),
        };
        let (b1, b2) = (hit.b1, hit.b2);
        let b0 = 1.0 - b1 - b2;
        let p_obj = b0 * p[0] + b1 * p[1] + b2 * p[2];
        let err_obj = gamma(7) * ((b0 * p[0]).abs() + (b1 * p[1]).abs() + (b2 * p[2]).abs());
        let identity = id.is_none_or_identity();
        let tf = inst.map(|i| i.transform).unwrap_or_default();
        let (pw, p_error) = if identity {
            (p_obj, err_obj)
        } else {
            (
                tf.point(p_obj),
                transform_point_error(&tf.m, p_obj, err_obj),
            )
        };

        let n_obj = face_normal(&p);
        let mut ng = if identity { n_obj } else { tf.normal * n_obj }.normalize_or(Vec3::Z);
        if id.is_some_and(|d| d.swaps_handedness) {
            ng = -ng;
        }
        let ns = nrm
            .map(|n| b0 * n[0] + b1 * n[1] + b2 * n[2])
            .map(|n| if identity { n } else { tf.normal * n })
            .and_then(|n| n.try_normalize())
            .unwrap_or(ng);

        let uv_tri = uvs
            .map(|u| [u[0], u[1], u[2]])
            .unwrap_or([Vec2::ZERO, Vec2::X, Vec2::Y]);
        let uv = uvs.map_or(Vec2::new(b1, b2), |u| b0 * u[0] + b1 * u[1] + b2 * u[2]);
        let duv02 = uv_tri[0] - uv_tri[2];
        let duv12 = uv_tri[1] - uv_tri[2];
        let dp02 = p[0] - p[2];
        let dp12 = p[1] - p[2];
        let det = duv02.x * duv12.y - duv02.y * duv12.x;
        let dpdu_obj = (duv12.y * dp02 - duv02.y * dp12) / det;
        let dpdu_w = if identity {
            dpdu_obj
        } else {
            tf.vector(dpdu_obj)
        };
        let dpdu = if det.abs() > 1e-20 && dpdu_w.is_finite() && dpdu_w.cross(ng) != Vec3::ZERO {
            dpdu_w
        } else {
            Frame::from_normal(ng).s
        };

        SurfaceInteraction {
            p: pw,
            p_error,
            ng,
            ns,
            uv,
            dpdu,
            wo: (-ray.d).normalize_or_zero(),
            material: mesh.map_or(0, |m| m.material(hit.prim)),
            instance: hit.instance,
            prim: hit.prim,
            t: hit.t,
            bary: Vec2::new(b1, b2),
            ray_length: hit.t * ray.d.length(),
            path: RayPath::default(),
        }
    }

    /// The named attributes of the mesh at `si`, interpolated; none when it has none.
    pub fn attributes(&self, si: &SurfaceInteraction) -> AttributeValues {
        let mut out = AttributeValues::default();
        let Some(m) = self
            .instances
            .get(si.instance as usize)
            .and_then(|i| self.meshes.get(i.mesh as usize))
        else {
            return out;
        };
        let (b1, b2) = (si.bary.x, si.bary.y);
        let b0 = 1.0 - b1 - b2;
        for (key, vals) in m.attributes.iter().take(MAX_ATTRIBUTES) {
            if let Some(v) = tri_attr(Some(vals.as_slice()), m.indices.get(si.prim as usize)) {
                let k = out.len as usize;
                out.keys[k] = *key;
                out.values[k] = b0 * v[0] + b1 * v[1] + b2 * v[2];
                out.d1[k] = v[1] - v[0];
                out.d2[k] = v[2] - v[0];
                out.len += 1;
            }
        }
        if out.len > 0 {
            let p = m.triangle(si.prim);
            let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
            let inst = &self.instances[si.instance as usize];
            (out.e1, out.e2) = (inst.transform.vector(e1), inst.transform.vector(e2));
        }
        out
    }

    /// Whether some mesh carries named attributes.
    pub fn has_attributes(&self) -> bool {
        self.any_attributes
    }

    /// World-space dp/dv at a hit (from the triangle's UVs; zero without UVs or when they
    /// are degenerate).
    pub fn dpdv(&self, si: &SurfaceInteraction) -> Vec3 {
        let Some(inst) = self.instances.get(si.instance as usize) else {
            return Vec3::ZERO;
        };
        let Some(m) = self.meshes.get(inst.mesh as usize) else {
            return Vec3::ZERO;
        };
        let Some(uv) = tri_attr(m.uvs.as_deref(), m.indices.get(si.prim as usize)) else {
            return Vec3::ZERO;
        };
        let p = m.triangle(si.prim);
        let (duv02, duv12) = (uv[0] - uv[2], uv[1] - uv[2]);
        let det = duv02.x * duv12.y - duv02.y * duv12.x;
        if !(det.abs() > 1e-20) {
            return Vec3::ZERO;
        }
        let d = (duv02.x * (p[1] - p[2]) - duv12.x * (p[0] - p[2])) / det;
        let d = if self.inst.get(si.instance as usize).is_none_or_identity() {
            d
        } else {
            inst.transform.vector(d)
        };
        if d.is_finite() {
            d
        } else {
            Vec3::ZERO
        }
    }
}

/// The three per-vertex attributes of a triangle, when the attribute array covers them.
fn tri_attr<T: Copy>(attr: Option<&[T]>, idx: Option<&[u32; 3]>) -> Option<[T; 3]> {
    let (a, i) = (attr?, idx?);
    Some([
        *a.get(i[0] as usize)?,
        *a.get(i[1] as usize)?,
        *a.get(i[2] as usize)?,
    ])
}
