//! [`Ahrs`]: the one orientation engine every other engine builds on. It checks each
//! sample at the door ([`super::door`]), runs the filter the settings choose
//! ([`AhrsAlgorithm`]: the decoupled filter by default, or Madgwick's) and derives the
//! outputs; batches, snapshots and restores the same way for both.
//!
//! # Time
//! `dt` comes from the timestamps. The first sample initialises. A sample not later
//! than the previous one is rejected ([`AhrsError::TimeNotIncreasing`]; equal
//! timestamps too). A gap longer than `max_gap_s` (default 1 s) is not integrated: the
//! motion during it is unknown, so the filter re-initialises from that sample (flag
//! `reinitialised`), keeping the learned gyroscope bias.
//!
//! # Snapshot format
//! Version 4 (this build): the settings (algorithm included), the door (the input
//! layer's time state and g-units check), the latest acceleration and flags, then the
//! filter's state (4: the decoupled filter's heading variance, trusted dip, typical
//! interval and gyroscope plateau). One layout per build: snapshots of other versions are refused with
//! [`SnapshotError::UnsupportedVersion`].

use super::decoupled::{Decoupled, DecoupledSettings};
use super::door::{Admitted, Door};
use super::error::AhrsError;
use super::flags::AhrsFlags;
use super::frame::{AxisRemap, EarthFrame};
use super::madgwick::Madgwick;
use super::output::{AhrsOutput, AhrsRejection, ImuSample};
use super::quat::{self, Quat};
use super::settings::{AhrsAlgorithm, AhrsSettings};
use crate::batch::{self, Batch};
use crate::snapshot::{Reader, SnapshotError, Writer};

/// Snapshot engine kind byte for the AHRS.
const SNAPSHOT_KIND: u8 = 2;
/// Snapshot format version written by this build (7: the decoupled filter's clip-run
/// miss; 6: the decoupled filter's mean
/// heading correction rate; 5: its magnetometer offset estimate and its setting; 4: the decoupled filter's gap,
/// plateau, trusted-dip and heading-variance state; 3: the input layer's time state and g-units
/// check; 2: both filters; 1: Madgwick only).
const SNAPSHOT_VERSION: u16 = 7;

// Not boxed: the state is a few hundred bytes, created once, and an indirection
// would sit on every update.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
enum Filter {
    Decoupled(Decoupled),
    Madgwick(Madgwick),
}

/// Orientation filter (attitude and heading reference system). Create with
/// [`Ahrs::new`], feed [`Ahrs::push`] / [`Ahrs::push_batch`] (the engine contract) or
/// the Fusion-style [`Ahrs::update_imu`] / [`Ahrs::update_marg`] (or
/// [`Ahrs::update_batch`]), read [`Ahrs::estimate`].
#[derive(Clone, Debug, PartialEq)]
pub struct Ahrs {
    settings: AhrsSettings,
    /// The axis remap, unless it is the identity.
    remap: Option<AxisRemap>,
    door: Door,
    /// Latest accepted specific force, body frame, m/s².
    last_accel_mps2: [f64; 3],
    /// The filter; it also keeps the flags of the latest sample ([`Ahrs::flags`]).
    filter: Filter,
}

impl Ahrs {
    /// A filter with validated settings; it starts at the first sample.
    pub fn new(settings: AhrsSettings) -> Result<Self, AhrsError> {
        settings.validate()?;
        let filter = match settings.algorithm {
            AhrsAlgorithm::Decoupled => Filter::Decoupled(Decoupled::new(&settings)),
            AhrsAlgorithm::Madgwick => Filter::Madgwick(Madgwick::new(&settings)),
        };
        Ok(Self {
            settings,
            remap: (settings.axis_remap != AxisRemap::IDENTITY).then_some(settings.axis_remap),
            door: Door::default(),
            last_accel_mps2: [0.0; 3],
            filter,
        })
    }

    pub fn settings(&self) -> &AhrsSettings {
        &self.settings
    }

    /// Whether a sample was accepted yet.
    pub fn is_started(&self) -> bool {
        self.door.started()
    }

    /// Flags of the latest accepted sample (kept by the filter only: a second copy here
    /// cost a 12-byte copy per update).
    #[inline(always)]
    pub fn flags(&self) -> AhrsFlags {
        match &self.filter {
            Filter::Decoupled(f) => f.flags(),
            Filter::Madgwick(f) => madgwick_flags(f.flags()),
        }
    }

    /// Estimated gyroscope bias, rad/s, body frame.
    pub fn gyro_bias_rads(&self) -> [f64; 3] {
        match &self.filter {
            Filter::Decoupled(f) => f.gyro_bias_rads(),
            Filter::Madgwick(f) => f.gyro_bias_rads(),
        }
    }

