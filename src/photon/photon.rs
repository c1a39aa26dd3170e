//! Photon records, Ward's RGBE shared-exponent power encoding and the
//! quantised (phi, theta) direction encoding.
//!
//! The 20-byte layout is the one of Jensen, *Realistic Image Synthesis Using
//! Photon Mapping* (2001), appendix B and *A Practical Guide to Global
//! Illumination using Photon Maps* (2000): `float x,y,z; char p[4];
//! char phi, theta; short flag;` with the power stored in Ward's RGBE format
//! (G. Ward, "Real Pixels", Graphics Gems II, 1991).

mod direction;
mod rgbe;

pub use direction::{
    decode_direction, direction_tables, encode_direction, DirectionTables, DIRECTION_ERROR_BOUND,
};
pub use rgbe::{rgbe_decode, rgbe_encode, RGBE_MAX};

use glam::Vec3;

use super::PhotonError;

/// Mask of the kd-tree split axis inside a photon's `flag`.
///
/// Bits 0–1 hold the split axis (0 = x, 1 = y, 2 = z, 3 = leaf); they are
/// owned by the kd-tree and overwritten when the tree is built. Bits 2–15 are
/// free for the renderer (e.g. a "caustic" or "direct" bit); see
/// [`Photon::user_flags`].
pub const AXIS_MASK: u16 = 0b11;

/// Axis value marking a kd-tree leaf (a node without children).
pub const LEAF_AXIS: u8 = 3;

/// Common interface of the photon records stored in a
/// [`PhotonKdTree`](super::PhotonKdTree).
pub trait KdRecord: Copy + Send + Sync {
    /// Position as a plain array (the hot path of the kd-tree queries).
    fn pos(&self) -> &[f32; 3];
    /// Position as a vector.
    #[inline]
    fn position(&self) -> Vec3 {
        Vec3::from_array(*self.pos())
    }
    /// kd-tree split axis (0, 1, 2) or [`LEAF_AXIS`].
    fn axis(&self) -> u8;
    /// Sets the kd-tree split axis (low two bits of the flag only; the other
    /// flag bits are preserved).
    fn set_axis(&mut self, axis: u8);
}

/// A photon record: a point of the kd-tree with the photon's power and direction.
pub trait PhotonRecord: KdRecord {
    /// Photon power (flux), decoded to `f32` if stored compressed.
    fn power(&self) -> Vec3;
    /// Unit vector pointing from the surface back towards where the photon
    /// came from.
    fn incoming(&self) -> Vec3;
    /// The 14 free flag bits (bits 2–15 of the flag word, shifted down).
    fn user_flags(&self) -> u16;
    /// A record from a position, a power and the incoming direction already quantised
    /// ([`encode_direction`] bytes), as the type's `with_direction_bytes`.
    fn from_parts(pos: Vec3, power: Vec3, dir: (u8, u8)) -> Result<Self, PhotonError>;
    /// Sets the 14 free flag bits, keeping the split axis.
    fn set_flags(&mut self, bits: u16);
}

// ---------------------------------------------------------------------------
// Photon (20 bytes, RGBE power)
// ---------------------------------------------------------------------------

/// A 20-byte photon: position, RGBE power, quantised incoming direction and a
/// flag word (Jensen 2001, appendix B; *Practical Guide* §2.3).
///
/// * power: Ward RGBE, see [`rgbe_encode`] for the precision;
/// * direction: the *incoming* direction (from the surface towards where the
///   photon came from, i.e. the negated travel direction) quantised to
///   `(phi, theta)` bytes, see [`encode_direction`] for the error bound;
/// * `flag`: bits 0–1 = kd-tree split axis ([`AXIS_MASK`]), bits 2–15 free.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Photon {
    pos: [f32; 3],
    rgbe: [u8; 4],
    phi: u8,
    theta: u8,
    flag: u16,
}

const _: () = assert!(std::mem::size_of::<Photon>() == 20);
const _: () = assert!(std::mem::align_of::<Photon>() == 4);

