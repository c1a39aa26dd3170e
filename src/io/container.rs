//! The binary container of the renderer's own files (saved photon maps, partial sums of
//! progressive passes): a fixed header, a payload and a checksum, written atomically.
//!
//! ```text
//! offset  size  field
//! 0       8     magic: what the file holds (e.g. b"PMAPS\0\r\n")
//! 8       4     format version, u32 little-endian
//! 12      8     payload length n, u64 little-endian
//! 20      n     payload
//! 20+n    4     CRC-32 (IEEE 802.3) of bytes [0, 20+n), u32 little-endian
//! ```
//!
//! Reading checks, in this order, and names the file in each error: the magic (another kind
//! of file), the version (a file of another version of the format), the length (a truncated
//! file) and the checksum (a corrupt file). Numbers inside payloads are little-endian.

use crate::error::{Error, Result};
use std::path::{Path, PathBuf};

/// Bytes before the payload.
pub const HEADER_BYTES: usize = 20;

/// The CRC-32 tables of the reflected IEEE polynomial 0xEDB88320 for slicing by 8 (table 0
/// is the classic byte-at-a-time table; table k advances a byte by k more zero bytes).
const CRC_TABLES: [[u32; 256]; 8] = {
    let mut t = [[0u32; 256]; 8];
    let mut i = 0;
    while i < 256 {
        let mut c = i as u32;
        let mut k = 0;
        while k < 8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
            k += 1;
        }
        t[0][i] = c;
        i += 1;
    }
    let mut i = 0;
    while i < 256 {
        let mut k = 1;
        while k < 8 {
            let prev = t[k - 1][i];
            t[k][i] = (prev >> 8) ^ t[0][(prev & 0xFF) as usize];
            k += 1;
        }
        i += 1;
    }
    t
};

/// CRC-32 (IEEE 802.3, as zlib's `crc32`) of `data`, eight bytes at a time.
pub fn crc32(data: &[u8]) -> u32 {
    let t = &CRC_TABLES;
    let mut c = 0xFFFF_FFFFu32;
    let mut chunks = data.chunks_exact(8);
    for b in &mut chunks {
        let lo = c ^ u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        c = t[7][(lo & 0xFF) as usize]
            ^ t[6][((lo >> 8) & 0xFF) as usize]
            ^ t[5][((lo >> 16) & 0xFF) as usize]
            ^ t[4][(lo >> 24) as usize]
            ^ t[3][b[4] as usize]
            ^ t[2][b[5] as usize]
            ^ t[1][b[6] as usize]
            ^ t[0][b[7] as usize];
    }
    for &b in chunks.remainder() {
        c = t[0][((c ^ b as u32) & 0xFF) as usize] ^ (c >> 8);
    }
    c ^ 0xFFFF_FFFF
}

/// What a container holds: its magic, the version this build writes and reads, and how
/// errors name it.
#[derive(Clone, Copy, Debug)]
pub struct Kind {
    pub magic: [u8; 8],
    pub version: u32,
    /// e.g. "photon-map file".
    pub what: &'static str,
}

/// The whole file: header, `payload`, checksum.
pub fn encode(kind: &Kind, payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEADER_BYTES + payload.len() + 4);
    out.extend_from_slice(&kind.magic);
    out.extend_from_slice(&kind.version.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(payload);
    let crc = crc32(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// The payload of a container's bytes, checked; `source` names the file in errors.
pub fn decode<'a>(kind: &Kind, bytes: &'a [u8], source: &Path) -> Result<&'a [u8]> {
    let what = kind.what;
    let err = |m: String| Error::io(source, m);
    if bytes.len() < 8 || bytes[..8] != kind.magic {
        return Err(err(format!(
            "not a photonmap {what} ({} bytes; it does not start with the {what}'s magic number)",
            bytes.len()
        )));
    }
    if bytes.len() < HEADER_BYTES {
        return Err(err(format!(
            "truncated {what}: {} bytes, shorter than its {HEADER_BYTES}-byte header",
            bytes.len()
        )));
    }
    let version = u32::from_le_bytes(bytes[8..12].try_into().unwrap_or_default());
    if version != kind.version {
        return Err(err(format!(
            "{what} of format version {version}; this photonmap ({}) reads version {} only: \
             write it again with this version",
            env!("CARGO_PKG_VERSION"),
            kind.version
        )));
    }
    let len = u64::from_le_bytes(bytes[12..20].try_into().unwrap_or_default());
    let expected = (HEADER_BYTES as u64).saturating_add(len).saturating_add(4);
    if (bytes.len() as u64) < expected {
        return Err(err(format!(
            "truncated {what}: {} bytes, its header says {expected}",
            bytes.len()
        )));
    }
    if (bytes.len() as u64) > expected {
        return Err(err(format!(
            "corrupt {what}: {} bytes, its header says {expected}",
            bytes.len()
        )));
    }
    let end = HEADER_BYTES + len as usize;
    let stored = u32::from_le_bytes(bytes[end..end + 4].try_into().unwrap_or_default());
    let actual = crc32(&bytes[..end]);
    if stored != actual {
        return Err(err(format!(
            "corrupt {what}: checksum {actual:08x} does not match the stored {stored:08x}"
        )));
    }
    Ok(&bytes[HEADER_BYTES..end])
}

