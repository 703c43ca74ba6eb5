//! Settings of the AHRS, with named defaults (the structure of x-io's Fusion
//! `FusionAhrsSettings`, in SI units and seconds instead of sample counts): which
//! filter runs ([`AhrsAlgorithm`]), the settings both share, Madgwick's, and the
//! decoupled filter's ([`DecoupledSettings`]).

use super::decoupled::DecoupledSettings;
use super::error::AhrsError;
use super::frame::{AxisRemap, EarthFrame};

/// Which orientation filter an [`Ahrs`](super::Ahrs) runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum AhrsAlgorithm {
    /// The default: inclination from the accelerometer averaged in an
    /// almost-inertial frame, heading from the magnetometer on its own, gyroscope
    /// bias learned at rest and in motion, magnetic disturbance rejection
    /// (`super::decoupled`; settings in [`AhrsSettings::decoupled`]).
    #[default]
    Decoupled,
    /// Madgwick's gradient-descent filter with Fusion-style initialisation, rejection
    /// and recovery (`super::madgwick`); the default before the decoupled filter.
    Madgwick,
}

impl AhrsAlgorithm {
    pub(crate) fn to_u8(self) -> u8 {
        match self {
            AhrsAlgorithm::Decoupled => 0,
            AhrsAlgorithm::Madgwick => 1,
        }
    }
    pub(crate) fn from_u8(v: u8) -> Option<Self> {
        match v {
            0 => Some(AhrsAlgorithm::Decoupled),
            1 => Some(AhrsAlgorithm::Madgwick),
            _ => None,
        }
    }
}

/// Standard gravity, m/s².
pub const STANDARD_GRAVITY_MPS2: f64 = 9.80665;

/// Default filter gain β, rad/s (Madgwick's β: rate at which the correction turns
/// the estimate towards the measured gravity / field, expressed as a quaternion
/// derivative; √(3/4) × the expected gyro error. 0.1 is the `ahrs` crate's default).
pub const DEFAULT_GAIN: f64 = 0.1;
/// Default gain at the start of the initialisation phase.
pub const DEFAULT_INITIAL_GAIN: f64 = 1.0;
/// Default length of the initialisation phase, s (Fusion: 3 s).
pub const DEFAULT_INITIALISATION_PERIOD_S: f64 = 3.0;
/// Default gyroscope range, rad/s (2000 °/s, the usual range of phone gyroscopes).
pub const DEFAULT_GYRO_RANGE_RADS: f64 = 2000.0 * std::f64::consts::PI / 180.0;
/// Default acceleration rejection: deviation of |a| from gravity, m/s².
///
/// The two acceleration thresholds are set so that a walking gait held in the hand
/// (±2.5 m/s² vertical, ±1.2 m/s² forward) is *not* rejected. A gait is periodic with
/// zero mean, so plain averaging (the gradient step) removes it; rejecting part of
/// every stride keeps only samples of particular gait phases, which are biased, and
/// lowers the effective gain against gyro bias. Measured on the synthetic walk of
/// `tests/ahrs.rs` with a 0.002 rad/s gyro bias: 1.1° rms tilt error with these
/// defaults, 3.7° with Fusion's example settings (10°) plus a 2 m/s² magnitude gate.
/// Bursts (a push, a car braking) still exceed 15° and are rejected.
pub const DEFAULT_ACCEL_REJECTION_MPS2: f64 = 3.0;
/// Default acceleration rejection: angle between measured and estimated gravity, rad (15°).
pub const DEFAULT_ACCEL_REJECTION_RAD: f64 = 15.0 * std::f64::consts::PI / 180.0;
/// Default magnetic rejection: deviation of |m| from the learned field, µT.
pub const DEFAULT_MAG_REJECTION_UT: f64 = 10.0;
/// Default magnetic rejection: deviation of the dip angle from the learned one, rad (10°).
pub const DEFAULT_MAG_REJECTION_DIP_RAD: f64 = 10.0 * std::f64::consts::PI / 180.0;
/// Default recovery trigger period, s (Fusion's examples: 5 s).
pub const DEFAULT_RECOVERY_TRIGGER_PERIOD_S: f64 = 5.0;
/// Default longest sample interval that is integrated, s.
pub const DEFAULT_MAX_GAP_S: f64 = 1.0;
/// Upper bound of `max_gap_s`, s.
pub const MAX_GAP_LIMIT_S: f64 = 10.0;

