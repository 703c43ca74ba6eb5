//! The GNSS weight the default filter reports: GNSS's share of the information about
//! the mean speed over the last [`SHARE_WINDOW_S`] (the pace a runner reads), against
//! the pedometer's. Reporting only: no estimate reads it (issue 36).
//!
//! Each epoch's variance reduction cannot say it: the pedometer updates once a second
//! and takes the velocity's variance before each fix comes, so a clean run read
//! `Pedometer` with weight 0 between fixes and about 0.003 at them. Over a window, GNSS
//! tells the mean speed by the chord of its fixes within the gate (the end points' variances
//! over the span squared); the pedometer by cadence × its step length, whose level
//! error does not average out over the window and whose gait noise does. In an outage
//! the weight is 0 once the last fix is [`FRESH_FIX_S`] old; after it the chord grows
//! again from its first fix.

use crate::snapshot::{Reader, SnapshotError, Writer};

/// The window whose mean speed the weight is about, s: about a minute of running, the
/// span over which a runner reads a pace.
pub const SHARE_WINDOW_S: f64 = 60.0;
/// GNSS speaks for the pace now only with a fix at most this old, s (the filter's
/// trust in GNSS lapses at the same age): an outage reads 0 after it.
pub const FRESH_FIX_S: f64 = 5.0;
/// Longest gap between two fixes of one chord, s (a longer one starts anew).
const MAX_CHORD_GAP_S: f64 = 10.0;

/// The span of consecutive fixes within the gate, and the variance of its end points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GnssChord {
    /// Time of the chord's first and last fix, s (NaN: no chord).
    start_t_s: f64,
    last_t_s: f64,
    /// Along-track variance of the first and last fix, m² (their own and the slowly
    /// varying GNSS error's).
    start_var_m2: f64,
    last_var_m2: f64,
}

impl GnssChord {
    pub const NONE: Self = Self {
        start_t_s: f64::NAN,
        last_t_s: f64::NAN,
        start_var_m2: f64::NAN,
        last_var_m2: f64::NAN,
    };

    /// A fix of per-axis variance `var_m2`; `used`: the filter took it at that
    /// variance (within its gate; a gated fix does not extend the chord, and
    /// [`MAX_CHORD_GAP_S`] of them end it).
    pub fn on_fix(&mut self, t_s: f64, var_m2: f64, used: bool) {
        if !used {
            return;
        }
        // NaN (no chord yet) starts one too.
        let continues = t_s - self.last_t_s <= MAX_CHORD_GAP_S;
        if !continues {
            self.start_t_s = t_s;
            self.start_var_m2 = var_m2;
        }
        self.last_t_s = t_s;
        self.last_var_m2 = var_m2;
    }

    /// GNSS's information about the mean speed of the window ending at `t_s`, s²/m²:
    /// the chord's overlap with the window squared over its end points' variance; 0
    /// once the last fix is older than [`FRESH_FIX_S`].
    pub fn information(&self, t_s: f64) -> f64 {
        let fresh = t_s - self.last_t_s <= FRESH_FIX_S;
        if !fresh {
            return 0.0;
        }
        let span = self.last_t_s - self.start_t_s.max(t_s - SHARE_WINDOW_S);
        if span > 0.0 {
            span * span / (self.start_var_m2 + self.last_var_m2)
        } else {
            0.0
        }
    }

    pub fn write(&self, w: &mut Writer) {
        let Self {
            start_t_s,
            last_t_s,
            start_var_m2,
            last_var_m2,
        } = *self;
        w.f64s(&[start_t_s, last_t_s, start_var_m2, last_var_m2]);
    }

    pub fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let mut v = [0.0; 4];
        for x in v.iter_mut() {
            *x = r.f64_or_nan()?;
        }
        let [start_t_s, last_t_s, start_var_m2, last_var_m2] = v;
        if start_var_m2 < 0.0 || last_var_m2 < 0.0 {
            return Err(SnapshotError::Invalid("GNSS chord variance"));
        }
        Ok(Self {
            start_t_s,
            last_t_s,
            start_var_m2,
            last_var_m2,
        })
    }
}

/// The pedometer's information about the window's mean speed `speed_mps`, s²/m²: its
/// step length's relative level σ `level_rel` (learned line, walking line, a
/// disagreement found) does not average out; its per-update gait noise `noise_rel`
/// does, over the window's updates one every `update_interval_s`.
pub fn pedometer_information(
    speed_mps: f64,
    level_rel: f64,
    noise_rel: f64,
    update_interval_s: f64,
) -> f64 {
    let n = SHARE_WINDOW_S / update_interval_s;
    let var = speed_mps * speed_mps * (level_rel * level_rel + noise_rel * noise_rel / n);
    if var > 0.0 {
        1.0 / var
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_chord_grows_with_the_window_and_leaves_it_in_an_outage() {
        let mut c = GnssChord::NONE;
        assert_eq!(c.information(0.0), 0.0);
        for t in 0..=100 {
            c.on_fix(t as f64, 9.0, true);
        }
        let full = c.information(100.0);
        assert!((full - SHARE_WINDOW_S * SHARE_WINDOW_S / 18.0).abs() < 1e-9);
        // 3 s into an outage the window is 57/60 covered; after 5 s, nothing.
        let part = c.information(103.0) / full;
        assert!((part - (57.0f64 / 60.0).powi(2)).abs() < 1e-9, "{part}");
        assert_eq!(c.information(100.0 + FRESH_FIX_S + 0.1), 0.0);
        // A chord restarted 30 s ago covers half the window.
        let mut d = GnssChord::NONE;
        for t in 200..=230 {
            d.on_fix(t as f64, 9.0, true);
        }
        assert!((d.information(230.0) - full / 4.0).abs() < 1e-9);
        c.on_fix(170.0, 9.0, true);
        assert_eq!(c.information(170.0), 0.0, "a gap starts a new chord");
        for t in 171..=185 {
            c.on_fix(t as f64, 9.0, false);
        }
        c.on_fix(186.0, 9.0, true);
        assert_eq!(c.information(186.0), 0.0, "gated fixes end it");
    }
}