impl Photon {
    /// Bytes of [`Photon::to_le_bytes`].
    pub const BYTES: usize = 20;

    /// The record as little-endian bytes: position, RGBE, direction, flag (the layout of
    /// the struct), for saved photon maps.
    pub fn to_le_bytes(&self) -> [u8; 20] {
        let mut b = [0u8; 20];
        for (i, v) in self.pos.iter().enumerate() {
            b[4 * i..4 * i + 4].copy_from_slice(&v.to_le_bytes());
        }
        b[12..16].copy_from_slice(&self.rgbe);
        b[16] = self.phi;
        b[17] = self.theta;
        b[18..20].copy_from_slice(&self.flag.to_le_bytes());
        b
    }

    /// The record of [`Photon::to_le_bytes`].
    pub fn from_le_bytes(b: &[u8]) -> Photon {
        let f = |i: usize| f32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
        Photon {
            pos: [f(0), f(4), f(8)],
            rgbe: [b[12], b[13], b[14], b[15]],
            phi: b[16],
            theta: b[17],
            flag: u16::from_le_bytes([b[18], b[19]]),
        }
    }

    /// Creates a photon at `pos` carrying `power`, which was travelling along
    /// `travel_dir` when it hit the surface (the ray direction; it need not be
    /// normalised). The stored direction is `-travel_dir`, returned by
    /// [`PhotonRecord::incoming`].
    ///
    /// Fails on non-finite positions, negative/NaN/infinite power, or a
    /// zero/non-finite direction.
    pub fn new(pos: Vec3, power: Vec3, travel_dir: Vec3) -> Result<Photon, PhotonError> {
        let pos = check_position(pos)?;
        let rgbe = rgbe_encode(power)?;
        let (phi, theta) = encode_direction(-check_direction(travel_dir)?);
        Ok(Photon {
            pos,
            rgbe,
            phi,
            theta,
            flag: 0,
        })
    }

    /// As [`Photon::new`], with the incoming direction already quantised
    /// (`dir` as [`encode_travel_direction`] gives it).
    pub fn with_direction_bytes(
        pos: Vec3,
        power: Vec3,
        dir: (u8, u8),
    ) -> Result<Photon, PhotonError> {
        let pos = check_position(pos)?;
        let rgbe = rgbe_encode(power)?;
        Ok(Photon {
            pos,
            rgbe,
            phi: dir.0,
            theta: dir.1,
            flag: 0,
        })
    }

    /// Position of the photon.
    #[inline]
    pub fn position(&self) -> Vec3 {
        KdRecord::position(self)
    }

    /// Decoded power (flux) of the photon.
    #[inline]
    pub fn power(&self) -> Vec3 {
        rgbe_decode(self.rgbe)
    }

    /// Unit vector pointing from the surface back towards where the photon
    /// came from.
    #[inline]
    pub fn incoming(&self) -> Vec3 {
        decode_direction(self.phi, self.theta)
    }

    /// The raw RGBE bytes of the power.
    #[inline]
    pub fn rgbe(&self) -> [u8; 4] {
        self.rgbe
    }

    /// The quantised incoming direction bytes `(phi, theta)`.
    #[inline]
    pub fn direction_bytes(&self) -> (u8, u8) {
        (self.phi, self.theta)
    }

    /// The whole flag word (bits 0–1: kd-tree axis, bits 2–15: user bits).
    #[inline]
    pub fn flag(&self) -> u16 {
        self.flag
    }

    /// The 14 free flag bits (bits 2–15 of the flag word, shifted down).
    #[inline]
    pub fn user_flags(&self) -> u16 {
        self.flag >> 2
    }

    /// Sets the 14 free flag bits (values above `0x3fff` are truncated);
    /// the kd-tree axis bits are preserved.
    #[inline]
    pub fn set_user_flags(&mut self, bits: u16) {
        self.flag = (self.flag & AXIS_MASK) | (bits << 2);
    }
}

