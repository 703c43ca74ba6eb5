//! A detected step and the features step-length models use.

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
}

impl StepEvent {
    /// Step frequency, steps/s (`NaN` when the duration is unknown).
    pub fn frequency_hz(&self) -> f64 {
        1.0 / self.duration_s
    }
}