/// Settings of [`Ahrs`](super::Ahrs). Every threshold may be `f64::INFINITY` to
/// switch its feature off. `frame`, `axis_remap`, `gyro_range_rads`,
/// `bias_estimation`, `gravity_mps2` and `max_gap_s` apply to both filters; the
/// fields from `gain` to `recovery_trigger_period_s` to Madgwick's only; `decoupled`
/// to the decoupled filter only.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AhrsSettings {
    /// Earth frame of the outputs.
    pub frame: EarthFrame,
    /// Sensor → body axis remap applied to every input vector.
    pub axis_remap: AxisRemap,
    /// The filter (default: [`AhrsAlgorithm::Decoupled`]).
    pub algorithm: AhrsAlgorithm,
    /// Settings of the decoupled filter.
    pub decoupled: DecoupledSettings,
    /// Madgwick: filter gain β after initialisation, rad/s. 0 = gyroscope only.
    pub gain: f64,
    /// Gain at the start of the initialisation phase; it ramps linearly down to `gain`
    /// over `initialisation_period_s`. Ignored when not above `gain`.
    pub initial_gain: f64,
    /// Length of the initialisation phase, s; 0 switches it off. While initialising,
    /// no measurement is rejected.
    pub initialisation_period_s: f64,
    /// Full-scale range of the gyroscope, rad/s. A reading beyond 98 % of it is
    /// clipped, so the integrated orientation is wrong: the filter restarts its
    /// initialisation phase from the current orientation ("angular rate recovery").
    pub gyro_range_rads: f64,
    /// Skip the accelerometer correction while ||a| − g| exceeds this, m/s².
    pub accel_rejection_mps2: f64,
    /// ... or while measured and estimated gravity differ by more than this angle, rad.
    pub accel_rejection_rad: f64,
    /// Skip the magnetometer correction while |m| differs from the learned field
    /// magnitude by more than this, µT.
    pub mag_rejection_ut: f64,
    /// ... or while the dip angle differs from the learned one by more than this, rad.
    pub mag_rejection_dip_rad: f64,
    /// A sensor rejected for this long (net of accepted samples, which count 9× back)
    /// is trusted again: the estimate, not the sensor, is taken to be wrong. Seconds.
    pub recovery_trigger_period_s: f64,
    /// Learn the gyroscope bias (Madgwick: while still; decoupled: at rest and in
    /// motion).
    pub bias_estimation: bool,
    /// Local gravity, m/s².
    pub gravity_mps2: f64,
    /// A sample interval longer than this is not integrated: the filter re-initialises
    /// its orientation from that sample (the motion during the gap is unknown), s.
    pub max_gap_s: f64,
}

impl Default for AhrsSettings {
    fn default() -> Self {
        Self {
            frame: EarthFrame::Enu,
            axis_remap: AxisRemap::IDENTITY,
            algorithm: AhrsAlgorithm::Decoupled,
            decoupled: DecoupledSettings::default(),
            gain: DEFAULT_GAIN,
            initial_gain: DEFAULT_INITIAL_GAIN,
            initialisation_period_s: DEFAULT_INITIALISATION_PERIOD_S,
            gyro_range_rads: DEFAULT_GYRO_RANGE_RADS,
            accel_rejection_mps2: DEFAULT_ACCEL_REJECTION_MPS2,
            accel_rejection_rad: DEFAULT_ACCEL_REJECTION_RAD,
            mag_rejection_ut: DEFAULT_MAG_REJECTION_UT,
            mag_rejection_dip_rad: DEFAULT_MAG_REJECTION_DIP_RAD,
            recovery_trigger_period_s: DEFAULT_RECOVERY_TRIGGER_PERIOD_S,
            bias_estimation: true,
            gravity_mps2: STANDARD_GRAVITY_MPS2,
            max_gap_s: DEFAULT_MAX_GAP_S,
        }
    }
}

impl AhrsSettings {
    /// Madgwick's filter with its defaults (Fusion-style initialisation, rejection,
    /// recovery and bias at rest): the default AHRS before the decoupled filter.
    pub fn madgwick() -> Self {
        Self {
            algorithm: AhrsAlgorithm::Madgwick,
            ..Self::default()
        }
    }

