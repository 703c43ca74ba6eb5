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
//! **IMU samples**, one layout family for every IMU engine: the 6-axis record and
//! the 9-axis record, which is the same 56 bytes followed by the magnetometer.
//!
//! | offset | field                                             | record        |
//! |-------:|---------------------------------------------------|---------------|
//! | 0      | `t_s`, seconds (monotonic clock)                  | 6- and 9-axis |
//! | 8      | `accel_x_mps2` (specific force, gravity included) | 6- and 9-axis |
//! | 16     | `accel_y_mps2`                                    | 6- and 9-axis |
//! | 24     | `accel_z_mps2`                                    | 6- and 9-axis |
//! | 32     | `gyro_x_rads`                                     | 6- and 9-axis |
//! | 40     | `gyro_y_rads`                                     | 6- and 9-axis |
//! | 48     | `gyro_z_rads`                                     | 6- and 9-axis |
//! | 56     | `mag_x_ut` (NaN: no magnetometer)                 | 9-axis only   |
//! | 64     | `mag_y_ut`                                        | 9-axis only   |
//! | 72     | `mag_z_ut`                                        | 9-axis only   |
//!
//! - 9-axis ([`IMU_RECORD_BYTES`] = 80 bytes, ten f64 LE): `PhoneNavigator`,
//!   `PhoneOdometry`, `OrientationFilter` (`pushImuPacked`), device axes as the
//!   platform reports them; a record with any magnetometer field NaN has no
//!   magnetometer.
//! - 6-axis ([`IMU6_RECORD_BYTES`] = 56 bytes, seven f64 LE): `FootNavigator`
//!   (`pushPacked`), sensor axes.
//!
//! Both are packed from the one `ImuSample` record: `packImuSamples` (80 bytes) and
//! `packFootSamples` (56 bytes, the magnetometer fields are not written).
//!
//! **Separate sensor events** ([`SENSOR_EVENT_RECORD_BYTES`] = 40 bytes per event):
//! what a phone delivers, one sensor per event, each with its own time; merged into
//! IMU samples by the SDK (`PhoneNavigator.pushSensorEventsPacked`, rule in
//! `stridekit_core::imu`).
//!
//! | offset | type   | field                                                        |
//! |-------:|--------|--------------------------------------------------------------|
//! | 0      | f64 LE | `t_s`, seconds (the same clock for every sensor)             |
//! | 8      | i64 LE | `sensor_type`: Android `Sensor.TYPE_*`: 1 accelerometer, 2 magnetometer, 4 gyroscope |
//! | 16     | f64 LE | `x` (m/s², µT or rad/s by type; device axes)                 |
//! | 24     | f64 LE | `y`                                                          |
//! | 32     | f64 LE | `z`                                                          |
//!
//! Every layout has a pack helper (`packFixes`, `packStepCounts`, `packAccelSamples`,
//! `packImuSamples`, `packFootSamples`) for code that has records; code that fills a
//! buffer itself (a sensor callback) writes the same: Kotlin
//! `ByteBuffer.allocate(n * 56).order(ByteOrder.LITTLE_ENDIAN)` and `putDouble` per
//! field (`Double.NaN` for a missing optional); Swift
//! `withUnsafeBytes(of: value.bitPattern.littleEndian)`.
//!
//! A buffer whose length is not a whole number of records is rejected as a whole
//! (the engine's `InvalidBuffer` error, e.g. [`PaceError::InvalidBuffer`]); otherwise
//! each record is checked and pushed like its record-list counterpart, and rejected
//! records are reported by index.

use crate::error::PaceError;
use stridekit_core::ahrs::ImuSample as CoreImuSample;
use stridekit_core::foot::FootSample;
use stridekit_core::imu::{ImuEvent as CoreImuEvent, SensorKind};
use stridekit_core::pace as core;

/// Bytes per packed step-count record.
pub const STEP_COUNT_RECORD_BYTES: usize = 16;
/// Bytes per packed GNSS fix record.
pub const FIX_RECORD_BYTES: usize = 56;
/// Bytes per packed accelerometer record.
pub const ACCEL_RECORD_BYTES: usize = 32;
/// Bytes per packed 6-axis IMU record (`FootNavigator`).
pub const IMU6_RECORD_BYTES: usize = 56;
/// Bytes per packed 9-axis IMU record (the phone engines): a 6-axis record, then
/// the magnetometer.
pub const IMU_RECORD_BYTES: usize = 80;
/// Bytes per packed sensor event (`PhoneNavigator.pushSensorEventsPacked`).
pub const SENSOR_EVENT_RECORD_BYTES: usize = 40;