impl KdRecord for Photon {
    #[inline(always)]
    fn pos(&self) -> &[f32; 3] {
        &self.pos
    }
    #[inline(always)]
    fn axis(&self) -> u8 {
        (self.flag & AXIS_MASK) as u8
    }
    #[inline]
    fn set_axis(&mut self, axis: u8) {
        self.flag = (self.flag & !AXIS_MASK) | (axis as u16 & AXIS_MASK);
    }
}

impl PhotonRecord for Photon {
    #[inline]
    fn from_parts(pos: Vec3, power: Vec3, dir: (u8, u8)) -> Result<Self, PhotonError> {
        Photon::with_direction_bytes(pos, power, dir)
    }
    #[inline]
    fn set_flags(&mut self, bits: u16) {
        self.set_user_flags(bits)
    }
    #[inline]
    fn power(&self) -> Vec3 {
        rgbe_decode(self.rgbe)
    }
    #[inline]
    fn incoming(&self) -> Vec3 {
        decode_direction(self.phi, self.theta)
    }
    #[inline]
    fn user_flags(&self) -> u16 {
        self.flag >> 2
    }
}

// ---------------------------------------------------------------------------
// PhotonF32 (28 bytes, f32 power)
// ---------------------------------------------------------------------------

/// A photon with full-precision `f32` power: 28 bytes (12 position, 12
/// power, 2 direction, 2 flag). Same direction and flag conventions as
/// [`Photon`]; kept to compare RGBE against `f32` accuracy and memory.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct PhotonF32 {
    pos: [f32; 3],
    power: [f32; 3],
    phi: u8,
    theta: u8,
    flag: u16,
}

const _: () = assert!(std::mem::size_of::<PhotonF32>() == 28);

impl PhotonF32 {
    /// Bytes of [`PhotonF32::to_le_bytes`].
    pub const BYTES: usize = 28;

    /// The record as little-endian bytes (the layout of the struct), for saved photon maps.
    pub fn to_le_bytes(&self) -> [u8; 28] {
        let mut b = [0u8; 28];
        for (i, v) in self.pos.iter().chain(&self.power).enumerate() {
            b[4 * i..4 * i + 4].copy_from_slice(&v.to_le_bytes());
        }
        b[24] = self.phi;
        b[25] = self.theta;
        b[26..28].copy_from_slice(&self.flag.to_le_bytes());
        b
    }

    /// The record of [`PhotonF32::to_le_bytes`].
    pub fn from_le_bytes(b: &[u8]) -> PhotonF32 {
        let f = |i: usize| f32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
        PhotonF32 {
            pos: [f(0), f(4), f(8)],
            power: [f(12), f(16), f(20)],
            phi: b[24],
            theta: b[25],
            flag: u16::from_le_bytes([b[26], b[27]]),
        }
    }

    /// Same contract as [`Photon::new`]; the power is stored unquantised.
    pub fn new(pos: Vec3, power: Vec3, travel_dir: Vec3) -> Result<PhotonF32, PhotonError> {
        let pos = check_position(pos)?;
        check_power(power)?;
        let (phi, theta) = encode_direction(-check_direction(travel_dir)?);
        Ok(PhotonF32 {
            pos,
            power: power.to_array(),
            phi,
            theta,
            flag: 0,
        })
    }

    /// As [`PhotonF32::new`], with the incoming direction already quantised
    /// (`dir` as [`encode_travel_direction`] gives it).
    pub fn with_direction_bytes(
        pos: Vec3,
        power: Vec3,
        dir: (u8, u8),
    ) -> Result<PhotonF32, PhotonError> {
        let pos = check_position(pos)?;
        check_power(power)?;
        Ok(PhotonF32 {
            pos,
            power: power.to_array(),
            phi: dir.0,
            theta: dir.1,
            flag: 0,
        })
    }

    /// Position of the photon.
    #[inline]
    pub fn position(&self) -> Vec3 {
        Vec3::from_array(self.pos)
    }

    /// Power (flux) of the photon.
    #[inline]
    pub fn power(&self) -> Vec3 {
        Vec3::from_array(self.power)
    }

