//! Versioned, little-endian state serialisation used by every engine's
//! `snapshot()` / `restore()`.
//!
//! Layout: magic `b"STK2"`, one byte engine kind, u16 format version, u32 total
//! length in bytes (so a cut-off snapshot is told from a corrupted one), then the
//! engine's fields in a fixed order, then a CRC-32 of everything before it.
//! Floats are stored bit-exactly, so a restored engine continues with exactly the
//! output the original would have produced. Snapshots of the first envelope (magic
//! `b"STRK"`, no length) are still read.
//!
//! Restoring trusts nothing: [`Reader::f64`] refuses NaN and ±∞ (fields that may
//! legitimately hold them use [`Reader::f64_any`]), counts are bounded by
//! [`Reader::len`], and every engine checks its own ranges and invariants after
//! reading. The cost of a restore is linear in the snapshot's size.

/// Why a snapshot could not be read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SnapshotError {
    #[error("not a stridekit snapshot (bad magic)")]
    BadMagic,
    #[error("snapshot is of another engine (kind {found}, expected {expected})")]
    WrongKind { found: u8, expected: u8 },
    #[error(
        "snapshot format version {found} is not the one this build reads ({supported}): \
         it was written by another stridekit version"
    )]
    UnsupportedVersion { found: u16, supported: u16 },
    #[error("snapshot is truncated")]
    Truncated,
    #[error("snapshot checksum mismatch (corrupted)")]
    Checksum,
    #[error("snapshot holds an invalid value: {0}")]
    Invalid(&'static str),
    /// A number that must be finite is NaN, ±∞ or larger than any state holds
    /// (`offset`: its byte position).
    #[error("snapshot holds a number that is not finite or implausibly large (byte {offset})")]
    NonFinite { offset: usize },
}

/// Largest magnitude of a restored number, a backstop against values whose squares
/// or products overflow: no engine state comes near it (times are at most 10¹¹ s,
/// positions 10⁷ m, sums over a day of samples ~10¹³). Engines check their own,
/// tighter, physical ranges on top.
pub const MAX_MAGNITUDE: f64 = 1e30;

