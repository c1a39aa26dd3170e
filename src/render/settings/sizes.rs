//! Sizes in bytes: of a stored photon and a triangle in the memory estimate, of the memory
//! available, and byte counts as users write them.

/// Bytes per stored photon: the 20-byte photon of `photon::Photon` (RGBE power, position,
/// quantised direction, split-axis flag).
pub const BYTES_PER_PHOTON: u64 = 20;

/// Bytes per stored photon with `photon_power f32`: the 28-byte `photon::PhotonF32`
/// (the same record with the power as three `f32`).
pub const BYTES_PER_PHOTON_F32: u64 = 28;

/// Bytes per triangle of the BVH in the memory estimate. The 4-wide BVH takes 128 bytes per
/// node plus a 4-byte index per triangle, and the leaf-ordered triangle copy 36 bytes per
/// triangle: about 24 + 36 = 60 bytes per triangle with leaves of three triangles on
/// average (the BVH bench's 808,200-triangle sphere: 127,006 nodes, 19.5 MB, and 29.1 MB of
/// triangles); the 68 bytes counted leave room for smaller leaves.
pub const BYTES_PER_TRIANGLE: u64 = 2 * 32 + 4;

/// Available memory: `MemAvailable` of `/proc/meminfo`, in bytes; `None` where it cannot be
/// read (other systems), which means no limit.
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let mut parts = line["MemAvailable:".len()..].split_whitespace();
    let value: u64 = parts.next()?.parse().ok()?;
    match parts.next() {
        Some("kB") => value.checked_mul(1024),
        None => Some(value),
        Some(_) => None,
    }
}

/// Parses a byte count: a plain integer, or one with a binary suffix `K`, `M`, `G`, `T`
/// (optionally followed by `B` or `iB`, any case): `8G` = 8 * 2^30, `512M` = 512 * 2^20.
pub fn parse_bytes(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let digits = t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len());
    let (num, suffix) = t.split_at(digits);
    let bad = || format!("`{s}` is not a size in bytes (expected e.g. 1000000, 512M or 8G)");
    let n: u64 = num.parse().map_err(|_| bad())?;
    let unit = suffix.trim().to_ascii_lowercase();
    let shift = match unit.trim_end_matches("ib").trim_end_matches('b') {
        "" => 0,
        "k" => 10,
        "m" => 20,
        "g" => 30,
        "t" => 40,
        _ => return Err(bad()),
    };
    if unit == "ib" {
        return Err(bad());
    }
    n.checked_mul(1u64 << shift).ok_or_else(bad)
}