    /// Decoupled filter: the magnetometer offset (hard iron) it estimates and removes,
    /// µT, body frame, and whether that is still being learned (flag
    /// `mag_calibrating`). `None` for the Madgwick filter or with
    /// `mag_offset_max_ut` = 0.
    pub fn mag_offset_ut(&self) -> Option<([f64; 3], bool)> {
        match &self.filter {
            Filter::Decoupled(f) => f.mag_offset_ut(),
            Filter::Madgwick(_) => None,
        }
    }

    /// Madgwick: current filter gain β, rad/s (above `settings.gain` while
    /// initialising). The decoupled filter has no gain: `None`.
    pub fn gain(&self) -> Option<f64> {
        match &self.filter {
            Filter::Decoupled(_) => None,
            Filter::Madgwick(f) => Some(f.gain()),
        }
    }

    /// Time of the latest accepted sample, s.
    pub fn last_t_s(&self) -> Option<f64> {
        self.door.time.last_t_s()
    }

    /// The filter's orientation in its own earth frame (both have +z up: NWU for
    /// Madgwick, ENU for the decoupled filter) and the rotation from that frame to the
    /// output frame.
    #[inline(always)]
    fn internal(&self) -> (Quat, Quat) {
        let frame = self.settings.frame;
        match &self.filter {
            Filter::Decoupled(f) => (f.q_enu(), frame.enu_to_frame()),
            Filter::Madgwick(f) => (f.q_nwu(), frame.nwu_to_frame()),
        }
    }

    /// Orientation body → earth in the configured frame, [w, x, y, z]. `None` before
    /// the first sample.
    pub fn quaternion(&self) -> Option<[f64; 4]> {
        self.door.started().then(|| {
            let (q, c) = self.internal();
            quat::normalised(quat::mul(&c, &q))
        })
    }

    /// IMU update: gyroscope (rad/s) and accelerometer (specific force, m/s²), sensor
    /// frame, at `t_s` (s). Returns the flags; read the full state with [`Ahrs::output`].
    #[inline]
    pub fn update_imu(
        &mut self,
        t_s: f64,
        gyro_rads: [f64; 3],
        accel_mps2: [f64; 3],
    ) -> Result<AhrsFlags, AhrsError> {
        self.update(t_s, gyro_rads, accel_mps2, None)
    }

    /// MARG update: as [`Ahrs::update_imu`] plus the magnetic field (µT, sensor frame).
    #[inline]
    pub fn update_marg(
        &mut self,
        t_s: f64,
        gyro_rads: [f64; 3],
        accel_mps2: [f64; 3],
        mag_ut: [f64; 3],
    ) -> Result<AhrsFlags, AhrsError> {
        self.update(t_s, gyro_rads, accel_mps2, Some(mag_ut))
    }

    /// One sample with an optional magnetometer reading. A rejected sample returns the
    /// error and leaves the filter exactly as it was.
    #[inline(always)]
    pub fn update(
        &mut self,
        t_s: f64,
        gyro_rads: [f64; 3],
        accel_mps2: [f64; 3],
        mag_ut: Option<[f64; 3]>,
    ) -> Result<AhrsFlags, AhrsError> {
        let s = self.door.check(
            self.remap.as_ref(),
            self.settings.max_gap_s,
            t_s,
            gyro_rads,
            accel_mps2,
            mag_ut,
        )?;
        // --- Accepted.
        self.door.commit(&s);
        self.last_accel_mps2 = s.accel;
        match &mut self.filter {
            Filter::Decoupled(f) => Ok(step_decoupled(f, &self.settings, &s)),
            Filter::Madgwick(f) => Ok(step_madgwick(f, &self.settings, &s)),
        }
    }

    /// Orientation and derived quantities after the latest accepted sample; `None`
    /// before the first.
    pub fn estimate(&self) -> Option<AhrsOutput> {
        self.door.started().then(|| self.make_output())
    }

    /// The same as [`estimate`](Self::estimate) (the Fusion-style name, kept next to
    /// the `update_*` methods).
    pub fn output(&self) -> Option<AhrsOutput> {
        self.estimate()
    }

    /// One sample (the engine contract's form of [`update`](Self::update)): the
    /// output after it, always `Some` once accepted.
    #[inline]
    pub fn push(&mut self, s: &ImuSample) -> Result<Option<AhrsOutput>, AhrsError> {
        self.update(s.t_s, s.gyro_rads, s.accel_mps2, s.mag_ut)?;
        Ok(Some(self.make_output()))
    }

    /// Feed many samples in order: one output per accepted sample; rejected samples
    /// leave the state untouched and the rest of the batch is still processed.
    pub fn push_batch(&mut self, samples: &[ImuSample]) -> Batch<AhrsOutput, AhrsError> {
        batch::run(samples, |s| self.push(s))
    }

