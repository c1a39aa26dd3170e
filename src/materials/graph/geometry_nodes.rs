//! The input and vector nodes that read the shading point: Texture Coordinate, Geometry,
//! UV Map, Object Info, Layer Weight, Fresnel, Mapping, Normal Map and Bump.

use super::point::{ObjectCoords, ShadingPoint};
use crate::materials::texture::{Interp, Texture};
use crate::math::Frame;
use glam::{EulerRot, Mat3, Vec2, Vec3};

/// Cycles' Fresnel reflectance of a dielectric for |cos| `cosi` and relative IOR `eta`.
pub fn fresnel_dielectric_cos(cosi: f32, eta: f32) -> f32 {
    let c = cosi.abs();
    let g = eta * eta - 1.0 + c * c;
    if g > 0.0 {
        let g = g.sqrt();
        let a = (g - c) / (g + c);
        let b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
        0.5 * a * a * (1.0 + b * b)
    } else {
        1.0
    }
}

/// The normal a node uses: its Normal input when linked, else the shading normal.
#[inline]
fn normal_or(sp: &ShadingPoint, n: Option<Vec3>) -> Vec3 {
    n.unwrap_or(sp.n)
}

/// Layer Weight: (Fresnel, Facing) for Blend `blend`.
pub fn layer_weight(sp: &ShadingPoint, blend: f32, n: Option<Vec3>) -> (f32, f32) {
    let n = normal_or(sp, n);
    let cos = sp.wo.dot(n);
    let eta = (1.0 - blend).max(1e-5);
    let eta = if sp.backfacing { eta } else { 1.0 / eta };
    let fresnel = fresnel_dielectric_cos(cos, eta);
    let mut f = cos.abs();
    if blend != 0.5 {
        let b = blend.clamp(0.0, 1.0 - 1e-5);
        let b = if b < 0.5 { 2.0 * b } else { 0.5 / (1.0 - b) };
        f = f.powf(b);
    }
    (fresnel, 1.0 - f)
}

/// Fresnel: the dielectric reflectance for IOR `ior`.
pub fn fresnel(sp: &ShadingPoint, ior: f32, n: Option<Vec3>) -> f32 {
    let n = normal_or(sp, n);
    let eta = ior.max(1e-5);
    let eta = if sp.backfacing { 1.0 / eta } else { eta };
    fresnel_dielectric_cos(sp.wo.dot(n), eta)
}

/// The Mapping node's kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MappingKind {
    Point,
    Texture,
    Vector,
    Normal,
}

impl MappingKind {
    pub fn from_blender(s: &str) -> Option<Self> {
        Some(match s {
            "POINT" => MappingKind::Point,
            "TEXTURE" => MappingKind::Texture,
            "VECTOR" => MappingKind::Vector,
            "NORMAL" => MappingKind::Normal,
            _ => return None,
        })
    }
}

fn safe_divide(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::new(
        if b.x != 0.0 { a.x / b.x } else { 0.0 },
        if b.y != 0.0 { a.y / b.y } else { 0.0 },
        if b.z != 0.0 { a.z / b.z } else { 0.0 },
    )
}

pub fn safe_normalize(v: Vec3) -> Vec3 {
    let l = v.length();
    if l > 0.0 && l.is_finite() {
        v / l
    } else {
        Vec3::ZERO
    }
}

/// Blender's XYZ Euler rotation (X first, then Y, then Z).
pub fn euler_xyz(r: Vec3) -> Mat3 {
    Mat3::from_euler(EulerRot::ZYX, r.z, r.y, r.x)
}

/// Mapping: `vector` moved by `location`, rotated by the XYZ Euler `rotation`, scaled by
/// `scale`, as a point, a texture (the inverse), a direction or a normal.
pub fn mapping(kind: MappingKind, v: Vec3, location: Vec3, rotation: Vec3, scale: Vec3) -> Vec3 {
    let r = euler_xyz(rotation);
    match kind {
        MappingKind::Point => r * (v * scale) + location,
        MappingKind::Texture => safe_divide(r.transpose() * (v - location), scale),
        MappingKind::Vector => r * (v * scale),
        MappingKind::Normal => safe_normalize(r * safe_divide(v, scale)),
    }
}