    /// Unit vector pointing from the surface back towards where the photon
    /// came from.
    #[inline]
    pub fn incoming(&self) -> Vec3 {
        decode_direction(self.phi, self.theta)
    }

    /// The quantised incoming direction bytes `(phi, theta)`.
    #[inline]
    pub fn direction_bytes(&self) -> (u8, u8) {
        (self.phi, self.theta)
    }

    /// The whole flag word (bits 0–1: kd-tree axis, bits 2–15: user bits).
    #[inline]
    pub fn flag(&self) -> u16 {
        self.flag
    }

    /// The 14 free flag bits (bits 2–15 of the flag word, shifted down).
    #[inline]
    pub fn user_flags(&self) -> u16 {
        self.flag >> 2
    }

    /// Sets the 14 free flag bits; the kd-tree axis bits are preserved.
    #[inline]
    pub fn set_user_flags(&mut self, bits: u16) {
        self.flag = (self.flag & AXIS_MASK) | (bits << 2);
    }
}

impl From<Photon> for PhotonF32 {
    fn from(p: Photon) -> Self {
        PhotonF32 {
            pos: p.pos,
            power: p.power().to_array(),
            phi: p.phi,
            theta: p.theta,
            flag: p.flag,
        }
    }
}

impl KdRecord for PhotonF32 {
    #[inline(always)]
    fn pos(&self) -> &[f32; 3] {
        &self.pos
    }
    #[inline(always)]
    fn axis(&self) -> u8 {
        (self.flag & AXIS_MASK) as u8
    }
    #[inline]
    fn set_axis(&mut self, axis: u8) {
        self.flag = (self.flag & !AXIS_MASK) | (axis as u16 & AXIS_MASK);
    }
}

impl PhotonRecord for PhotonF32 {
    #[inline]
    fn from_parts(pos: Vec3, power: Vec3, dir: (u8, u8)) -> Result<Self, PhotonError> {
        PhotonF32::with_direction_bytes(pos, power, dir)
    }
    #[inline]
    fn set_flags(&mut self, bits: u16) {
        self.set_user_flags(bits)
    }
    #[inline]
    fn power(&self) -> Vec3 {
        Vec3::from_array(self.power)
    }
    #[inline]
    fn incoming(&self) -> Vec3 {
        decode_direction(self.phi, self.theta)
    }
    #[inline]
    fn user_flags(&self) -> u16 {
        self.flag >> 2
    }
}

fn check_position(pos: Vec3) -> Result<[f32; 3], PhotonError> {
    if pos.is_finite() {
        Ok(pos.to_array())
    } else {
        Err(PhotonError::InvalidPosition(pos.to_array()))
    }
}

fn check_power(power: Vec3) -> Result<(), PhotonError> {
    // `!(x >= 0)` also catches NaN; `-0.0` is accepted (it encodes to zero).
    if power.is_finite() && power.cmpge(Vec3::ZERO).all() {
        Ok(())
    } else {
        Err(PhotonError::InvalidPower(power.to_array()))
    }
}

/// The incoming-direction bytes `(phi, theta)` that [`Photon::new`] and
/// [`PhotonF32::new`] store for a photon travelling along `travel_dir`.
pub fn encode_travel_direction(travel_dir: Vec3) -> Result<(u8, u8), PhotonError> {
    Ok(encode_direction(-check_direction(travel_dir)?))
}