/// Writes `bytes` to `path` atomically: to a temporary file beside it, then renamed over it,
/// so that `path` never holds a partial file (a reader sees the old file or the new one).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    with_temp_path(path, |tmp| {
        std::fs::write(tmp, bytes).map_err(|e| Error::io(path, e))
    })
}

/// Calls `write` with a temporary path beside `path` (its directory created if missing),
/// then renames the file written there to `path`; on error the temporary file is removed. The temporary name keeps the extension
/// (`out.exr` -> `.out.exr.<pid>.<n>.tmp.exr`), for writers that look at it.
pub fn with_temp_path(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".into());
    let ext = path
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp: PathBuf = path.with_file_name(format!(".{name}.{}.{n}.tmp{ext}", std::process::id()));
    match write(&tmp) {
        Ok(()) => std::fs::rename(&tmp, path).map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            Error::io(path, e)
        }),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// Reads and checks a container file; returns its payload.
pub fn read(kind: &Kind, path: &Path) -> Result<Vec<u8>> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    decode(kind, &bytes, path).map(|p| p.to_vec())
}

/// Little-endian writer of a payload.
#[derive(Default)]
pub struct Writer {
    pub buf: Vec<u8>,
}

impl Writer {
    pub fn u8(&mut self, v: u8) {
        self.buf.push(v);
    }
    pub fn u32(&mut self, v: u32) {
        self.buf.extend_from_slice(&v.to_le_bytes());
    }
    pub fn u64(&mut self, v: u64) {
        self.buf.extend_from_slice(&v.to_le_bytes());
    }
    pub fn i64(&mut self, v: i64) {
        self.buf.extend_from_slice(&v.to_le_bytes());
    }
    pub fn f32(&mut self, v: f32) {
        self.buf.extend_from_slice(&v.to_le_bytes());
    }
    pub fn f64(&mut self, v: f64) {
        self.buf.extend_from_slice(&v.to_le_bytes());
    }
    /// A length-prefixed byte string.
    pub fn bytes(&mut self, v: &[u8]) {
        self.u64(v.len() as u64);
        self.buf.extend_from_slice(v);
    }
    pub fn str(&mut self, v: &str) {
        self.bytes(v.as_bytes());
    }
}

/// Little-endian reader of a payload; running out is an error naming the file and the field.
pub struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
    source: &'a Path,
    what: &'static str,
}

impl<'a> Reader<'a> {
    pub fn new(data: &'a [u8], source: &'a Path, what: &'static str) -> Self {
        Reader {
            data,
            pos: 0,
            source,
            what,
        }
    }

    /// An error about this file: `corrupt <what>: <message>`.
    pub fn corrupt(&self, message: impl std::fmt::Display) -> Error {
        Error::io(self.source, format!("corrupt {}: {message}", self.what))
    }

    pub fn take(&mut self, n: usize, field: &str) -> Result<&'a [u8]> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.data.len());
        match end {
            Some(end) => {
                let s = &self.data[self.pos..end];
                self.pos = end;
                Ok(s)
            }
            None => Err(self.corrupt(format!(
                "`{field}` runs past the end of the payload ({} of {} bytes read)",
                self.pos,
                self.data.len()
            ))),
        }
    }
    fn array<const N: usize>(&mut self, field: &str) -> Result<[u8; N]> {
        let s = self.take(N, field)?;
        let mut a = [0u8; N];
        a.copy_from_slice(s);
        Ok(a)
    }
    pub fn u8(&mut self, field: &str) -> Result<u8> {
        Ok(self.array::<1>(field)?[0])
    }
    pub fn u32(&mut self, field: &str) -> Result<u32> {
        Ok(u32::from_le_bytes(self.array(field)?))
    }
    pub fn u64(&mut self, field: &str) -> Result<u64> {
        Ok(u64::from_le_bytes(self.array(field)?))
    }
    pub fn i64(&mut self, field: &str) -> Result<i64> {
        Ok(i64::from_le_bytes(self.array(field)?))
    }
    pub fn f32(&mut self, field: &str) -> Result<f32> {
        Ok(f32::from_le_bytes(self.array(field)?))
    }
    pub fn f64(&mut self, field: &str) -> Result<f64> {
        Ok(f64::from_le_bytes(self.array(field)?))
    }
    /// A count of items of `item_bytes` each that must fit in what is left.
    pub fn count(&mut self, item_bytes: usize, field: &str) -> Result<usize> {
        let n = self.u64(field)?;
        let left = (self.data.len() - self.pos) as u64;
        if n.saturating_mul(item_bytes.max(1) as u64) > left {
            return Err(self.corrupt(format!(
                "`{field}` says {n} items of {item_bytes} bytes, more than the {left} bytes left"
            )));
        }
        Ok(n as usize)
    }
    pub fn bytes(&mut self, field: &str) -> Result<&'a [u8]> {
        let n = self.count(1, field)?;
        self.take(n, field)
    }
    pub fn str(&mut self, field: &str) -> Result<&'a str> {
        let b = self.bytes(field)?;
        std::str::from_utf8(b).map_err(|_| self.corrupt(format!("`{field}` is not UTF-8")))
    }
    /// Errors unless every byte was read.
    pub fn finish(&self) -> Result<()> {
        if self.pos == self.data.len() {
            Ok(())
        } else {
            Err(self.corrupt(format!(
                "{} bytes left over after the last field",
                self.data.len() - self.pos
            )))
        }
    }
}