/// Magic of the current envelope (with a length field).
const MAGIC: &[u8; 4] = b"STK2";
/// Magic of the first envelope (no length field), still read.
const MAGIC_V1: &[u8; 4] = b"STRK";
/// Bytes before the fields: magic, kind, version, length.
const HEADER: usize = 4 + 1 + 2 + 4;

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
        buf.extend_from_slice(&[0; 4]); // total length, written by `finish`
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
        let total = u32::try_from(self.buf.len() + 4).expect("snapshot larger than 4 GiB");
        self.buf[7..11].copy_from_slice(&total.to_le_bytes());
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
    /// Check magic, length, checksum, kind and version (exactly `supported`); returns
    /// the reader and the version.
    pub fn new(bytes: &'a [u8], kind: u8, supported: u16) -> Result<(Self, u16), SnapshotError> {
        let legacy = bytes.starts_with(MAGIC_V1);
        let header = if legacy { HEADER - 4 } else { HEADER };
        if bytes.len() < 4 {
            return Err(if MAGIC.starts_with(bytes) || MAGIC_V1.starts_with(bytes) {
                SnapshotError::Truncated
            } else {
                SnapshotError::BadMagic
            });
        }
        if !legacy && &bytes[..4] != MAGIC {
            return Err(SnapshotError::BadMagic);
        }
        if bytes.len() < header + 4 {
            return Err(SnapshotError::Truncated);
        }
        if !legacy {
            let total = u32::from_le_bytes([bytes[7], bytes[8], bytes[9], bytes[10]]) as u64;
            if (bytes.len() as u64) < total {
                return Err(SnapshotError::Truncated);
            }
            if (bytes.len() as u64) > total {
                return Err(SnapshotError::Invalid("trailing bytes after the snapshot"));
            }
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
        // One layout per engine per build: snapshots resume a session across process
        // death with the same SDK, they are not an archive format.
        if version != supported {
            return Err(SnapshotError::UnsupportedVersion {
                found: version,
                supported,
            });
        }
        Ok((
            Self {
                buf: body,
                pos: header,
            },
            version,
        ))
    }
    /// The error for the number just read.
    pub fn non_finite(&self) -> SnapshotError {
        SnapshotError::NonFinite {
            offset: self.pos.saturating_sub(8),
        }
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
    /// A finite float of plausible size (NaN, ±∞ and |v| > [`MAX_MAGNITUDE`] are
    /// refused).
    pub fn f64(&mut self) -> Result<f64, SnapshotError> {
        let v = self.f64_any()?;
        if v.abs() <= MAX_MAGNITUDE {
            Ok(v)
        } else {
            Err(self.non_finite())
        }
    }
    /// A float that may be NaN or infinite (a field that uses them as markers).
    pub fn f64_any(&mut self) -> Result<f64, SnapshotError> {
        Ok(f64::from_bits(u64::from_le_bytes(self.take::<8>()?)))
    }
    /// A float as [`f64`](Self::f64), or NaN (NaN marks "none yet" in some states).
    pub fn f64_or_nan(&mut self) -> Result<f64, SnapshotError> {
        let v = self.f64_any()?;
        if v.is_nan() || v.abs() <= MAX_MAGNITUDE {
            Ok(v)
        } else {
            Err(self.non_finite())
        }
    }
    /// A time that may also be a marker: finite, NaN ("none yet") or −∞ ("long
    /// ago"); +∞ is refused.
    pub fn time_or_marker(&mut self) -> Result<f64, SnapshotError> {
        let v = self.f64_any()?;
        if v.is_nan() || v == f64::NEG_INFINITY || v.abs() <= MAX_MAGNITUDE {
            Ok(v)
        } else {
            Err(self.non_finite())
        }
    }
    /// A finite float in `min..=max`.
    pub fn f64_in(&mut self, min: f64, max: f64, what: &'static str) -> Result<f64, SnapshotError> {
        let v = self.f64()?;
        if (min..=max).contains(&v) {
            Ok(v)
        } else {
            Err(SnapshotError::Invalid(what))
        }
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
    /// An optional finite float.
    pub fn opt_f64(&mut self) -> Result<Option<f64>, SnapshotError> {
        let some = self.bool()?;
        let v = self.f64_any()?;
        if some && (v.is_nan() || v.abs() > MAX_MAGNITUDE) {
            return Err(self.non_finite());
        }
        Ok(some.then_some(v))
    }
    /// Finite floats.
    pub fn f64s(&mut self, out: &mut [f64]) -> Result<(), SnapshotError> {
        for v in out.iter_mut() {
            *v = self.f64()?;
        }
        Ok(())
    }
    /// Floats that may be NaN or infinite.
    pub fn f64s_any(&mut self, out: &mut [f64]) -> Result<(), SnapshotError> {
        for v in out.iter_mut() {
            *v = self.f64_any()?;
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

/// Whether a restored `p` is a covariance a Kalman filter can reach: symmetric and
/// positive semi-definite up to rounding. Tested on the correlation matrix
/// D^-1/2 P D^-1/2 (scale-free, so metres² beside radians² do not matter) by a
/// Cholesky factorisation with a small ridge. Checking |correlation| ≤ 1 pair by pair
/// is not enough: three states can be pairwise plausible and jointly impossible, and
/// the next update then drives a variance negative (a NaN standard deviation).
pub(crate) fn check_covariance<const N: usize>(
    p: &nalgebra::SMatrix<f64, N, N>,
) -> Result<(), &'static str> {
    let mut c = nalgebra::SMatrix::<f64, N, N>::zeros();
    for i in 0..N {
        if p[(i, i)].is_nan() || p[(i, i)] < 0.0 {
            return Err("negative variance");
        }
        for j in 0..N {
            let (a, b) = (p[(i, j)], p[(j, i)]);
            if (a - b).abs() > 1e-9 * (1.0 + a.abs()) {
                return Err("covariance not symmetric");
            }
            let d = (p[(i, i)] * p[(j, j)]).sqrt();
            c[(i, j)] = if i == j {
                1.0
            } else if d > 0.0 {
                0.5 * (a + b) / d
            } else if a == 0.0 && b == 0.0 {
                0.0
            } else {
                return Err("covariance with a zero variance but a correlation");
            };
        }
    }
    for i in 0..N {
        c[(i, i)] += 1e-9;
    }
    match c.cholesky() {
        Some(_) => Ok(()),
        None => Err("covariance not positive semi-definite"),
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
        bad[12] ^= 1;
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

    #[test]
    fn a_cut_off_snapshot_is_truncated_not_corrupted() {
        let mut w = Writer::new(7, 1);
        w.f64s(&[1.0; 16]);
        let bytes = w.finish();
        for n in 0..bytes.len() {
            assert_eq!(
                Reader::new(&bytes[..n], 7, 1).err(),
                Some(SnapshotError::Truncated),
                "cut at {n}"
            );
        }
        let mut long = bytes.clone();
        long.push(0);
        assert!(matches!(
            Reader::new(&long, 7, 1).err(),
            Some(SnapshotError::Invalid(_))
        ));
    }

    #[test]
    fn non_finite_numbers_are_refused_unless_asked_for() {
        let mut w = Writer::new(7, 1);
        w.f64(f64::NAN);
        w.f64(f64::INFINITY);
        w.opt_f64(Some(f64::NAN));
        let bytes = w.finish();
        let (mut r, _) = Reader::new(&bytes, 7, 1).unwrap();
        assert_eq!(r.f64().err(), Some(SnapshotError::NonFinite { offset: 11 }));
        let (mut r, _) = Reader::new(&bytes, 7, 1).unwrap();
        assert!(r.f64_any().unwrap().is_nan());
        assert_eq!(r.f64_any().unwrap(), f64::INFINITY);
        assert!(matches!(r.opt_f64(), Err(SnapshotError::NonFinite { .. })));
    }

    #[test]
    fn first_envelope_is_still_read() {
        // magic STRK, kind 7, version 1, one f64, CRC.
        let mut body = b"STRK".to_vec();
        body.push(7);
        body.extend_from_slice(&1u16.to_le_bytes());
        body.extend_from_slice(&2.5f64.to_bits().to_le_bytes());
        let crc = crc32(&body);
        body.extend_from_slice(&crc.to_le_bytes());
        let (mut r, v) = Reader::new(&body, 7, 1).unwrap();
        assert_eq!(v, 1);
        assert_eq!(r.f64().unwrap(), 2.5);
        r.end().unwrap();
    }
}
