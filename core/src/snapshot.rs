//! Versioned, little-endian state serialisation used by every engine's
//! `snapshot()` / `restore()`.
//!
//! Layout: magic `b"STRK"`, one byte engine kind, u16 format version, then the
//! engine's fields in a fixed order, then a CRC-32 of everything before it.
//! Floats are stored bit-exactly, so a restored engine continues with exactly the
//! output the original would have produced.

/// Why a snapshot could not be read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SnapshotError {
    #[error("not a stridekit snapshot (bad magic)")]
    BadMagic,
    #[error("snapshot is of another engine (kind {found}, expected {expected})")]
    WrongKind { found: u8, expected: u8 },
    #[error("snapshot version {found} is not supported (this build reads {supported})")]
    UnsupportedVersion { found: u16, supported: u16 },
    #[error("snapshot is truncated")]
    Truncated,
    #[error("snapshot checksum mismatch (corrupted)")]
    Checksum,
    #[error("snapshot holds an invalid value: {0}")]
    Invalid(&'static str),
}

const MAGIC: &[u8; 4] = b"STRK";

/// Appends fields to a snapshot buffer.
pub struct Writer {
    buf: Vec<u8>,
}

impl Writer {
    pub fn new(kind: u8, version: u16) -> Self {
        let mut buf = Vec::with_capacity(1024);
        buf.extend_from_slice(MAGIC);
        buf.push(kind);
        buf.extend_from_slice(&version.to_le_bytes());
        Self { buf }
    }
    pub fn f64(&mut self, v: f64) {
        self.buf.extend_from_slice(&v.to_bits().to_le_bytes());
    }
    pub fn u64(&mut self, v: u64) {
        self.buf.extend_from_slice(&v.to_le_bytes());
    }
    pub fn u8(&mut self, v: u8) {
        self.buf.push(v);
    }
    pub fn bool(&mut self, v: bool) {
        self.buf.push(v as u8);
    }
    pub fn opt_f64(&mut self, v: Option<f64>) {
        self.bool(v.is_some());
        self.f64(v.unwrap_or(0.0));
    }
    pub fn f64s(&mut self, vs: &[f64]) {
        for &v in vs {
            self.f64(v);
        }
    }
    /// A nested blob (e.g. a sub-engine's own snapshot), length-prefixed.
    pub fn bytes(&mut self, b: &[u8]) {
        self.u64(b.len() as u64);
        self.buf.extend_from_slice(b);
    }
    pub fn finish(mut self) -> Vec<u8> {
        let crc = crc32(&self.buf);
        self.buf.extend_from_slice(&crc.to_le_bytes());
        self.buf
    }
}