/// `bytes` as records of `record` bytes, or why not (the engine wraps the reason in
/// its own `InvalidBuffer`).
fn whole_records<'a>(
    bytes: &'a [u8],
    record: usize,
    what: &str,
) -> Result<std::slice::ChunksExact<'a, u8>, String> {
    if bytes.len() % record == 0 {
        Ok(bytes.chunks_exact(record))
    } else {
        Err(format!(
            "{} bytes is not a whole number of {record}-byte {what} records",
            bytes.len()
        ))
    }
}

/// [`whole_records`] with the pace engine's error.
fn pace_records<'a>(
    bytes: &'a [u8],
    record: usize,
    what: &str,
) -> Result<std::slice::ChunksExact<'a, u8>, PaceError> {
    whole_records(bytes, record, what).map_err(|reason| PaceError::InvalidBuffer { reason })
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

fn put(out: &mut Vec<u8>, values: impl IntoIterator<Item = f64>) {
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
}

/// Decode packed accelerometer samples `(t_s, ax, ay, az)`.
pub fn accel(bytes: &[u8]) -> Result<impl Iterator<Item = (f64, [f64; 3])> + '_, PaceError> {
    Ok(pace_records(bytes, ACCEL_RECORD_BYTES, "accelerometer")?
        .map(|c| (f64_at(c, 0), [f64_at(c, 8), f64_at(c, 16), f64_at(c, 24)])))
}

/// Decode packed step counts (see the module docs for the layout).
/// A record with a negative count decodes to its (typed) rejection.
pub fn step_counts(
    bytes: &[u8],
) -> Result<impl Iterator<Item = Result<core::StepSample, core::PaceError>> + '_, PaceError> {
    Ok(
        pace_records(bytes, STEP_COUNT_RECORD_BYTES, "step-count")?.map(|c| {
            let mut s = [0u8; 8];
            s.copy_from_slice(&c[8..16]);
            Ok(core::StepSample::Count {
                t_s: f64_at(c, 0),
                steps: crate::pace::types::step_count(i64::from_le_bytes(s))?,
            })
        }),
    )
}

/// Decode packed GNSS fixes (see the module docs for the layout).
pub fn fixes(bytes: &[u8]) -> Result<impl Iterator<Item = core::GnssFix> + '_, PaceError> {
    Ok(
        pace_records(bytes, FIX_RECORD_BYTES, "GNSS fix")?.map(|c| core::GnssFix {
            t_s: f64_at(c, 0),
            lat_deg: f64_at(c, 8),
            lon_deg: f64_at(c, 16),
            alt_m: opt_f64_at(c, 24),
            horizontal_accuracy_m: opt_f64_at(c, 32),
            speed_mps: opt_f64_at(c, 40),
            speed_accuracy_mps: opt_f64_at(c, 48),
        }),
    )
}

/// Decode one 6-axis IMU record (also the first 56 bytes of a 9-axis one;
/// `ios/check-generated.py` reads the field order from this function).
fn imu6_record(c: &[u8]) -> FootSample {
    FootSample {
        t_s: f64_at(c, 0),
        accel_mps2: [f64_at(c, 8), f64_at(c, 16), f64_at(c, 24)],
        gyro_rads: [f64_at(c, 32), f64_at(c, 40), f64_at(c, 48)],
    }
}

/// Decode one 9-axis IMU record: the 6-axis record, then the magnetometer (`None`
/// when any of its fields is NaN).
fn imu_record(c: &[u8]) -> CoreImuSample {
    let FootSample {
        t_s,
        accel_mps2,
        gyro_rads,
    } = imu6_record(c);
    let mag = [f64_at(c, 56), f64_at(c, 64), f64_at(c, 72)];
    CoreImuSample {
        t_s,
        gyro_rads,
        accel_mps2,
        mag_ut: (!mag.iter().any(|v| v.is_nan())).then_some(mag),
    }
}

/// Decode packed 6-axis IMU records (`FootNavigator.pushPacked`), or why the buffer
/// is not a whole number of them.
pub fn imu6_samples(
    bytes: &[u8],
) -> Result<impl ExactSizeIterator<Item = FootSample> + '_, String> {
    Ok(whole_records(bytes, IMU6_RECORD_BYTES, "6-axis IMU")?.map(imu6_record))
}

/// Decode packed 9-axis IMU records (`pushImuPacked` of the phone engines), or why
/// the buffer is not a whole number of them.
pub fn imu_samples(
    bytes: &[u8],
) -> Result<impl ExactSizeIterator<Item = CoreImuSample> + '_, String> {
    Ok(whole_records(bytes, IMU_RECORD_BYTES, "IMU")?.map(imu_record))
}

