//! What the filter did with the latest sample and why (Fusion's "flags" and
//! "internal states"): so an app can tell a trusted orientation from a coasting one.

/// State of the filter after a sample. All `false` in steady, undisturbed operation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct AhrsFlags {
    /// The filter (re)started its orientation from this sample: the first sample, or
    /// the first after a gap longer than `max_gap_s`.
    pub reinitialised: bool,
    /// Initialisation phase: the gain is ramping down from `initial_gain`, nothing is
    /// rejected.
    pub initialising: bool,
    /// The gyroscope clipped (reading beyond 98 % of its range): the initialisation
    /// phase was restarted from the current orientation. Cleared when it ends.
    pub angular_rate_recovery: bool,
    /// The accelerometer correction was skipped for this sample (linear acceleration:
    /// |a| far from g, or its direction far from the estimated gravity), or the sample
    /// had no usable acceleration (all zero).
    pub accel_rejected: bool,
    /// Acceleration recovery: the accelerometer was rejected for the recovery trigger
    /// period, so it is trusted again until it agrees with the estimate.
    pub accel_recovery: bool,
    /// The magnetometer correction was skipped (field magnitude or dip angle off the
    /// learned Earth field: a magnet, steel, a motor nearby). Always `false` for IMU
    /// updates.
    pub mag_rejected: bool,
    /// Magnetic recovery: the magnetometer was rejected for the recovery trigger period;
    /// the learned field is reset to the current one and trusted again.
    pub mag_recovery: bool,
    /// The gyroscope bias estimator is learning (device still for over 5 s).
    pub bias_learning: bool,
}

impl AhrsFlags {
    pub(crate) fn to_bits(self) -> u8 {
        (self.reinitialised as u8)
            | (self.initialising as u8) << 1
            | (self.angular_rate_recovery as u8) << 2
            | (self.accel_rejected as u8) << 3
            | (self.accel_recovery as u8) << 4
            | (self.mag_rejected as u8) << 5
            | (self.mag_recovery as u8) << 6
            | (self.bias_learning as u8) << 7
    }

    pub(crate) fn from_bits(b: u8) -> Self {
        let bit = |i: u8| b & (1 << i) != 0;
        Self {
            reinitialised: bit(0),
            initialising: bit(1),
            angular_rate_recovery: bit(2),
            accel_rejected: bit(3),
            accel_recovery: bit(4),
            mag_rejected: bit(5),
            mag_recovery: bit(6),
            bias_learning: bit(7),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_roundtrip() {
        for b in 0..=255u8 {
            assert_eq!(AhrsFlags::from_bits(b).to_bits(), b);
        }
    }
}