/// A shading normal `n` bent, if needed, so that the mirror direction of `wo` about it stays
/// above the geometric normal `ng` (Cycles' `ensure_valid_specular_reflection`).
pub fn ensure_valid_reflection(ng: Vec3, wo: Vec3, n: Vec3) -> Vec3 {
    let r = 2.0 * n.dot(wo) * n - wo;
    let iz = wo.dot(ng);
    let threshold = (0.9 * iz).min(0.01);
    if ng.dot(r) >= threshold {
        return n;
    }
    let x = safe_normalize(n - n.dot(ng) * ng);
    let ix = wo.dot(x);
    let a = ix * ix + iz * iz;
    let b = 2.0 * (a + iz * threshold);
    let c = (threshold + iz) * (threshold + iz);
    let disc = (b * b - 4.0 * a * c).max(0.0).sqrt();
    let nz2 = if ix < 0.0 {
        0.25 * (b + disc) / a
    } else {
        0.25 * (b - disc) / a
    };
    if !nz2.is_finite() {
        return n;
    }
    let nx = (1.0 - nz2).max(0.0).sqrt();
    let nz = nz2.max(0.0).sqrt();
    safe_normalize(nx * x + nz * ng)
}

/// The Normal Map node's spaces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NormalSpace {
    Tangent,
    Object,
    World,
}

impl NormalSpace {
    pub fn from_blender(s: &str) -> Option<Self> {
        Some(match s {
            "TANGENT" => NormalSpace::Tangent,
            "OBJECT" | "BLENDER_OBJECT" => NormalSpace::Object,
            "WORLD" | "BLENDER_WORLD" => NormalSpace::World,
            _ => return None,
        })
    }
}

/// Normal Map: the colour `color` read as a normal in `space`, blended by `strength`.
/// In tangent space the frame is the mesh's tangent attribute when it carries one (object
/// space, taken to world space as normals are, with the bitangent sign in `w`; see
/// [`crate::geometry::vertex_tangents`]); otherwise dp/du made orthogonal to the normal,
/// with the bitangent's sign following dp/dv.
pub fn normal_map(sp: &ShadingPoint, space: NormalSpace, strength: f32, color: Vec3) -> Vec3 {
    let c = 2.0 * (color - Vec3::splat(0.5));
    // The unflipped normal: tangent frames belong to the surface, not to the ray.
    let n0 = if sp.backfacing { -sp.n } else { sp.n };
    let tangent = match space {
        NormalSpace::Tangent => sp.attributes.get(crate::geometry::TANGENT_KEY),
        _ => None,
    };
    let mut n = match space {
        NormalSpace::Tangent if tangent.is_some() => {
            // As Cycles: in object space, over the tangent and the normal interpolated
            // and not normalised, then carried to world space as a normal.
            let t4 = tangent.unwrap_or_default();
            let m = Mat3::from_mat4(sp.object.to_object).transpose();
            let sign = if t4.w < 0.0 { -1.0 } else { 1.0 };
            let t = t4.truncate();
            match sp.attributes.get(crate::geometry::TANGENT_NORMAL_KEY) {
                Some(nn) => {
                    let nn = nn.truncate();
                    safe_normalize(m * (c.x * t + c.y * sign * nn.cross(t) + c.z * nn))
                }
                None => {
                    let t = safe_normalize(m * t);
                    safe_normalize(c.x * t + c.y * sign * n0.cross(t) + c.z * n0)
                }
            }
        }
        NormalSpace::Tangent => {
            let t = safe_normalize(sp.dpdu - n0 * n0.dot(sp.dpdu));
            if t == Vec3::ZERO {
                n0
            } else {
                let b = n0.cross(t);
                let sign = if b.dot(sp.dpdv) < 0.0 { -1.0 } else { 1.0 };
                safe_normalize(c.x * t + c.y * sign * b + c.z * n0)
            }
        }
        NormalSpace::Object => {
            let m = Mat3::from_mat4(sp.object.to_object).transpose();
            safe_normalize(m * c)
        }
        NormalSpace::World => safe_normalize(c),
    };
    if n == Vec3::ZERO {
        n = n0;
    }
    if sp.backfacing {
        n = -n;
    }
    if strength != 1.0 {
        let s = strength.max(0.0);
        n = safe_normalize(sp.n + (n - sp.n) * s);
        if n == Vec3::ZERO {
            n = sp.n;
        }
    }
    n
}

