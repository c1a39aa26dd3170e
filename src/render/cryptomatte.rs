//! Cryptomatte (Friedman & Jones, Psyop 2015; specification 1.1.0): ids from names by
//! MurmurHash3, their float form, the ranking of a pixel's ids by coverage, and the EXR
//! metadata (type name, hash, conversion, manifest).
//!
//! A name's id is MurmurHash3_x86_32 of its UTF-8 bytes with seed 0, written into a float
//! bit for bit with the exponent clamped to [1, 254] (no zero, denormal, infinity or NaN:
//! the specification's `uint32_to_float32`). Each pixel keeps, per type, the ids its camera
//! samples saw first, ranked by coverage (the share of the pixel's samples; every sample
//! weighs the same under filter importance sampling), as (id, coverage) pairs in
//! `<type>00.R/G/B/A`, `<type>01` ...: ranks 0 and 1 in the first layer, and so on. Samples
//! that reach no surface add no id, so coverages sum to the pixel's share of surfaces.

use std::collections::BTreeMap;

/// MurmurHash3_x86_32 (Austin Appleby, public domain) of `data` with `seed`.
pub fn murmur3_32(data: &[u8], seed: u32) -> u32 {
    const C1: u32 = 0xcc9e_2d51;
    const C2: u32 = 0x1b87_3593;
    let mut h = seed;
    let mut blocks = data.chunks_exact(4);
    for b in &mut blocks {
        let mut k = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        k = k.wrapping_mul(C1).rotate_left(15).wrapping_mul(C2);
        h ^= k;
        h = h.rotate_left(13).wrapping_mul(5).wrapping_add(0xe654_6b64);
    }
    let tail = blocks.remainder();
    if !tail.is_empty() {
        let mut k = 0u32;
        for (i, &byte) in tail.iter().enumerate() {
            k |= (byte as u32) << (8 * i);
        }
        k = k.wrapping_mul(C1).rotate_left(15).wrapping_mul(C2);
        h ^= k;
    }
    h ^= data.len() as u32;
    h ^= h >> 16;
    h = h.wrapping_mul(0x85eb_ca6b);
    h ^= h >> 13;
    h = h.wrapping_mul(0xc2b2_ae35);
    h ^= h >> 16;
    h
}

/// The specification's `uint32_to_float32`: the hash's bits as a float, the exponent clamped
/// to [1, 254].
pub fn hash_to_float(hash: u32) -> f32 {
    let mantissa = hash & ((1 << 23) - 1);
    let exponent = ((hash >> 23) & 0xff).clamp(1, 254);
    f32::from_bits((hash & 0x8000_0000) | (exponent << 23) | mantissa)
}

/// A name's id, as the pixels hold it.
pub fn name_id(name: &str) -> f32 {
    hash_to_float(murmur3_32(name.as_bytes(), 0))
}

/// The manifest's form of an id: the 8 hex digits of its float's bits.
pub fn id_hex(id: f32) -> String {
    format!("{:08x}", id.to_bits())
}

/// The metadata key of a Cryptomatte layer named `layer` (the type name, with a view layer's
/// name before it in Blender): the first 7 hex digits of its MurmurHash3, as Blender and
/// the reference implementations choose it.
pub fn metadata_key(layer: &str) -> String {
    format!("{:08x}", murmur3_32(layer.as_bytes(), 0))[..7].to_string()
}

/// The EXR header attributes of one Cryptomatte type: `cryptomatte/<key>/name`, `hash`,
/// `conversion` and `manifest` (a JSON object of name -> id hex, names sorted).
pub fn header(layer: &str, names: &[String]) -> BTreeMap<String, String> {
    let key = metadata_key(layer);
    let manifest: BTreeMap<&str, String> = names
        .iter()
        .map(|n| (n.as_str(), id_hex(name_id(n))))
        .collect();
    let mut out = BTreeMap::new();
    let mut put = |k: &str, v: String| out.insert(format!("cryptomatte/{key}/{k}"), v);
    put("name", layer.to_string());
    put("hash", "MurmurHash3_32".to_string());
    put("conversion", "uint32_to_float32".to_string());
    put(
        "manifest",
        serde_json::to_string(&manifest).unwrap_or_else(|_| "{}".into()),
    );
    out
}