    fn make_output(&self) -> AhrsOutput {
        let frame = self.settings.frame;
        let (qi, c) = self.internal();
        let q = quat::normalised(quat::mul(&c, &qi));
        let (roll_rad, pitch_rad, yaw_rad) = quat::to_euler(&q);
        let heading = match frame {
            EarthFrame::Enu => -yaw_rad,
            EarthFrame::Ned => yaw_rad,
        };
        let mut heading_rad = heading.rem_euclid(std::f64::consts::TAU) + 0.0;
        if heading_rad >= std::f64::consts::TAU {
            heading_rad = 0.0;
        }
        // Up in the body frame: third row of R(q) in the filter's own z-up frame.
        let [w, x, y, z] = quat::normalised(qi);
        let g = self.settings.gravity_mps2;
        let gravity_body_mps2 = [
            g * 2.0 * (x * z - w * y),
            g * 2.0 * (w * x + y * z),
            g * (1.0 - 2.0 * (x * x + y * y)),
        ];
        let a = &self.last_accel_mps2;
        let linear_accel_body_mps2 = [
            a[0] - gravity_body_mps2[0],
            a[1] - gravity_body_mps2[1],
            a[2] - gravity_body_mps2[2],
        ];
        let linear_accel_earth_mps2 = quat::rotate(&q, &linear_accel_body_mps2);
        AhrsOutput {
            t_s: self.door.last_t_s(),
            frame,
            quaternion: q,
            roll_rad,
            pitch_rad,
            yaw_rad,
            heading_rad,
            gravity_body_mps2,
            linear_accel_body_mps2,
            linear_accel_earth_mps2,
            gyro_bias_rads: self.gyro_bias_rads(),
            flags: self.flags(),
        }
    }

    /// As [`push_batch`](Self::push_batch) into containers of the caller's: one
    /// output per accepted sample goes to `out`, every rejected sample to `rejected`.
    /// Returns the number accepted. Allocates nothing itself (only `out` /
    /// `rejected` may grow: reserve capacity to avoid that).
    pub fn update_batch<O, R>(
        &mut self,
        samples: &[ImuSample],
        out: &mut O,
        rejected: &mut R,
    ) -> usize
    where
        O: Extend<AhrsOutput>,
        R: Extend<AhrsRejection>,
    {
        batch::each(
            samples,
            |o| out.extend(Some(o)),
            |r| rejected.extend(Some(r)),
            |s| self.push(s),
        )
    }

    /// The whole state as bytes (versioned, checksummed): restoring continues with
    /// bit-identical output.
    pub fn snapshot(&self) -> Vec<u8> {
        let mut w = Writer::new(SNAPSHOT_KIND, SNAPSHOT_VERSION);
        write_settings(&mut w, &self.settings);
        self.door.write(&mut w);
        w.f64s(&self.last_accel_mps2);
        let flags = self.flags().to_bits();
        w.u8(flags as u8);
        w.u8((flags >> 8) as u8);
        match &self.filter {
            Filter::Decoupled(f) => f.write_state(&mut w),
            Filter::Madgwick(f) => f.write_state(&mut w),
        }
        w.finish()
    }

    /// A filter continuing exactly where the snapshot was taken; a snapshot of another
    /// format version is [`SnapshotError::UnsupportedVersion`].
    pub fn restore(bytes: &[u8]) -> Result<Self, AhrsError> {
        let (mut r, _) = Reader::new(bytes, SNAPSHOT_KIND, SNAPSHOT_VERSION)?;
        let settings = read_settings(&mut r)?;
        let mut a = Ahrs::new(settings).map_err(|_| SnapshotError::Invalid("settings"))?;
        a.door = Door::read(&mut r)?;
        r.f64s(&mut a.last_accel_mps2)?;
        let lo = r.u8()? as u16;
        let hi = r.u8()? as u16;
        let bits = lo | hi << 8;
        if bits >> AhrsFlags::NAMES.len() != 0 {
            return Err(SnapshotError::Invalid("flags").into());
        }
        let flags = AhrsFlags::from_bits(bits);
        match &mut a.filter {
            Filter::Decoupled(f) => {
                f.read_state(&mut r)?;
                f.set_flags(flags);
            }
            Filter::Madgwick(f) => {
                f.read_state(&mut r, &settings)?;
                f.set_flags(flags);
            }
        }
        r.end()?;
        if crate::input::accel(&a.last_accel_mps2).is_err() {
            return Err(SnapshotError::Invalid("last acceleration").into());
        }
        Ok(a)
    }
}

