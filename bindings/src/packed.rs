//! Packed little-endian sample buffers: the fast path beside the record-list API.
//!
//! A `List<GnssFix>` crossing the FFI is serialised field by field by generated code;
//! a packed buffer is one `ByteArray` copy. Both give the same estimates.
//!
//! **Step counts** ([`STEP_COUNT_RECORD_BYTES`] = 16 bytes per sample):
//!
//! | offset | type    | field                                  |
//! |-------:|---------|----------------------------------------|
//! | 0      | f64 LE  | `t_s`, seconds (monotonic clock)       |
//! | 8      | u64 LE  | `steps`, cumulative count              |
//!
//! **GNSS fixes** ([`FIX_RECORD_BYTES`] = 56 bytes per fix, seven f64 LE):
//!
//! | offset | field                   | absent (null) encoded as |
//! |-------:|-------------------------|--------------------------|
//! | 0      | `t_s`                   | —                        |
//! | 8      | `lat_deg`               | —                        |
//! | 16     | `lon_deg`               | —                        |
//! | 24     | `alt_m`                 | NaN                      |
//! | 32     | `horizontal_accuracy_m` | NaN                      |
//! | 40     | `speed_mps`             | NaN                      |
//! | 48     | `speed_accuracy_mps`    | NaN                      |
//!
//! **Accelerometer samples** ([`ACCEL_RECORD_BYTES`] = 32 bytes per sample, four
//! f64 LE): `t_s`, `ax`, `ay`, `az` (m/s², gravity included, any axes).
//!
//! Kotlin: `ByteBuffer.allocate(n * 56).order(ByteOrder.LITTLE_ENDIAN)` and
//! `putDouble` seven times per fix (`Double.NaN` for a missing optional); Swift:
//! `withUnsafeBytes(of: value.bitPattern.littleEndian)`.
//!
//! A buffer whose length is not a whole number of records is rejected as a whole
//! ([`PaceError::InvalidBuffer`]); otherwise each record is checked and pushed like
//! its record-list counterpart, and rejected records are reported by index.

use crate::error::PaceError;
use stridekit_core::pace as core;

/// Bytes per packed step-count record.
pub const STEP_COUNT_RECORD_BYTES: usize = 16;
/// Bytes per packed GNSS fix record.
pub const FIX_RECORD_BYTES: usize = 56;
/// Bytes per packed accelerometer record.
pub const ACCEL_RECORD_BYTES: usize = 32;

/// Decode packed accelerometer samples `(t_s, ax, ay, az)`.
pub fn accel(bytes: &[u8]) -> Result<impl Iterator<Item = (f64, [f64; 3])> + '_, PaceError> {
    check_len(bytes, ACCEL_RECORD_BYTES, "accelerometer")?;
    Ok(bytes
        .chunks_exact(ACCEL_RECORD_BYTES)
        .map(|c| (f64_at(c, 0), [f64_at(c, 8), f64_at(c, 16), f64_at(c, 24)])))
}

fn check_len(bytes: &[u8], record: usize, what: &str) -> Result<(), PaceError> {
    if bytes.len() % record == 0 {
        Ok(())
    } else {
        Err(PaceError::InvalidBuffer {
            reason: format!(
                "{} bytes is not a whole number of {record}-byte {what} records",
                bytes.len()
            ),
        })
    }
}

fn f64_at(chunk: &[u8], offset: usize) -> f64 {
    let mut b = [0u8; 8];
    b.copy_from_slice(&chunk[offset..offset + 8]);
    f64::from_le_bytes(b)
}

fn opt_f64_at(chunk: &[u8], offset: usize) -> Option<f64> {
    let v = f64_at(chunk, offset);
    (!v.is_nan()).then_some(v)
}

/// Decode packed step counts (see the module docs for the layout).
pub fn step_counts(bytes: &[u8]) -> Result<impl Iterator<Item = core::StepSample> + '_, PaceError> {
    check_len(bytes, STEP_COUNT_RECORD_BYTES, "step-count")?;
    Ok(bytes.chunks_exact(STEP_COUNT_RECORD_BYTES).map(|c| {
        let mut s = [0u8; 8];
        s.copy_from_slice(&c[8..16]);
        core::StepSample::Count {
            t_s: f64_at(c, 0),
            steps: u64::from_le_bytes(s),
        }
    }))
}

/// Decode packed GNSS fixes (see the module docs for the layout).
pub fn fixes(bytes: &[u8]) -> Result<impl Iterator<Item = core::GnssFix> + '_, PaceError> {
    check_len(bytes, FIX_RECORD_BYTES, "GNSS fix")?;
    Ok(bytes.chunks_exact(FIX_RECORD_BYTES).map(|c| core::GnssFix {
        t_s: f64_at(c, 0),
        lat_deg: f64_at(c, 8),
        lon_deg: f64_at(c, 16),
        alt_m: opt_f64_at(c, 24),
        horizontal_accuracy_m: opt_f64_at(c, 32),
        speed_mps: opt_f64_at(c, 40),
        speed_accuracy_mps: opt_f64_at(c, 48),
    }))
}

/// Pack step counts `(t_s, steps)` into the 16-byte layout. Other step shapes
/// (events, cadence) have no packed form and are skipped.
#[uniffi::export]
pub fn pack_step_counts(samples: Vec<crate::StepSample>) -> Vec<u8> {
    let mut out = Vec::with_capacity(samples.len() * STEP_COUNT_RECORD_BYTES);
    for s in samples {
        if let crate::StepSample::Count { t_s, steps } = s {
            out.extend_from_slice(&t_s.to_le_bytes());
            out.extend_from_slice(&steps.to_le_bytes());
        }
    }
    out
}

/// Pack GNSS fixes into the 56-byte layout (null optionals become NaN).
#[uniffi::export]
pub fn pack_fixes(fixes: Vec<crate::GnssFix>) -> Vec<u8> {
    let mut out = Vec::with_capacity(fixes.len() * FIX_RECORD_BYTES);
    for f in fixes {
        for v in [
            f.t_s,
            f.lat_deg,
            f.lon_deg,
            f.alt_m.unwrap_or(f64::NAN),
            f.horizontal_accuracy_m.unwrap_or(f64::NAN),
            f.speed_mps.unwrap_or(f64::NAN),
            f.speed_accuracy_mps.unwrap_or(f64::NAN),
        ] {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out
}