/// A Displacement node's offset in object space, back in world space: height `h` along the
/// object-space normal of `n` (Cycles' object_inverse_normal_transform, normalised), carried
/// by the object's transform, so that the offset grows with the object's scale.
pub fn object_displacement(obj: &ObjectCoords, n: Vec3, h: f32) -> Vec3 {
    let to_world = obj.to_object.inverse();
    let n_obj = safe_normalize(to_world.transpose().transform_vector3(n));
    let d = to_world.transform_vector3(n_obj * h);
    if d.is_finite() {
        d
    } else {
        n * h
    }
}

/// The two tangent offsets at which a Bump node evaluates its height, `eps` long.
pub fn bump_offsets(sp: &ShadingPoint, n: Vec3) -> [Vec3; 2] {
    let f = Frame::from_normal_tangent(n, sp.dpdu);
    let eps = bump_step(sp.p);
    [f.s * eps, f.t * eps]
}

/// The finite-difference step of a Bump node at `p`: small against the scene, large against
/// the float spacing there.
pub fn bump_step(p: Vec3) -> f32 {
    1e-4 * p.abs().max_element().max(1.0)
}

/// Bump: the normal `n` tilted by the height's surface gradient (Cycles 5.0 divides its
/// finite difference by the filter width: the gradient itself) (heights `hc` at the point,
/// `hx`, `hy` at the offsets `dx`, `dy` of [`bump_offsets`]), `distance` high, blended by
/// `strength`; `invert` bumps inwards.
#[allow(clippy::too_many_arguments)]
pub fn bump(
    n: Vec3,
    [dx, dy]: [Vec3; 2],
    hc: f32,
    hx: f32,
    hy: f32,
    strength: f32,
    distance: f32,
    invert: bool,
) -> Vec3 {
    let rx = dy.cross(n);
    let ry = n.cross(dx);
    let det = dx.dot(rx);
    let surfgrad = (hx - hc) * rx + (hy - hc) * ry;
    let mut d = distance;
    if invert {
        d = -d;
    }
    let strength = strength.max(0.0);
    let out = safe_normalize(det.abs() * n - d * det.signum() * surfgrad);
    let out = if out == Vec3::ZERO {
        n
    } else {
        safe_normalize(strength * out + (1.0 - strength) * n)
    };
    if out == Vec3::ZERO {
        n
    } else {
        out
    }
}

/// How an Image Texture maps its vector to the image (Cycles' projections; Box is
/// [`image_box`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageProjection {
    Flat,
    /// The vector, remapped from [0, 1]^3 to [-1, 1]^3, as longitude and latitude.
    Sphere,
    /// The vector, remapped likewise, as angle around z and height.
    Tube,
}