/// One admitted sample through the decoupled filter; its flags. The flags are kept by
/// the filter only, packed, and returned as read back from there (unpacked in
/// registers): every copy of the struct built byte by byte was a wide load of narrow
/// stores, which stalls store-to-load forwarding.
#[inline(always)]
fn step_decoupled(f: &mut Decoupled, settings: &AhrsSettings, s: &Admitted) -> AhrsFlags {
    if s.restart {
        start_decoupled(f, settings, s);
    } else {
        f.step(s.dt, s.gyro, &s.accel, s.mag.as_ref());
    }
    f.flags()
}

/// A (re)start of the decoupled filter: rare (the first sample, a gap), so kept out of
/// line, away from the per-sample code.
#[cold]
#[inline(never)]
fn start_decoupled(f: &mut Decoupled, settings: &AhrsSettings, s: &Admitted) {
    f.start(settings, &s.gyro, &s.accel, s.mag.as_ref());
}

/// One admitted sample through the Madgwick filter; its flags.
#[inline(always)]
fn step_madgwick(f: &mut Madgwick, settings: &AhrsSettings, s: &Admitted) -> AhrsFlags {
    let flags = if s.restart {
        f.start(settings, &s.accel, s.a_norm, s.mag.as_ref())
    } else {
        f.step(
            settings,
            s.dt,
            s.gyro,
            &s.accel,
            s.a2,
            s.a_norm,
            s.mag.as_ref(),
        )
    };
    madgwick_flags(flags)
}

/// The flags of the Madgwick filter as the engine reports them: it has no rest
/// detector and no field check of its own, so `at_rest` is `bias_learning`, and
/// `mag_disturbed` and `heading_held` are `mag_rejected`.
#[inline(always)]
fn madgwick_flags(mut flags: AhrsFlags) -> AhrsFlags {
    flags.at_rest = flags.bias_learning;
    flags.mag_disturbed = flags.mag_rejected;
    flags.heading_held = flags.mag_rejected;
    flags
}

fn write_settings(w: &mut Writer, s: &AhrsSettings) {
    // Exhaustive on purpose: a new setting must be added to the snapshot.
    let AhrsSettings {
        frame,
        axis_remap,
        algorithm,
        decoupled,
        gain,
        initial_gain,
        initialisation_period_s,
        gyro_range_rads,
        accel_rejection_mps2,
        accel_rejection_rad,
        mag_rejection_ut,
        mag_rejection_dip_rad,
        recovery_trigger_period_s,
        bias_estimation,
        gravity_mps2,
        max_gap_s,
    } = s;
    w.u8(algorithm.to_u8());
    w.u8(frame.to_u8());
    axis_remap.write(w);
    w.f64s(&[
        *gain,
        *initial_gain,
        *initialisation_period_s,
        *gyro_range_rads,
        *accel_rejection_mps2,
        *accel_rejection_rad,
        *mag_rejection_ut,
        *mag_rejection_dip_rad,
        *recovery_trigger_period_s,
        *gravity_mps2,
        *max_gap_s,
    ]);
    w.bool(*bias_estimation);
    w.f64s(&decoupled.to_array());
}

/// Frame, remap and the eleven numbers of the Madgwick settings.
fn read_common_settings(
    r: &mut Reader,
    algorithm: AhrsAlgorithm,
) -> Result<AhrsSettings, AhrsError> {
    let frame = EarthFrame::from_u8(r.u8()?).ok_or(SnapshotError::Invalid("frame"))?;
    let axis_remap = AxisRemap::read(r)?;
    // +∞ switches a feature off: the settings' own validation (run by `Ahrs::new`)
    // decides what each value may be.
    let mut v = [0.0; 11];
    r.f64s_any(&mut v)?;
    Ok(AhrsSettings {
        frame,
        axis_remap,
        algorithm,
        decoupled: DecoupledSettings::default(),
        gain: v[0],
        initial_gain: v[1],
        initialisation_period_s: v[2],
        gyro_range_rads: v[3],
        accel_rejection_mps2: v[4],
        accel_rejection_rad: v[5],
        mag_rejection_ut: v[6],
        mag_rejection_dip_rad: v[7],
        recovery_trigger_period_s: v[8],
        gravity_mps2: v[9],
        max_gap_s: v[10],
        bias_estimation: r.bool()?,
    })
}

fn read_settings(r: &mut Reader) -> Result<AhrsSettings, AhrsError> {
    let algorithm = AhrsAlgorithm::from_u8(r.u8()?).ok_or(SnapshotError::Invalid("algorithm"))?;
    let mut s = read_common_settings(r, algorithm)?;
    let mut d = [0.0; 16];
    r.f64s_any(&mut d)?;
    s.decoupled = DecoupledSettings::from_array(d);
    Ok(s)
}