/// Decode packed sensor events (`PhoneNavigator.pushSensorEventsPacked`): each an
/// event, or the sensor type it does not know; or why the buffer is not a whole
/// number of records.
pub fn sensor_events(
    bytes: &[u8],
) -> Result<impl ExactSizeIterator<Item = Result<CoreImuEvent, i64>> + '_, String> {
    Ok(
        whole_records(bytes, SENSOR_EVENT_RECORD_BYTES, "sensor event")?.map(|c| {
            let mut code = [0u8; 8];
            code.copy_from_slice(&c[8..16]);
            let code = i64::from_le_bytes(code);
            let kind = SensorKind::from_android(code).ok_or(code)?;
            Ok(CoreImuEvent {
                t_s: f64_at(c, 0),
                kind,
                values: [f64_at(c, 16), f64_at(c, 24), f64_at(c, 32)],
            })
        }),
    )
}

/// One sensor event as a phone delivers it (`packImuEvents` packs it for
/// `PhoneNavigator.pushSensorEventsPacked`; an app's sensor callback usually writes
/// the 40-byte records itself).
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct ImuEvent {
    /// Time, seconds on the app's monotonic clock (one clock for every sensor),
    /// strictly increasing within each sensor.
    pub t_s: f64,
    /// Android's `Sensor.TYPE_*`: 1 accelerometer (m/s²), 2 magnetometer (µT),
    /// 4 gyroscope (rad/s).
    pub sensor_type: i64,
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

/// Pack sensor events into the 40-byte little-endian layout of
/// `PhoneNavigator.pushSensorEventsPacked`: `t_s` (f64), `sensor_type` (i64), `x, y,
/// z` (f64).
#[uniffi::export]
pub fn pack_imu_events(events: Vec<ImuEvent>) -> Vec<u8> {
    let mut out = Vec::with_capacity(events.len() * SENSOR_EVENT_RECORD_BYTES);
    for e in events {
        out.extend_from_slice(&e.t_s.to_le_bytes());
        out.extend_from_slice(&e.sensor_type.to_le_bytes());
        put(&mut out, [e.x, e.y, e.z]);
    }
    out
}

/// The 6-axis record of a sample, in layout order (the pack side of [`imu6_record`]).
fn imu6_values(s: &FootSample) -> [f64; 7] {
    [
        s.t_s,
        s.accel_mps2[0],
        s.accel_mps2[1],
        s.accel_mps2[2],
        s.gyro_rads[0],
        s.gyro_rads[1],
        s.gyro_rads[2],
    ]
}

/// Core samples as 9-axis records (NaN magnetometer when absent).
pub(crate) fn pack_imu(samples: impl ExactSizeIterator<Item = CoreImuSample>) -> Vec<u8> {
    let mut out = Vec::with_capacity(samples.len() * IMU_RECORD_BYTES);
    for s in samples {
        let six = FootSample {
            t_s: s.t_s,
            accel_mps2: s.accel_mps2,
            gyro_rads: s.gyro_rads,
        };
        put(&mut out, imu6_values(&six));
        put(&mut out, s.mag_ut.unwrap_or([f64::NAN; 3]));
    }
    out
}

/// Core samples as 6-axis records.
pub(crate) fn pack_imu6(samples: impl ExactSizeIterator<Item = FootSample>) -> Vec<u8> {
    let mut out = Vec::with_capacity(samples.len() * IMU6_RECORD_BYTES);
    for s in samples {
        put(&mut out, imu6_values(&s));
    }
    out
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
        put(
            &mut out,
            [
                f.t_s,
                f.lat_deg,
                f.lon_deg,
                f.alt_m.unwrap_or(f64::NAN),
                f.horizontal_accuracy_m.unwrap_or(f64::NAN),
                f.speed_mps.unwrap_or(f64::NAN),
                f.speed_accuracy_mps.unwrap_or(f64::NAN),
            ],
        );
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
        put(&mut out, [s.t_s, s.x_mps2, s.y_mps2, s.z_mps2]);
    }
    out
}

/// One IMU sample, the record of every IMU engine: `packImuSamples` packs it for
/// `PhoneNavigator`, `PhoneOdometry` and `OrientationFilter` (device axes as the
/// platform reports them); `FootNavigator.push`, `pushWithStance` and `pushSamples`
/// take it directly and `packFootSamples` packs it for `FootNavigator.pushPacked`
/// (sensor axes). The foot navigator does not use the magnetometer fields.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct ImuSample {
    /// Time, seconds on the app's monotonic clock, strictly increasing.
    pub t_s: f64,
    /// Specific force, m/s² (gravity included: +9.8 along "up" at rest; iOS reports
    /// g: multiply by −9.80665).
    pub accel_x_mps2: f64,
    pub accel_y_mps2: f64,
    pub accel_z_mps2: f64,
    /// Angular rate, rad/s.
    pub gyro_x_rads: f64,
    pub gyro_y_rads: f64,
    pub gyro_z_rads: f64,
    /// Magnetic field, µT (null: no magnetometer; all three or none, a sample with
    /// only some of them counts as none). Not used by `FootNavigator`.
    #[uniffi(default = None)]
    pub mag_x_ut: Option<f64>,
    #[uniffi(default = None)]
    pub mag_y_ut: Option<f64>,
    #[uniffi(default = None)]
    pub mag_z_ut: Option<f64>,
}