impl ImageProjection {
    /// The image coordinates of vector `co`.
    pub fn uv(self, co: Vec3) -> Vec2 {
        let c = (co - Vec3::splat(0.5)) * 2.0;
        let pi = std::f32::consts::PI;
        match self {
            ImageProjection::Flat => Vec2::new(co.x, co.y),
            ImageProjection::Sphere => {
                let l = c.length();
                if !(l > 0.0) {
                    return Vec2::ZERO;
                }
                let u = if c.x == 0.0 && c.y == 0.0 {
                    0.0
                } else {
                    (1.0 - c.x.atan2(c.y) / pi) / 2.0
                };
                Vec2::new(u, 1.0 - (c.z / l).clamp(-1.0, 1.0).acos() / pi)
            }
            ImageProjection::Tube => {
                let l = (c.x * c.x + c.y * c.y).sqrt();
                if !(l > 0.0) {
                    return Vec2::ZERO;
                }
                Vec2::new(
                    (1.0 - (c.x / l).atan2(c.y / l) / pi) * 0.5,
                    (c.z + 1.0) * 0.5,
                )
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    fn point() -> ShadingPoint {
        let mut sp = ShadingPoint::at(Vec3::new(0.3, -0.2, 0.0), Vec3::Z, Vec2::new(0.3, 0.8));
        sp.wo = Vec3::new(0.3, 0.1, 1.0).normalize();
        sp.dpdu = Vec3::X;
        sp.dpdv = Vec3::Y;
        sp
    }

    #[test]
    fn sphere_and_tube_projections_map_as_cycles() {
        use ImageProjection::*;
        let close = |a: Vec2, b: Vec2| (a - b).length() < 1e-6;
        // The vector is remapped from [0, 1]^3 to [-1, 1]^3: its centre along +y (Cycles'
        // atan2(x, y) = 0) is the middle of the image; +x a quarter turn further.
        assert!(close(
            Sphere.uv(Vec3::new(0.5, 1.0, 0.5)),
            Vec2::new(0.5, 0.5)
        ));
        assert!(close(
            Sphere.uv(Vec3::new(1.0, 0.5, 0.5)),
            Vec2::new(0.25, 0.5)
        ));
        assert!(close(
            Sphere.uv(Vec3::new(0.5, 0.5, 1.0)),
            Vec2::new(0.0, 1.0)
        ));
        assert!(close(
            Tube.uv(Vec3::new(0.0, 0.5, 0.75)),
            Vec2::new(0.75, 0.75)
        ));
        assert!(close(Tube.uv(Vec3::splat(0.5)), Vec2::ZERO));
        assert!(close(
            Flat.uv(Vec3::new(0.2, 0.7, 0.9)),
            Vec2::new(0.2, 0.7)
        ));
    }

    #[test]
    fn bump_of_a_linear_height_tilts_by_its_gradient() {
        // h = a x: the bumped normal is normalize(n - distance * grad h) = (-d a, 0, 1) / len.
        let sp = point();
        let a = 0.7;
        let d = 0.5;
        let off = bump_offsets(&sp, sp.n);
        let h = |p: Vec3| a * p.x;
        let n = bump(
            sp.n,
            off,
            h(sp.p),
            h(sp.p + off[0]),
            h(sp.p + off[1]),
            1.0,
            d,
            false,
        );
        let want = Vec3::new(-d * a, 0.0, 1.0).normalize();
        assert!((n - want).length() < 1e-3, "{n} vs {want}");
        let inv = bump(
            sp.n,
            off,
            h(sp.p),
            h(sp.p + off[0]),
            h(sp.p + off[1]),
            1.0,
            d,
            true,
        );
        assert!((inv - Vec3::new(d * a, 0.0, 1.0).normalize()).length() < 1e-3);
        // Strength 0 leaves the normal alone.
        let flat = bump(
            sp.n,
            off,
            h(sp.p),
            h(sp.p + off[0]),
            h(sp.p + off[1]),
            0.0,
            d,
            false,
        );
        assert!((flat - sp.n).length() < 1e-6);
    }

    #[test]
    fn tangent_space_normal_map() {
        let sp = point();
        // (0.5, 0.5, 1) is the unperturbed normal.
        let n = normal_map(&sp, NormalSpace::Tangent, 1.0, Vec3::new(0.5, 0.5, 1.0));
        assert!((n - Vec3::Z).length() < 1e-5);
        // Red towards +u, green towards +v.
        let t = normal_map(&sp, NormalSpace::Tangent, 1.0, Vec3::new(0.75, 0.5, 1.0));
        assert!(t.x > 0.0 && t.y.abs() < 1e-5);
        let b = normal_map(&sp, NormalSpace::Tangent, 1.0, Vec3::new(0.5, 0.75, 1.0));
        assert!(b.y > 0.0 && b.x.abs() < 1e-5);
        let mut flipped_v = sp;
        flipped_v.dpdv = -Vec3::Y;
        let b2 = normal_map(
            &flipped_v,
            NormalSpace::Tangent,
            1.0,
            Vec3::new(0.5, 0.75, 1.0),
        );
        assert!(b2.y < 0.0);
    }

    #[test]
    fn mapping_point_and_texture_are_inverse() {
        let (loc, rot, sc) = (
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(0.3, -0.5, 1.1),
            Vec3::new(2.0, 0.5, 3.0),
        );
        let v = Vec3::new(0.2, -0.7, 0.4);
        let p = mapping(MappingKind::Point, v, loc, rot, sc);
        let back = mapping(MappingKind::Texture, p, loc, rot, sc);
        assert!((back - v).length() < 1e-5);
        // Z rotation by 90 degrees takes x to y; rotation order X, then Y, then Z.
        let z90 = mapping(
            MappingKind::Vector,
            Vec3::X,
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, std::f32::consts::FRAC_PI_2),
            Vec3::ONE,
        );
        assert!((z90 - Vec3::Y).length() < 1e-6);
        let xy = mapping(
            MappingKind::Vector,
            Vec3::Y,
            Vec3::ZERO,
            Vec3::new(
                std::f32::consts::FRAC_PI_2,
                0.0,
                std::f32::consts::FRAC_PI_2,
            ),
            Vec3::ONE,
        );
        // X first: y -> z; then Z about z leaves z.
        assert!((xy - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn layer_weight_and_fresnel_at_normal_incidence() {
        let mut sp = point();
        sp.wo = Vec3::Z;
        let (fres, facing) = layer_weight(&sp, 0.5, None);
        // eta = 1 / 0.5 = 2: F0 = (1/3)^2.
        assert!((fres - 1.0 / 9.0).abs() < 1e-5);
        assert!(facing.abs() < 1e-6);
        assert!((fresnel(&sp, 1.5, None) - 0.04).abs() < 1e-5);
    }
}

/// Cycles' Box projection of texture `t` at coordinates `co`, for the object-space normal
/// `n`: the three axis projections weighted over a triangle of zones by the normal's
/// components (one texture near each axis, two or three blended within `blend` of the
/// diagonals), each oriented so that no face is mirrored. Returns (colour, alpha).
pub fn image_box(t: &Texture, co: Vec3, n: Vec3, blend: f32, interp: Interp) -> (Vec3, f32) {
    let signed = n;
    let mut a = n.abs();
    let s = a.x + a.y + a.z;
    if s > 0.0 {
        a /= s;
    }
    let limit = 0.5 * (1.0 + blend);
    let mut w = Vec3::ZERO;
    if a.x > limit * (a.x + a.y) && a.x > limit * (a.x + a.z) {
        w.x = 1.0;
    } else if a.y > limit * (a.x + a.y) && a.y > limit * (a.y + a.z) {
        w.y = 1.0;
    } else if a.z > limit * (a.x + a.z) && a.z > limit * (a.y + a.z) {
        w.z = 1.0;
    } else if blend > 0.0 {
        let ramp = |v: f32| ((v - 0.5 * (1.0 - blend)) / blend).clamp(0.0, 1.0);
        if a.z < (1.0 - limit) * (a.y + a.x) {
            w.x = ramp(a.x / (a.x + a.y));
            w.y = 1.0 - w.x;
        } else if a.x < (1.0 - limit) * (a.y + a.z) {
            w.y = ramp(a.y / (a.y + a.z));
            w.z = 1.0 - w.y;
        } else if a.y < (1.0 - limit) * (a.x + a.z) {
            w.x = ramp(a.x / (a.x + a.z));
            w.z = 1.0 - w.x;
        } else {
            let d = 2.0 * limit - 1.0;
            w = ((2.0 - limit) * a + Vec3::splat(limit - 1.0)) / d;
        }
    } else {
        w.x = 1.0;
    }
    let mut rgb = Vec3::ZERO;
    let mut alpha = 0.0;
    let mut fetch = |weight: f32, uv: Vec2| {
        if weight > 0.0 {
            rgb += weight * t.eval_rgb_with(uv, interp);
            alpha += weight
                * if t.channels() == 4 {
                    t.eval_channel_with(uv, 3, interp)
                } else {
                    1.0
                };
        }
    };
    fetch(
        w.x,
        Vec2::new(if signed.x < 0.0 { 1.0 - co.y } else { co.y }, co.z),
    );
    fetch(
        w.y,
        Vec2::new(if signed.y > 0.0 { 1.0 - co.x } else { co.x }, co.z),
    );
    fetch(
        w.z,
        Vec2::new(if signed.z > 0.0 { 1.0 - co.y } else { co.y }, co.x),
    );
    (rgb, alpha)
}

#[cfg(test)]
mod box_tests {
    use super::*;
    use crate::scene::desc::{TextureDesc, TextureEncoding, WrapMode};

    /// A 2 x 2 linear texture whose texels are red, green, blue and white (rows top to
    /// bottom), read as constant by nearest sampling at the texel centres.
    fn quad_texture() -> Texture {
        Texture::from_desc(&TextureDesc {
            name: String::new(),
            width: 2,
            height: 2,
            channels: 3,
            data: vec![1., 0., 0., 0., 1., 0., 0., 0., 1., 1., 1., 1.],
            wrap: WrapMode::Repeat,
            encoding: TextureEncoding::Linear,
        })
    }

    #[test]
    fn each_axis_reads_its_own_projection_and_the_diagonal_blends() {
        let t = quad_texture();
        let co = Vec3::new(0.25, 0.25, 0.75);
        // Along +x: (y, z) = (0.25, 0.75); along -x mirrored in u: (0.75, 0.75).
        let (px, _) = image_box(&t, co, Vec3::X, 0.0, Interp::Linear);
        let (mx, _) = image_box(&t, co, -Vec3::X, 0.0, Interp::Linear);
        assert_eq!(px, t.eval_rgb(Vec2::new(0.25, 0.75)));
        assert_eq!(mx, t.eval_rgb(Vec2::new(0.75, 0.75)));
        assert_ne!(px, mx);
        // Along +z: (1 - y, x); along -z: (y, x).
        let (pz, _) = image_box(&t, co, Vec3::Z, 0.0, Interp::Linear);
        assert_eq!(pz, t.eval_rgb(Vec2::new(0.75, 0.25)));
        // Without blend the diagonal takes one face; with blend 1 the three share equally.
        let d = Vec3::ONE.normalize();
        let (all, a) = image_box(&t, co, d, 1.0, Interp::Linear);
        let want = (t.eval_rgb(Vec2::new(0.25, 0.75))
            + t.eval_rgb(Vec2::new(0.75, 0.75))
            + t.eval_rgb(Vec2::new(0.75, 0.25)))
            / 3.0;
        assert!((all - want).abs().max_element() < 1e-5, "{all} vs {want}");
        assert!((a - 1.0).abs() < 1e-6);
    }
}

#[cfg(test)]
mod valid_reflection_tests {
    use super::*;

    fn reflect(n: Vec3, wo: Vec3) -> Vec3 {
        2.0 * n.dot(wo) * n - wo
    }

    #[test]
    fn a_valid_reflection_keeps_the_normal() {
        let ng = Vec3::Z;
        let n = Vec3::new(0.2, 0.0, 1.0).normalize();
        let wo = Vec3::new(0.0, 0.3, 1.0).normalize();
        assert_eq!(ensure_valid_reflection(ng, wo, n), n);
    }

    #[test]
    fn an_invalid_reflection_is_lifted_to_the_threshold() {
        let ng = Vec3::Z;
        // A normal tilted 60 degrees away from a grazing view reflects it below the surface.
        for (tilt, view) in [(1.0f32, 1.2f32), (0.8, 1.4), (1.3, 0.9), (0.6, 1.5)] {
            let n = Vec3::new(tilt.sin(), 0.0, tilt.cos());
            let wo = Vec3::new(-view.sin(), 0.0, view.cos());
            assert!(ng.dot(reflect(n, wo)) < 0.0);
            let m = ensure_valid_reflection(ng, wo, n);
            let t = (0.9 * wo.dot(ng)).min(0.01);
            assert!((m.length() - 1.0).abs() < 1e-5, "{m}");
            let rz = ng.dot(reflect(m, wo));
            assert!(
                (rz - t).abs() < 2e-4,
                "tilt {tilt} view {view}: R.z {rz}, wanted {t}"
            );
            // Bent towards ng, in the plane of n and ng.
            assert!(m.z > n.z && m.y.abs() < 1e-6 && m.x > 0.0);
        }
    }
}
