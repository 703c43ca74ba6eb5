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
//! | 8      | i64 LE  | `steps`, cumulative count (≥ 0)        |
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
//! **Phone IMU samples** (80 bytes per sample, ten f64 LE; `PhoneNavigator`,
//! `PhoneOdometry`, `OrientationFilter`): `t_s`, `gyro_x/y/z` (rad/s),
//! `accel_x/y/z` (m/s², gravity included), `mag_x/y/z` (µT; NaN when there is no
//! magnetometer), device axes as the platform reports them.
//!
//! **Foot IMU samples** (56 bytes, seven f64 LE; `FootNavigator`): `t_s`,
//! `accel_x/y/z` (m/s²), `gyro_x/y/z` (rad/s), sensor axes.
//!
//! Every layout has a pack helper (`packFixes`, `packStepCounts`, `packAccelSamples`,
//! `packImuSamples`, `packFootSamples`) for code that has records; code that fills a
//! buffer itself (a sensor callback) writes the same: Kotlin
//! `ByteBuffer.allocate(n * 56).order(ByteOrder.LITTLE_ENDIAN)` and `putDouble` per
//! field (`Double.NaN` for a missing optional); Swift
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
/// A record with a negative count decodes to its (typed) rejection.
pub fn step_counts(
    bytes: &[u8],
) -> Result<impl Iterator<Item = Result<core::StepSample, core::PaceError>> + '_, PaceError> {
    check_len(bytes, STEP_COUNT_RECORD_BYTES, "step-count")?;
    Ok(bytes.chunks_exact(STEP_COUNT_RECORD_BYTES).map(|c| {
        let mut s = [0u8; 8];
        s.copy_from_slice(&c[8..16]);
        Ok(core::StepSample::Count {
            t_s: f64_at(c, 0),
            steps: crate::pace::types::step_count(i64::from_le_bytes(s))?,
        })
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

/// Pack step counts into the 16-byte little-endian layout of
/// `PaceTracker.pushStepCountsPacked`: `t_s` (f64), `steps` (i64). Other step shapes
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

/// Pack GNSS fixes into the 56-byte little-endian layout of
/// `PaceTracker.pushFixesPacked`: seven f64 `t_s, lat_deg, lon_deg, alt_m,
/// horizontal_accuracy_m, speed_mps, speed_accuracy_mps` (null optionals become NaN).
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

/// Pack accelerometer samples into the 32-byte little-endian layout of
/// `PaceTracker.pushAccelPacked` and `PlacementClassifier.pushAccelPacked`: four f64
/// `t_s, x_mps2, y_mps2, z_mps2`.
#[uniffi::export]
pub fn pack_accel_samples(samples: Vec<crate::AccelSample>) -> Vec<u8> {
    let mut out = Vec::with_capacity(samples.len() * ACCEL_RECORD_BYTES);
    for s in samples {
        for v in [s.t_s, s.x_mps2, s.y_mps2, s.z_mps2] {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out
}

/// One phone IMU sample: what `packImuSamples` packs for `PhoneNavigator`,
/// `PhoneOdometry` and `OrientationFilter`. Device axes as the platform reports them.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct PhoneImuSample {
    /// Time, seconds on the app's monotonic clock, strictly increasing.
    pub t_s: f64,
    /// Specific force, m/s² (gravity included; iOS reports g: multiply by −9.80665).
    pub accel_x_mps2: f64,
    pub accel_y_mps2: f64,
    pub accel_z_mps2: f64,
    /// Angular rate, rad/s.
    pub gyro_x_rads: f64,
    pub gyro_y_rads: f64,
    pub gyro_z_rads: f64,
    /// Magnetic field, µT (null: no magnetometer; all three or none).
    #[uniffi(default = None)]
    pub mag_x_ut: Option<f64>,
    #[uniffi(default = None)]
    pub mag_y_ut: Option<f64>,
    #[uniffi(default = None)]
    pub mag_z_ut: Option<f64>,
}

/// Pack phone IMU samples into the 80-byte little-endian layout of
/// `pushImuPacked`: ten f64 `t_s, gyro_x, gyro_y, gyro_z (rad/s), accel_x, accel_y,
/// accel_z (m/s²), mag_x, mag_y, mag_z (µT, NaN when absent)`. Note the order: gyro
/// before accel (the foot layout has accel first).
#[uniffi::export]
pub fn pack_imu_samples(samples: Vec<PhoneImuSample>) -> Vec<u8> {
    let mut out = Vec::with_capacity(samples.len() * crate::phone::navigator::IMU_RECORD_BYTES);
    for s in samples {
        let nan = f64::NAN;
        for v in [
            s.t_s,
            s.gyro_x_rads,
            s.gyro_y_rads,
            s.gyro_z_rads,
            s.accel_x_mps2,
            s.accel_y_mps2,
            s.accel_z_mps2,
            s.mag_x_ut.unwrap_or(nan),
            s.mag_y_ut.unwrap_or(nan),
            s.mag_z_ut.unwrap_or(nan),
        ] {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn imu_pack_decodes_to_the_same_fields() {
        let s = PhoneImuSample {
            t_s: 1.5,
            accel_x_mps2: 0.1,
            accel_y_mps2: 0.2,
            accel_z_mps2: 9.8,
            gyro_x_rads: 0.01,
            gyro_y_rads: 0.02,
            gyro_z_rads: 0.03,
            mag_x_ut: Some(20.0),
            mag_y_ut: Some(0.0),
            mag_z_ut: Some(-40.0),
        };
        let no_mag = PhoneImuSample {
            mag_x_ut: None,
            mag_y_ut: None,
            mag_z_ut: None,
            t_s: 2.0,
            ..s
        };
        let bytes = pack_imu_samples(vec![s, no_mag]);
        let mut recs = crate::phone::navigator::imu_records(&bytes).unwrap();
        let r = crate::phone::navigator::imu_record(recs.next().unwrap());
        assert_eq!(r.t_s, 1.5);
        assert_eq!(r.accel_mps2, [0.1, 0.2, 9.8]);
        assert_eq!(r.gyro_rads, [0.01, 0.02, 0.03]);
        assert_eq!(r.mag_ut, Some([20.0, 0.0, -40.0]));
        let r = crate::phone::navigator::imu_record(recs.next().unwrap());
        assert_eq!((r.t_s, r.mag_ut), (2.0, None));
    }

    #[test]
    fn accel_pack_decodes_to_the_same_fields() {
        let a = crate::AccelSample {
            t_s: 3.0,
            x_mps2: 1.0,
            y_mps2: -2.0,
            z_mps2: 9.0,
        };
        let bytes = pack_accel_samples(vec![a]);
        let got: Vec<_> = accel(&bytes).unwrap().collect();
        assert_eq!(got, vec![(3.0, [1.0, -2.0, 9.0])]);
    }
}
