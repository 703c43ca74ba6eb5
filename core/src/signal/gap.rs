//! Lost samples: an interval much longer than the stream's typical one is a gap. The
//! typical interval is learned from the intervals that are not gaps; the AHRS and the
//! PDR navigator's heading bridge use the same rule.

/// An interval longer than this many typical intervals is a gap: samples were lost
/// (a Bluetooth burst, a busy phone) and the motion meanwhile is unknown.
const GAP_INTERVALS: f64 = 3.0;
/// Gain per sample of the typical interval (a running mean over ~100 samples of the
/// intervals that are not gaps).
const TYPICAL_INTERVAL_GAIN: f64 = 0.01;

/// Whether `dt` (s, > 0) is a gap against `dt_typ_s` (0 before the first interval);
/// learns the typical interval from the intervals that are not gaps.
#[inline(always)]
pub(crate) fn is_gap(dt_typ_s: &mut f64, dt: f64) -> bool {
    if *dt_typ_s <= 0.0 {
        *dt_typ_s = dt;
        return false;
    }
    if dt <= GAP_INTERVALS * *dt_typ_s {
        *dt_typ_s += TYPICAL_INTERVAL_GAIN * (dt - *dt_typ_s);
        return false;
    }
    true
}