    /// Plain Madgwick: gain `gain`, no initialisation phase, no rejection, no bias
    /// estimation, no gyroscope range (the filter of the paper, as in the `ahrs` crate).
    pub fn plain(gain: f64) -> Self {
        Self {
            algorithm: AhrsAlgorithm::Madgwick,
            gain,
            initial_gain: gain,
            initialisation_period_s: 0.0,
            gyro_range_rads: f64::INFINITY,
            accel_rejection_mps2: f64::INFINITY,
            accel_rejection_rad: f64::INFINITY,
            mag_rejection_ut: f64::INFINITY,
            mag_rejection_dip_rad: f64::INFINITY,
            bias_estimation: false,
            ..Self::default()
        }
    }

    /// The same settings in another earth frame.
    pub fn with_frame(self, frame: EarthFrame) -> Self {
        Self { frame, ..self }
    }

    /// Checks every value; `Ahrs::new` calls it.
    pub fn validate(&self) -> Result<(), AhrsError> {
        fn bad(field: &'static str, reason: &'static str) -> AhrsError {
            AhrsError::InvalidSettings { field, reason }
        }
        if !(self.gain.is_finite() && (0.0..=100.0).contains(&self.gain)) {
            return Err(bad("gain", "must be in 0..=100 rad/s"));
        }
        if !(self.initial_gain.is_finite() && (0.0..=100.0).contains(&self.initial_gain)) {
            return Err(bad("initial_gain", "must be in 0..=100 rad/s"));
        }
        if !(self.initialisation_period_s.is_finite()
            && (0.0..=60.0).contains(&self.initialisation_period_s))
        {
            return Err(bad("initialisation_period_s", "must be in 0..=60 s"));
        }
        for (field, v) in [
            ("gyro_range_rads", self.gyro_range_rads),
            ("accel_rejection_mps2", self.accel_rejection_mps2),
            ("accel_rejection_rad", self.accel_rejection_rad),
            ("mag_rejection_ut", self.mag_rejection_ut),
            ("mag_rejection_dip_rad", self.mag_rejection_dip_rad),
            ("recovery_trigger_period_s", self.recovery_trigger_period_s),
        ] {
            // NaN fails the comparison; +∞ switches the feature off.
            if v.is_nan() || v <= 0.0 {
                return Err(bad(field, "must be positive (or +∞ to switch it off)"));
            }
        }
        if !(self.gravity_mps2.is_finite() && (9.7..=9.9).contains(&self.gravity_mps2)) {
            return Err(bad("gravity_mps2", "must be in 9.7..=9.9 m/s²"));
        }
        if !(self.max_gap_s.is_finite()
            && self.max_gap_s > 0.0
            && self.max_gap_s <= MAX_GAP_LIMIT_S)
        {
            return Err(bad("max_gap_s", "must be in (0, 10] s"));
        }
        self.decoupled.validate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_checks_bite() {
        AhrsSettings::default().validate().unwrap();
        AhrsSettings::plain(0.05).validate().unwrap();
        let s = AhrsSettings {
            gain: f64::NAN,
            ..AhrsSettings::default()
        };
        assert!(matches!(
            s.validate(),
            Err(AhrsError::InvalidSettings { field: "gain", .. })
        ));
        let s = AhrsSettings {
            recovery_trigger_period_s: 0.0,
            ..AhrsSettings::default()
        };
        assert!(s.validate().is_err());
        let s = AhrsSettings {
            gravity_mps2: 1.0,
            ..AhrsSettings::default()
        };
        assert!(s.validate().is_err());
        let mut s = AhrsSettings::default();
        s.decoupled.accel_time_constant_s = 0.0;
        assert!(matches!(
            s.validate(),
            Err(AhrsError::InvalidSettings {
                field: "accel_time_constant_s",
                ..
            })
        ));
        let mut s = AhrsSettings::default();
        s.decoupled.mag_norm_threshold = f64::NAN;
        assert!(s.validate().is_err());
        for a in [AhrsAlgorithm::Decoupled, AhrsAlgorithm::Madgwick] {
            assert_eq!(AhrsAlgorithm::from_u8(a.to_u8()), Some(a));
        }
        assert_eq!(AhrsAlgorithm::from_u8(9), None);
        assert_eq!(AhrsSettings::madgwick().algorithm, AhrsAlgorithm::Madgwick);
    }
}