fn check_direction(dir: Vec3) -> Result<Vec3, PhotonError> {
    let d = dir.normalize_or_zero();
    if d == Vec3::ZERO {
        Err(PhotonError::InvalidDirection(dir.to_array()))
    } else {
        Ok(d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Small deterministic generator (xorshift64*), to avoid a rand dependency.
    struct Rng(u64);
    impl Rng {
        fn next_u64(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }
        fn f64(&mut self) -> f64 {
            (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn sizes() {
        assert_eq!(std::mem::size_of::<Photon>(), 20);
        assert_eq!(std::mem::size_of::<PhotonF32>(), 28);
    }

    #[test]
    fn rgbe_exact_values() {
        assert_eq!(rgbe_encode(Vec3::ZERO).unwrap(), [0; 4]);
        assert_eq!(rgbe_encode(Vec3::splat(-0.0)).unwrap(), [0; 4]);
        assert_eq!(rgbe_decode([0, 0, 0, 0]), Vec3::ZERO);
        // 1.0 = 0.5·2^1 → mantissa 128, exponent byte 129.
        assert_eq!(
            rgbe_encode(Vec3::new(1.0, 0.5, 0.0)).unwrap(),
            [128, 64, 0, 129]
        );
        assert_eq!(rgbe_decode([128, 64, 0, 129]), Vec3::new(1.0, 0.5, 0.0));
        // Powers of two and small dyadic values round-trip exactly.
        for e in -120..120 {
            let v = 2f32.powi(e);
            let c = Vec3::new(v, v * 0.75, v * 0.5);
            assert_eq!(rgbe_decode(rgbe_encode(c).unwrap()), c, "2^{e}");
        }
    }

    #[test]
    fn rgbe_rejects_invalid() {
        for bad in [
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(0.0, f32::NAN, 0.0),
            Vec3::new(0.0, 0.0, f32::INFINITY),
            Vec3::new(f32::NEG_INFINITY, 1.0, 1.0),
            Vec3::new(1.0, -1e-30, 1.0),
        ] {
            assert!(matches!(
                rgbe_encode(bad),
                Err(PhotonError::InvalidPower(_))
            ));
            assert!(Photon::new(Vec3::ZERO, bad, Vec3::Z).is_err());
            assert!(PhotonF32::new(Vec3::ZERO, bad, Vec3::Z).is_err());
        }
        assert!(matches!(
            Photon::new(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::ONE, Vec3::Z),
            Err(PhotonError::InvalidPosition(_))
        ));
        assert!(matches!(
            Photon::new(Vec3::ZERO, Vec3::ONE, Vec3::ZERO),
            Err(PhotonError::InvalidDirection(_))
        ));
        assert!(matches!(
            Photon::new(Vec3::ZERO, Vec3::ONE, Vec3::new(f32::NAN, 1.0, 0.0)),
            Err(PhotonError::InvalidDirection(_))
        ));
    }

    #[test]
    fn rgbe_subnormal_and_tiny_are_zero() {
        for v in [
            f32::MIN_POSITIVE / 2.0,
            f32::from_bits(1),
            f32::MIN_POSITIVE * 0.999,
        ] {
            assert_eq!(rgbe_encode(Vec3::splat(v)).unwrap(), [0; 4]);
        }
        // The smallest normal is representable.
        let v = f32::MIN_POSITIVE;
        let d = rgbe_decode(rgbe_encode(Vec3::new(v, 0.0, 0.0)).unwrap());
        assert_eq!(d.x, v);
    }

    #[test]
    fn rgbe_saturates_without_wrap() {
        let enc = rgbe_encode(Vec3::new(f32::MAX, 1.0, 0.0)).unwrap();
        assert_eq!(enc, [255, 0, 0, 255]);
        assert_eq!(rgbe_decode(enc).x, RGBE_MAX);
        let enc = rgbe_encode(Vec3::new(f32::MAX, f32::MAX / 2.0, 1e38)).unwrap();
        assert_eq!(enc[3], 255);
        let d = rgbe_decode(enc);
        assert!(d.is_finite() && d.max_element() == RGBE_MAX);
        // Largest value below the saturation threshold still encodes normally.
        let v = RGBE_MAX;
        let d = rgbe_decode(rgbe_encode(Vec3::splat(v)).unwrap());
        assert_eq!(d, Vec3::splat(v));
        // Values just under 2^127 round up into exponent byte 255 (no wrap).
        let v = f32::from_bits((127 + 126) << 23 | 0x7f_ffff); // just below 2^127
        let enc = rgbe_encode(Vec3::splat(v)).unwrap();
        assert_eq!(enc[3], 255);
        assert!(rgbe_decode(enc).x > 0.0);
    }

    /// Relative error of the largest channel ≤ 1/256, absolute error of every
    /// channel ≤ max/256, over 1e-30 … 1e30 (log-uniform), plus flush-to-zero
    /// of channels below max·2⁻⁹.
    #[test]
    fn rgbe_precision_over_range() {
        let mut rng = Rng(0x1234_5678_9abc_def1);
        let mut worst_rel = 0.0f64;
        let mut worst_abs = 0.0f64;
        for i in 0..1_000_000 {
            let exp = -30.0 + 60.0 * rng.f64();
            let max = 10f64.powf(exp);
            // Other channels: anywhere from 0 to max, log-spread down to 2^-40·max.
            let mut c = [max, max * rng.f64(), max * 2f64.powf(-40.0 * rng.f64())];
            c.rotate_left(i % 3);
            let cf = c.map(|x| x as f32);
            let m = cf.iter().copied().fold(0.0f32, f32::max) as f64;
            let d = rgbe_decode(rgbe_encode(Vec3::from_array(cf)).unwrap()).to_array();
            for ch in 0..3 {
                let err = (d[ch] as f64 - cf[ch] as f64).abs();
                worst_abs = worst_abs.max(err / m);
                assert!(err <= m / 255.5, "abs {cf:?} -> {d:?}");
                if (cf[ch] as f64) < m * 2f64.powi(-9) {
                    assert_eq!(d[ch], 0.0, "flush {cf:?} -> {d:?}");
                }
                if cf[ch] as f64 == m {
                    worst_rel = worst_rel.max(err / m);
                    assert!(err / m <= 1.0 / 256.0, "rel {cf:?} -> {d:?}");
                }
            }
        }
        eprintln!("rgbe: worst relative error (largest channel) {worst_rel:.6e} = {:.4}/256, worst absolute error / max {worst_abs:.6e} = {:.4}/256", worst_rel * 256.0, worst_abs * 256.0);
        assert!(worst_rel <= 1.0 / 256.0 && worst_abs <= 1.0 / 255.5);
        // Rounding reaches close to the half-step bound.
        assert!(worst_rel > 0.9 / 256.0, "worst relative error {worst_rel}");
    }

    #[test]
    fn rgbe_extremes_of_requested_range() {
        for v in [1e-30f32, 3.3e-30, 1e30, 7.7e29, 1.2e-38, 1e38] {
            let d = rgbe_decode(rgbe_encode(Vec3::new(v, v / 3.0, 0.0)).unwrap());
            assert!(((d.x - v) / v).abs() <= 1.0 / 256.0, "{v} -> {}", d.x);
            assert!((d.y - v / 3.0).abs() <= v / 256.0);
            assert_eq!(d.z, 0.0);
        }
    }

    #[test]
    fn direction_tables_are_unit() {
        let t = direction_tables();
        for i in 0..256 {
            let s = t.sin_theta[i].powi(2) + t.cos_theta[i].powi(2);
            assert!((s - 1.0).abs() < 1e-6);
            let s = t.sin_phi[i].powi(2) + t.cos_phi[i].powi(2);
            assert!((s - 1.0).abs() < 1e-6);
        }
    }

    fn angle(a: Vec3, b: Vec3) -> f64 {
        // atan2 form is accurate for small angles.
        let (a, b) = (a.as_dvec3().normalize(), b.as_dvec3().normalize());
        a.cross(b).length().atan2(a.dot(b))
    }

    /// Dense sampling of the sphere (10^6 random directions + a θ/φ grid with
    /// poles, seams and the phi wrap): the max error stays under the derived
    /// bound π√5/512, and each sample under its local bound
    /// √((π/512)² + (S·π/256)²) with S = max sin θ over its theta bin.
    #[test]
    fn direction_quantisation_error_bound() {
        use std::f64::consts::PI;
        let bound = DIRECTION_ERROR_BOUND as f64;
        assert!((bound - PI * 5f64.sqrt() / 512.0).abs() < 1e-6);
        let mut worst = 0.0f64;
        let mut check = |d: Vec3| {
            let (phi, theta) = encode_direction(d);
            let q = decode_direction(phi, theta);
            let a = angle(d, q);
            let lo = theta as f64 * PI / 256.0;
            let hi = lo + PI / 256.0;
            let s = if lo <= PI / 2.0 && hi >= PI / 2.0 {
                1.0
            } else {
                lo.sin().max(hi.sin())
            };
            let local = ((PI / 512.0).powi(2) + (s * PI / 256.0).powi(2)).sqrt();
            // 1e-6 slack: f32 rounding of the input and of acos/atan2.
            assert!(a <= local + 1e-6, "{d:?}: {a} > {local}");
            worst = worst.max(a);
        };
        let mut rng = Rng(42);
        for _ in 0..1_000_000 {
            let z = 2.0 * rng.f64() - 1.0;
            let p = 2.0 * PI * rng.f64();
            let r = (1.0 - z * z).sqrt();
            check(Vec3::new(
                (r * p.cos()) as f32,
                (r * p.sin()) as f32,
                z as f32,
            ));
        }
        // Grid through bin edges (worst cases), poles and the ±π seam.
        for i in 0..=512 {
            let t = i as f64 * PI / 512.0;
            for j in 0..=1024 {
                let p = -PI + j as f64 * 2.0 * PI / 1024.0;
                let d = Vec3::new(
                    (t.sin() * p.cos()) as f32,
                    (t.sin() * p.sin()) as f32,
                    t.cos() as f32,
                );
                check(d);
                // Just either side of the phi = 0 wrap.
                check(Vec3::new(d.x.abs().max(1e-3), -1e-7, d.z).normalize());
            }
        }
        for d in [Vec3::Z, -Vec3::Z, Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y] {
            check(d);
        }
        eprintln!("direction: worst angular error {worst:.6e} rad, bound {bound:.6e} rad");
        assert!(worst <= bound + 1e-6, "worst {worst} > {bound}");
        // The bound is reasonably tight (the measured max is near it).
        assert!(worst > 0.8 * bound, "worst {worst} bound {bound}");
    }

    #[test]
    fn direction_edges() {
        assert_eq!(encode_direction(Vec3::Z).1, 0);
        assert_eq!(encode_direction(-Vec3::Z).1, 255);
        // Slightly negative phi wraps to the last bin, not bin 0.
        assert_eq!(encode_direction(Vec3::new(1.0, -1e-6, 0.0)).0, 255);
        assert_eq!(encode_direction(Vec3::new(1.0, 1e-6, 0.0)).0, 0);
        assert_eq!(encode_direction(-Vec3::X).0, 128);
        // Non-unit z slightly above 1 is clamped, not NaN.
        assert_eq!(encode_direction(Vec3::new(0.0, 0.0, 1.000_001)).1, 0);
    }

    #[test]
    fn photon_accessors() {
        let pos = Vec3::new(1.0, -2.0, 3.5);
        let power = Vec3::new(0.25, 0.5, 1.0);
        let travel = Vec3::new(0.3, -0.4, -1.0);
        let mut p = Photon::new(pos, power, travel).unwrap();
        let f = PhotonF32::new(pos, power, travel).unwrap();
        assert_eq!(p.position(), pos);
        assert_eq!(p.power(), power);
        assert_eq!(f.power(), power);
        let inc = -travel.normalize();
        assert!(angle(p.incoming(), inc) <= DIRECTION_ERROR_BOUND as f64 + 1e-6);
        assert_eq!(p.incoming(), f.incoming());
        assert!((p.incoming().length() - 1.0).abs() < 1e-6);
        p.set_axis(2);
        p.set_user_flags(0x155);
        assert_eq!(p.axis(), 2);
        assert_eq!(p.user_flags(), 0x155);
        p.set_axis(LEAF_AXIS);
        assert_eq!(p.axis(), 3);
        assert_eq!(p.user_flags(), 0x155);
        let g: PhotonF32 = p.into();
        assert_eq!(g.axis(), 3);
        assert_eq!(g.user_flags(), 0x155);
    }
}