/// A 64-bit FNV-1a hash, fed bytes; used for content keys (not for security).
#[derive(Clone, Copy, Debug)]
pub struct Fnv64(pub u64);

impl Default for Fnv64 {
    fn default() -> Self {
        Fnv64(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv64 {
    pub fn write(&mut self, bytes: &[u8]) {
        let mut h = self.0;
        for &b in bytes {
            h ^= b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01B3);
        }
        self.0 = h;
    }
    pub fn u64(&mut self, v: u64) {
        self.write(&v.to_le_bytes());
    }
    pub fn finish(&self) -> u64 {
        self.0
    }
}

impl std::io::Write for Fnv64 {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        Fnv64::write(self, buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const KIND: Kind = Kind {
        magic: *b"TESTFILE",
        version: 3,
        what: "test file",
    };

    #[test]
    fn crc32_matches_the_standard_check_value() {
        // The check value of CRC-32/ISO-HDLC (zlib's crc32) for "123456789".
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
        assert_eq!(crc32(b""), 0);
        // Eight bytes at a time and one at a time agree, for every length and alignment.
        let data: Vec<u8> = (0..100u32).map(|i| (i * 37 + 11) as u8).collect();
        for a in 0..9 {
            for b in a..data.len() {
                let mut c = 0xFFFF_FFFFu32;
                for &x in &data[a..b] {
                    c = CRC_TABLES[0][((c ^ x as u32) & 0xFF) as usize] ^ (c >> 8);
                }
                assert_eq!(crc32(&data[a..b]), c ^ 0xFFFF_FFFF, "{a}..{b}");
            }
        }
    }

    #[test]
    fn fnv1a_matches_its_reference_values() {
        let h = |s: &[u8]| {
            let mut f = Fnv64::default();
            f.write(s);
            f.finish()
        };
        assert_eq!(h(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(h(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(h(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn a_container_round_trips_and_every_damage_is_named() {
        let p = Path::new("x.bin");
        let payload: Vec<u8> = (0..100u8).collect();
        let file = encode(&KIND, &payload);
        assert_eq!(decode(&KIND, &file, p).unwrap(), &payload[..]);
        let msg = |b: &[u8]| decode(&KIND, b, p).unwrap_err().to_string();
        assert!(msg(&file[..file.len() - 1]).contains("truncated test file"));
        assert!(msg(&file[..10]).contains("truncated test file"));
        assert!(msg(b"hello").contains("not a photonmap test file"));
        let mut other = file.clone();
        other[8] = 2;
        let m = msg(&other);
        assert!(
            m.contains("format version 2") && m.contains("reads version 3"),
            "{m}"
        );
        let mut bad = file.clone();
        bad[50] ^= 1;
        assert!(msg(&bad).contains("checksum"), "{}", msg(&bad));
        let mut long = file.clone();
        long.push(0);
        assert!(msg(&long).contains("corrupt"));
        assert!(msg(&file[..file.len() - 1]).starts_with("x.bin: "));
    }

    #[test]
    fn readers_stop_at_the_end() {
        let mut w = Writer::default();
        w.u32(7);
        w.str("abc");
        let p = Path::new("y.bin");
        let mut r = Reader::new(&w.buf, p, "test file");
        assert_eq!(r.u32("a").unwrap(), 7);
        assert_eq!(r.str("b").unwrap(), "abc");
        r.finish().unwrap();
        let e = r.u64("c").unwrap_err().to_string();
        assert!(e.contains("`c` runs past the end"), "{e}");
        let mut r = Reader::new(&w.buf, p, "test file");
        let e = r.count(8, "n").unwrap_err().to_string();
        assert!(e.contains("more than"), "{e}");
    }

    #[test]
    fn atomic_writes_leave_no_temporary_file() {
        let dir = std::env::temp_dir().join(format!("pm_atomic_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.bin");
        write_atomic(&p, b"one").unwrap();
        write_atomic(&p, b"two").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        let failed = with_temp_path(&p, |tmp| {
            std::fs::write(tmp, b"partial").unwrap();
            Err(Error::Internal("disk full".into()))
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 1, "{names:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
