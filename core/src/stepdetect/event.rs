//! A detected step and the features step-length models use.

use crate::snapshot::{Reader, SnapshotError, Writer};

/// One detected step. Features are computed over the step (from the previous step
/// to this one) on the acceleration magnitude, gravity included, m/s².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepEvent {
    /// Time of the step (the detector's heel-strike estimate), seconds.
    pub t_s: f64,
    /// Time since the previous step, seconds (`NaN` for the first step of a bout);
    /// step frequency F = 1 / duration_s.
    pub duration_s: f64,
    /// Variance of the acceleration magnitude over the step, (m/s²)² ("SV").
    pub accel_variance_m2ps4: f64,
    /// Largest acceleration magnitude over the step, m/s².
    pub accel_max_mps2: f64,
    /// Smallest acceleration magnitude over the step, m/s².
    pub accel_min_mps2: f64,
    /// Peak-to-peak vertical displacement of the device over the step, metres, for
    /// the inverted-pendulum step length (`StepLengthModel::Pendulum`). `NaN` when
    /// unknown: the detector alone does not know the attitude, so its events carry
    /// `NaN` and the phone navigator fills it in from its own attitude; an app with an
    /// attitude of its own may fill it in (see [`crate::pdr::VerticalHistory`]).
    pub vertical_displacement_m: f64,
    /// Whether the step was seen in the signal or credited without being seen (a
    /// filled step: its time is spaced evenly at the walk's cadence and its features
    /// are those of the detected step after it).
    pub origin: StepOrigin,
}

/// Where a step event comes from. The robust detector credits steps it did not see
/// where the walk evidently went on; a count may rest on them, and an app may tell
/// them apart (`StepEvent::origin`). The published detector emits only `Detected`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum StepOrigin {
    /// A heel strike seen in the acceleration.
    #[default]
    Detected,
    /// Filled at the walk's cadence into an interval across dropped samples (a gap in
    /// the input's timestamps that hid the step).
    FilledAcrossGap,
    /// Filled at the walk's cadence into an interval of about two steps inside a bout
    /// with no data gap: a step too weak to be seen.
    FilledMissed,
    /// Filled at the walk's cadence between two bouts of one walk (the first lost its
    /// periodicity, not by silence, and the next came within 10 s at the same cadence:
    /// a turn, a message read on the way).
    FilledBetweenBouts,
}

impl StepOrigin {
    /// Whether the step was credited without being seen.
    pub fn is_filled(self) -> bool {
        self != StepOrigin::Detected
    }

    /// Snapshot code (stable: stored in detector snapshots).
    fn code(self) -> u8 {
        match self {
            StepOrigin::Detected => 0,
            StepOrigin::FilledAcrossGap => 1,
            StepOrigin::FilledMissed => 2,
            StepOrigin::FilledBetweenBouts => 3,
        }
    }

    /// The origin of a snapshot code (`None`: not a code).
    fn from_code(code: u8) -> Option<Self> {
        Some(match code {
            0 => StepOrigin::Detected,
            1 => StepOrigin::FilledAcrossGap,
            2 => StepOrigin::FilledMissed,
            3 => StepOrigin::FilledBetweenBouts,
            _ => return None,
        })
    }

    /// Write the origin into a snapshot (one byte, [`Self::code`]).
    pub(crate) fn write(self, w: &mut Writer) {
        w.u8(self.code());
    }

    /// Read an origin written by [`Self::write`]; an unknown code is refused.
    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        Self::from_code(r.u8()?).ok_or(SnapshotError::Invalid("step origin"))
    }
}

impl StepEvent {
    /// Step frequency, steps/s (`NaN` when the duration is unknown).
    pub fn frequency_hz(&self) -> f64 {
        1.0 / self.duration_s
    }
}