/// The 6-axis part (what `FootNavigator` takes): the magnetometer is dropped.
impl From<ImuSample> for FootSample {
    fn from(s: ImuSample) -> Self {
        Self {
            t_s: s.t_s,
            accel_mps2: [s.accel_x_mps2, s.accel_y_mps2, s.accel_z_mps2],
            gyro_rads: [s.gyro_x_rads, s.gyro_y_rads, s.gyro_z_rads],
        }
    }
}

impl From<ImuSample> for CoreImuSample {
    fn from(s: ImuSample) -> Self {
        let FootSample {
            t_s,
            accel_mps2,
            gyro_rads,
        } = s.into();
        Self {
            t_s,
            gyro_rads,
            accel_mps2,
            mag_ut: match (s.mag_x_ut, s.mag_y_ut, s.mag_z_ut) {
                (Some(x), Some(y), Some(z)) => Some([x, y, z]),
                _ => None,
            },
        }
    }
}

/// Pack IMU samples into the 80-byte (9-axis) little-endian layout of
/// `pushImuPacked` (`PhoneNavigator`, `PhoneOdometry`, `OrientationFilter`): ten f64
/// `t_s, accel_x, accel_y, accel_z (m/s²), gyro_x, gyro_y, gyro_z (rad/s), mag_x,
/// mag_y, mag_z (µT, NaN when absent)`.
#[uniffi::export]
pub fn pack_imu_samples(samples: Vec<ImuSample>) -> Vec<u8> {
    pack_imu(samples.into_iter().map(Into::into))
}

/// Pack IMU samples into the 56-byte (6-axis) little-endian layout of
/// `FootNavigator.pushPacked`: seven f64 `t_s, accel_x, accel_y, accel_z (m/s²),
/// gyro_x, gyro_y, gyro_z (rad/s)`, the first 56 bytes of the 80-byte record (the
/// magnetometer fields are not written).
#[uniffi::export]
pub fn pack_foot_samples(samples: Vec<ImuSample>) -> Vec<u8> {
    pack_imu6(samples.into_iter().map(Into::into))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> ImuSample {
        ImuSample {
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
        }
    }

    fn values(bytes: &[u8]) -> Vec<f64> {
        bytes.chunks_exact(8).map(|c| f64_at(c, 0)).collect()
    }

    #[test]
    fn imu_pack_decodes_to_the_same_fields() {
        let s = sample();
        let no_mag = ImuSample {
            mag_x_ut: None,
            mag_y_ut: None,
            mag_z_ut: None,
            t_s: 2.0,
            ..s
        };
        let bytes = pack_imu_samples(vec![s, no_mag]);
        let mut recs = imu_samples(&bytes).unwrap();
        assert_eq!(recs.len(), 2);
        let r = recs.next().unwrap();
        assert_eq!(r.t_s, 1.5);
        assert_eq!(r.accel_mps2, [0.1, 0.2, 9.8]);
        assert_eq!(r.gyro_rads, [0.01, 0.02, 0.03]);
        assert_eq!(r.mag_ut, Some([20.0, 0.0, -40.0]));
        assert_eq!(r, CoreImuSample::from(s));
        let r = recs.next().unwrap();
        assert_eq!((r.t_s, r.mag_ut), (2.0, None));
        assert!(imu_samples(&bytes[..79]).is_err());
    }

    #[test]
    fn the_two_imu_records_are_one_family_accel_before_gyro() {
        let s = sample();
        let nine = pack_imu_samples(vec![s]);
        let six = pack_foot_samples(vec![s]);
        assert_eq!(
            (nine.len(), six.len()),
            (IMU_RECORD_BYTES, IMU6_RECORD_BYTES)
        );
        assert_eq!(
            values(&nine),
            [1.5, 0.1, 0.2, 9.8, 0.01, 0.02, 0.03, 20.0, 0.0, -40.0]
        );
        // The 6-axis record is the 9-axis record without the magnetometer.
        assert_eq!(six[..], nine[..IMU6_RECORD_BYTES]);
        let foot: Vec<_> = imu6_samples(&six).unwrap().collect();
        assert_eq!(foot, vec![FootSample::from(s)]);
        assert!(imu6_samples(&six[..55]).is_err());
        // A partial magnetometer is none.
        let partial = ImuSample {
            mag_y_ut: None,
            ..s
        };
        let r = imu_samples(&pack_imu_samples(vec![partial]))
            .unwrap()
            .next()
            .unwrap();
        assert_eq!(r.mag_ut, None);
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
