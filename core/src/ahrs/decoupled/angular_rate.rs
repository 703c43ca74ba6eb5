//! Angular-rate recovery: a clipped gyroscope (beyond its range, or stuck on one fast
//! reading) or a gap in the samples makes the integration wrong; this file tells
//! when, bridges short gaps and says how much rotation may have been missed.

use super::Decoupled;

/// A gap is bridged by the gyroscope (the mean of the rates before and after it,
/// integrated over the gap) when the rotation that could hide in it, the larger rate
/// times the gap, is below this, rad (2°); beyond, the averages restart as after a
/// clipped gyroscope.
pub const GAP_BRIDGE_RAD: f64 = 2.0 * std::f64::consts::PI / 180.0;
/// What one clipped gyroscope sample may have missed, rad (5°).
pub const CLIP_MISSED_RAD: f64 = 5.0 * std::f64::consts::PI / 180.0;
/// A gyroscope axis that reads exactly the same value on many consecutive samples at
/// a rate of at least this, rad/s (115°/s), is clipped: a sensor's output code
/// saturates, while a real rate that fast rarely holds one code. Catches the clipping
/// of a gyroscope whose range the settings do not know.
pub const CLIP_PLATEAU_MIN_RADS: f64 = 2.0;
/// Repeats (samples after the first) that make a plateau: the BROAD sensor's own
/// quantisation repeats a reading above 2 rad/s up to 5 times in 16 trials.
const CLIP_PLATEAU_REPEATS: u8 = 8;

/// The verdict on one gyroscope sample.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RateCheck {
    /// The interval is a gap (bridged or not).
    pub(crate) gap: bool,
    /// The integration is lost: a clipped reading, or a gap too long to bridge.
    pub(crate) lost: bool,
    /// The gap could hide up to √this rad (0 without a gap).
    missed2: f64,
    /// The reading before this one, rad/s.
    prev: [f64; 3],
}

/// The watch's state lives in [`Decoupled`] (`dt_typ_s`, `gyro_prev`,
/// `plateau_run`), next to the flags it shares padding with.
impl Decoupled {
    /// Start from one reading.
    pub(crate) fn start_watch(&mut self, gyro: &[f64; 3]) {
        self.gyro_prev = *gyro;
        self.plateau_run = 0;
    }

    /// Judge one reading `gyro` after `dt`.
    #[inline(always)]
    pub(crate) fn check_rate(&mut self, dt: f64, gyro: &[f64; 3]) -> RateCheck {
        let clip_rads = self.gyro_clip_rads;
        let prev = self.gyro_prev;
        let clipped = (gyro[0].abs() > clip_rads)
            | (gyro[1].abs() > clip_rads)
            | (gyro[2].abs() > clip_rads)
            | self.plateau(gyro);
        let gap = self.gap(dt);
        let missed2 = if gap {
            bridge_angle2(&prev, gyro, dt)
        } else {
            0.0
        };
        let bridged = missed2 <= GAP_BRIDGE_RAD * GAP_BRIDGE_RAD;
        RateCheck {
            gap,
            lost: clipped | !bridged,
            missed2,
            prev,
        }
    }

    /// Whether the gyroscope repeats a fast reading exactly (a clipped axis).
    #[inline(always)]
    fn plateau(&mut self, gyro: &[f64; 3]) -> bool {
        let p = &self.gyro_prev;
        let same = |i: usize| (gyro[i] == p[i]) & (gyro[i].abs() >= CLIP_PLATEAU_MIN_RADS);
        self.plateau_run = if same(0) | same(1) | same(2) {
            self.plateau_run.saturating_add(1)
        } else {
            0
        };
        self.gyro_prev = *gyro;
        self.plateau_run >= CLIP_PLATEAU_REPEATS
    }

    /// Whether `dt` is a gap (samples lost); learns the typical interval from the
    /// intervals that are not gaps.
    #[inline(always)]
    fn gap(&mut self, dt: f64) -> bool {
        crate::signal::is_gap(&mut self.dt_typ_s, dt)
    }
}

impl RateCheck {
    /// The rate to integrate, bias `b` removed: across a gap, the mean of the rates on
    /// either side.
    #[inline(always)]
    pub(crate) fn rate(&self, gyro: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
        if self.gap {
            let prev = &self.prev;
            std::array::from_fn(|i| 0.5 * (gyro[i] + prev[i]) - b[i])
        } else {
            [gyro[0] - b[0], gyro[1] - b[1], gyro[2] - b[2]]
        }
    }

    /// What a lost integration may have missed, rad: a clipped reading at least what
    /// it would have turned by, an unbridged gap its rate times its length.
    #[cold]
    pub(crate) fn missed_rad(&self, gyro: &[f64; 3], dt: f64) -> f64 {
        if self.missed2 <= GAP_BRIDGE_RAD * GAP_BRIDGE_RAD {
            let w2 = gyro[0] * gyro[0] + gyro[1] * gyro[1] + gyro[2] * gyro[2];
            CLIP_MISSED_RAD.max(w2.sqrt() * dt)
        } else {
            self.missed2.sqrt()
        }
    }
}

/// The square of the rotation a gap of `dt` could hide: the larger of the rates on
/// either side of it, times the gap.
#[cold]
fn bridge_angle2(before: &[f64; 3], after: &[f64; 3], dt: f64) -> f64 {
    let n2 = |w: &[f64; 3]| w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    n2(before).max(n2(after)) * dt * dt
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaps_are_bridged_or_lost_and_plateaus_are_clipping() {
        let settings = crate::ahrs::AhrsSettings {
            gyro_range_rads: 100.0 / crate::ahrs::madgwick::GYRO_CLIP_SHARE,
            ..crate::ahrs::AhrsSettings::default()
        };
        let mut w = Decoupled::new(&settings);
        w.start_watch(&[0.0; 3]);
        for _ in 0..10 {
            assert!(!w.check_rate(0.01, &[0.1, 0.0, 0.0]).gap);
        }
        // A 0.05 s gap at 0.1 rad/s hides 0.3°: bridged with the mean rate.
        let c = w.check_rate(0.05, &[0.3, 0.0, 0.0]);
        assert!(c.gap && !c.lost);
        assert!((c.rate(&[0.3, 0.0, 0.0], &[0.0; 3])[0] - 0.2).abs() < 1e-12);
        // The same gap at 3 rad/s could hide 8.6°: lost.
        let c = w.check_rate(0.05, &[3.0, 0.0, 0.0]);
        assert!(c.gap && c.lost);
        assert!((c.missed_rad(&[3.0, 0.0, 0.0], 0.05) - 0.15).abs() < 1e-12);
        // Beyond the range: lost, missing at least CLIP_MISSED_RAD.
        let c = w.check_rate(0.01, &[0.0, 150.0, 0.0]);
        assert!(!c.gap && c.lost);
        assert!(c.missed_rad(&[0.0, 150.0, 0.0], 0.01) >= CLIP_MISSED_RAD);
        // A fast reading repeated exactly: clipped once the run is long enough.
        let lost: Vec<bool> = (0..12)
            .map(|_| w.check_rate(0.01, &[2.5, 0.0, 0.0]).lost)
            .collect();
        let first = lost.iter().position(|&l| l).unwrap();
        assert_eq!(first, CLIP_PLATEAU_REPEATS as usize);
    }
}