/// A pixel's samples of one type: how many samples saw each id (by the index of its name),
/// in order of first appearance.
#[derive(Clone, Debug, Default)]
pub struct Coverage(Vec<(u32, u32)>);

impl Coverage {
    pub fn add(&mut self, index: u32) {
        match self.0.iter_mut().find(|(i, _)| *i == index) {
            Some((_, n)) => *n += 1,
            None => self.0.push((index, 1)),
        }
    }

    /// The (id, coverage) pairs of the `levels` most covering ids over `samples` samples:
    /// by coverage, ties by id bits (a pixel's result does not depend on the order of its
    /// samples); unused ranks are (0, 0).
    pub fn ranked(&self, ids: &[f32], samples: u32, levels: usize) -> Vec<(f32, f32)> {
        let mut v: Vec<(f32, u32)> = self
            .0
            .iter()
            .map(|&(i, n)| (ids.get(i as usize).copied().unwrap_or(0.0), n))
            .collect();
        v.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.to_bits().cmp(&b.0.to_bits())));
        let inv = 1.0 / samples.max(1) as f32;
        (0..levels)
            .map(|r| v.get(r).map_or((0.0, 0.0), |&(id, n)| (id, n as f32 * inv)))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference values of MurmurHash3_x86_32, seed 0 (SMHasher's verification strings and
    /// the values the Python `mmh3` module gives).
    #[test]
    fn murmur3_matches_the_reference() {
        assert_eq!(murmur3_32(b"", 0), 0);
        assert_eq!(murmur3_32(b"", 1), 0x514e_28b7);
        assert_eq!(murmur3_32(b"hello", 0), 0x248b_fa47);
        assert_eq!(murmur3_32(b"Hello, world!", 0), 0xc036_3e43);
        assert_eq!(
            murmur3_32(b"The quick brown fox jumps over the lazy dog", 0),
            0x2e4f_f723
        );
        // Tails of 1, 2 and 3 bytes.
        assert_eq!(murmur3_32(b"a", 0), 0x3c25_69b2);
        assert_eq!(murmur3_32(b"ab", 0), 0x9bbf_d75f);
        assert_eq!(murmur3_32(b"abc", 0), 0xb3dd_93fa);
    }

    /// The specification's example manifest: "bunny" -> 13851a76, "default" -> 42c9679f.
    #[test]
    fn ids_are_the_specifications() {
        assert_eq!(id_hex(name_id("bunny")), "13851a76");
        assert_eq!(id_hex(name_id("default")), "42c9679f");
        // The exponent is clamped: no id is zero, denormal, infinite or NaN.
        for h in [0u32, 0x7f80_0000, 0xff80_0001, 0x0000_0001, 0x7fff_ffff] {
            let f = hash_to_float(h);
            assert!(f.is_normal(), "{h:#x} -> {f}");
        }
        assert_eq!(hash_to_float(0x4000_0000), 2.0);
    }

    #[test]
    fn coverage_ranks_by_share_and_pads_with_zeros() {
        let ids = [name_id("a"), name_id("b"), name_id("c")];
        let mut c = Coverage::default();
        for i in [2, 0, 2, 1, 2, 0] {
            c.add(i);
        }
        let r = c.ranked(&ids, 8, 4);
        assert_eq!(r[0], (ids[2], 3.0 / 8.0));
        assert_eq!(r[1], (ids[0], 2.0 / 8.0));
        assert_eq!(r[2], (ids[1], 1.0 / 8.0));
        assert_eq!(r[3], (0.0, 0.0));
    }

    #[test]
    fn the_header_names_its_type_and_lists_the_manifest() {
        let h = header(
            "CryptoObject",
            &["bunny".to_string(), "default".to_string()],
        );
        let key = metadata_key("CryptoObject");
        assert_eq!(key.len(), 7);
        assert_eq!(h[&format!("cryptomatte/{key}/name")], "CryptoObject");
        assert_eq!(h[&format!("cryptomatte/{key}/hash")], "MurmurHash3_32");
        assert_eq!(
            h[&format!("cryptomatte/{key}/conversion")],
            "uint32_to_float32"
        );
        assert_eq!(
            h[&format!("cryptomatte/{key}/manifest")],
            r#"{"bunny":"13851a76","default":"42c9679f"}"#
        );
    }
}
