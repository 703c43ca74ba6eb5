//! What the filter did with the latest sample and why (Fusion's "flags" and
//! "internal states"): so an app can tell a trusted orientation from a coasting one.

/// State of the filter after a sample. All `false` in steady, undisturbed motion
/// (the decoupled filter sets `at_rest` / `bias_learning` when still and
/// `bias_motion` while it learns the bias from the accelerometer in motion).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct AhrsFlags {
    /// The filter (re)started its orientation from this sample: the first sample, or
    /// the first after a gap longer than `max_gap_s`.
    pub reinitialised: bool,
    /// Initialisation phase. Madgwick: the gain is ramping down from `initial_gain`,
    /// nothing is rejected. Decoupled: the accelerometer average or the heading is
    /// still a running mean of the samples since the start (converging fast).
    pub initialising: bool,
    /// The gyroscope clipped (reading beyond 98 % of its range): the integrated
    /// orientation is not trusted, the filter re-converges from the accelerometer and
    /// magnetometer (Madgwick: restarts its initialisation phase). Cleared when done.
    pub angular_rate_recovery: bool,
    /// The accelerometer correction was skipped for this sample. Madgwick: linear
    /// acceleration (|a| far from g, or its direction far from the estimated
    /// gravity). Both: the sample had no usable acceleration (all zero).
    pub accel_rejected: bool,
    /// Madgwick's acceleration recovery: the accelerometer was rejected for the
    /// recovery trigger period, so it is trusted again until it agrees with the
    /// estimate.
    pub accel_recovery: bool,
    /// The magnetometer did not correct the heading on this sample (disturbed, or not
    /// yet settled after a disturbance). Always `false` for IMU updates.
    pub mag_rejected: bool,
    /// Magnetic recovery: the field was rejected for too long (Madgwick: the recovery
    /// trigger period; decoupled: `mag_max_rejection_s`), so the current field became
    /// the learned one and the heading re-converges to it.
    pub mag_recovery: bool,
    /// The gyroscope bias is being learned at rest (Madgwick: still for over 5 s;
    /// decoupled: `at_rest`).
    pub bias_learning: bool,
    /// The device is at rest (decoupled filter's rest detector; Madgwick: same as
    /// `bias_learning`).
    pub at_rest: bool,
    /// The gyroscope bias is being learned in motion from the inclination corrections
    /// (decoupled filter only).
    pub bias_motion: bool,
    /// The field's magnitude or dip is off the learned Earth field: a magnet, steel or
    /// electronics nearby (Madgwick: same as `mag_rejected`).
    pub mag_disturbed: bool,
    /// The heading follows the gyroscope alone on this sample although a
    /// magnetometer reading came with it (the field was rejected). Decoupled filter:
    /// the inclination is unaffected by this; Madgwick: same as `mag_rejected`.
    pub heading_held: bool,
    /// Decoupled filter: the magnetometer offset (hard iron) is still being learned
    /// (its uncertainty is above 2 µT on some axis, so the heading may be off by
    /// several degrees); it clears once the device has turned about two axes. Never
    /// set with `mag_offset_max_ut` = 0, nor by the Madgwick filter.
    pub mag_calibrating: bool,
}

impl AhrsFlags {
    #[inline(always)]
    pub(crate) fn to_bits(self) -> u16 {
        (self.reinitialised as u16)
            | (self.initialising as u16) << 1
            | (self.angular_rate_recovery as u16) << 2
            | (self.accel_rejected as u16) << 3
            | (self.accel_recovery as u16) << 4
            | (self.mag_rejected as u16) << 5
            | (self.mag_recovery as u16) << 6
            | (self.bias_learning as u16) << 7
            | (self.at_rest as u16) << 8
            | (self.bias_motion as u16) << 9
            | (self.mag_disturbed as u16) << 10
            | (self.heading_held as u16) << 11
            | (self.mag_calibrating as u16) << 12
    }

    #[inline(always)]
    pub(crate) fn from_bits(b: u16) -> Self {
        let bit = |i: u16| b & (1 << i) != 0;
        Self {
            reinitialised: bit(0),
            initialising: bit(1),
            angular_rate_recovery: bit(2),
            accel_rejected: bit(3),
            accel_recovery: bit(4),
            mag_rejected: bit(5),
            mag_recovery: bit(6),
            bias_learning: bit(7),
            at_rest: bit(8),
            bias_motion: bit(9),
            mag_disturbed: bit(10),
            heading_held: bit(11),
            mag_calibrating: bit(12),
        }
    }

    /// Names of the flags, in bit order (the CSV header of `stridekit orientation`).
    pub const NAMES: [&'static str; 13] = [
        "reinitialised",
        "initialising",
        "angular_rate_recovery",
        "accel_rejected",
        "accel_recovery",
        "mag_rejected",
        "mag_recovery",
        "bias_learning",
        "at_rest",
        "bias_motion",
        "mag_disturbed",
        "heading_held",
        "mag_calibrating",
    ];

    /// The flags as booleans in the order of [`AhrsFlags::NAMES`].
    pub fn to_array(self) -> [bool; 13] {
        let b = self.to_bits();
        std::array::from_fn(|i| b & (1 << i) != 0)
    }
}

/// The flags packed into one integer (bit i: [`AhrsFlags::NAMES`]`[i]`), as a filter
/// carries them from one sample to the next: one 2-byte store per update, where a copy
/// of the 12-byte struct, built byte by byte, stalls store-to-load forwarding.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct PackedFlags(u16);

impl PackedFlags {
    #[inline(always)]
    pub(crate) fn pack(flags: AhrsFlags) -> Self {
        Self(flags.to_bits())
    }

    #[inline(always)]
    pub(crate) fn unpack(self) -> AhrsFlags {
        AhrsFlags::from_bits(self.0)
    }

    /// `angular_rate_recovery` (bit 2) without unpacking the rest.
    #[inline(always)]
    pub(crate) fn angular_rate_recovery(self) -> bool {
        self.0 & (1 << 2) != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_roundtrip() {
        for b in 0..(1u16 << 13) {
            assert_eq!(AhrsFlags::from_bits(b).to_bits(), b);
        }
        let f = AhrsFlags {
            heading_held: true,
            ..AhrsFlags::default()
        };
        assert!(f.to_array()[11]);
        assert_eq!(PackedFlags::pack(f).unpack(), f);
        assert_eq!(AhrsFlags::NAMES[11], "heading_held");
    }
}