/// Reads fields back in the order they were written.
pub struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    /// Check magic, kind, version and checksum; returns the reader and the version found.
    pub fn new(bytes: &'a [u8], kind: u8, supported: u16) -> Result<(Self, u16), SnapshotError> {
        if bytes.len() < 4 + 1 + 2 + 4 {
            return Err(if bytes.starts_with(MAGIC) || bytes.len() < 4 {
                SnapshotError::Truncated
            } else {
                SnapshotError::BadMagic
            });
        }
        if &bytes[..4] != MAGIC {
            return Err(SnapshotError::BadMagic);
        }
        let (body, crc) = bytes.split_at(bytes.len() - 4);
        let crc = u32::from_le_bytes([crc[0], crc[1], crc[2], crc[3]]);
        if crc32(body) != crc {
            return Err(SnapshotError::Checksum);
        }
        if body[4] != kind {
            return Err(SnapshotError::WrongKind {
                found: body[4],
                expected: kind,
            });
        }
        let version = u16::from_le_bytes([body[5], body[6]]);
        if version == 0 || version > supported {
            return Err(SnapshotError::UnsupportedVersion {
                found: version,
                supported,
            });
        }
        Ok((Self { buf: body, pos: 7 }, version))
    }
    fn take<const N: usize>(&mut self) -> Result<[u8; N], SnapshotError> {
        let end = self.pos + N;
        let s = self
            .buf
            .get(self.pos..end)
            .ok_or(SnapshotError::Truncated)?;
        self.pos = end;
        let mut a = [0u8; N];
        a.copy_from_slice(s);
        Ok(a)
    }
    pub fn f64(&mut self) -> Result<f64, SnapshotError> {
        Ok(f64::from_bits(u64::from_le_bytes(self.take::<8>()?)))
    }
    pub fn u64(&mut self) -> Result<u64, SnapshotError> {
        Ok(u64::from_le_bytes(self.take::<8>()?))
    }
    pub fn u8(&mut self) -> Result<u8, SnapshotError> {
        Ok(self.take::<1>()?[0])
    }
    pub fn bool(&mut self) -> Result<bool, SnapshotError> {
        match self.u8()? {
            0 => Ok(false),
            1 => Ok(true),
            _ => Err(SnapshotError::Invalid("boolean")),
        }
    }
    pub fn opt_f64(&mut self) -> Result<Option<f64>, SnapshotError> {
        let some = self.bool()?;
        let v = self.f64()?;
        Ok(some.then_some(v))
    }
    pub fn f64s(&mut self, out: &mut [f64]) -> Result<(), SnapshotError> {
        for v in out.iter_mut() {
            *v = self.f64()?;
        }
        Ok(())
    }
    /// A nested blob written by [`Writer::bytes`].
    pub fn bytes(&mut self) -> Result<&'a [u8], SnapshotError> {
        let n = self.u64()?;
        let n = usize::try_from(n).map_err(|_| SnapshotError::Truncated)?;
        let end = self.pos.checked_add(n).ok_or(SnapshotError::Truncated)?;
        let s = self
            .buf
            .get(self.pos..end)
            .ok_or(SnapshotError::Truncated)?;
        self.pos = end;
        Ok(s)
    }
    /// A count stored as u64 that must not exceed `max`.
    pub fn len(&mut self, max: usize) -> Result<usize, SnapshotError> {
        let n = self.u64()?;
        if n > max as u64 {
            return Err(SnapshotError::Invalid("length"));
        }
        Ok(n as usize)
    }
    /// Fails unless every byte was consumed.
    pub fn end(self) -> Result<(), SnapshotError> {
        if self.pos == self.buf.len() {
            Ok(())
        } else {
            Err(SnapshotError::Invalid("trailing bytes"))
        }
    }
}

/// CRC-32 (IEEE 802.3, reflected, poly 0xEDB88320), bitwise: snapshots are small.
pub fn crc32(data: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFFu32;
    for &b in data {
        crc ^= b as u32;
        for _ in 0..8 {
            let mask = (crc & 1).wrapping_neg();
            crc = (crc >> 1) ^ (0xEDB8_8320 & mask);
        }
    }
    !crc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_matches_reference() {
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
    }

    #[test]
    fn roundtrip_and_corruption() {
        let mut w = Writer::new(7, 1);
        w.f64(1.5);
        w.opt_f64(None);
        w.u64(42);
        let bytes = w.finish();
        let (mut r, v) = Reader::new(&bytes, 7, 1).unwrap();
        assert_eq!(v, 1);
        assert_eq!(r.f64().unwrap(), 1.5);
        assert_eq!(r.opt_f64().unwrap(), None);
        assert_eq!(r.u64().unwrap(), 42);
        r.end().unwrap();
        let mut bad = bytes.clone();
        bad[9] ^= 1;
        assert_eq!(Reader::new(&bad, 7, 1).err(), Some(SnapshotError::Checksum));
        assert!(matches!(
            Reader::new(&bytes, 8, 1).err(),
            Some(SnapshotError::WrongKind { .. })
        ));
        assert_eq!(
            Reader::new(&bytes[..3], 7, 1).err(),
            Some(SnapshotError::Truncated)
        );
        assert_eq!(
            Reader::new(b"hello world!", 7, 1).err(),
            Some(SnapshotError::BadMagic)
        );
    }
}
