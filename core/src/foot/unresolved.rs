//! The rotation the gyroscope's samples do not resolve: the trapezoid rule's error over
//! each interval, from the raw rates' second difference. The filter's attitude variance
//! grows by it, so that an under-sampled swing is not taken as exactly integrated.

/// The trapezoid rule's error over an interval `dt` is `−dt³ ω''/12`; with `ω'' ≈ Δ²ω /
/// dt²` (the rates' second difference) it is `dt |Δ²ω| / 12` rad. A smooth swing at
/// 200 Hz gives next to nothing, a heel strike point-sampled at 50 Hz tens of degrees
/// over a stride (issue 39: such copies ran away to metres when the zero-velocity
/// updates put the tilt error into an accelerometer bias).
pub(crate) const TRAPEZOID_ERROR: f64 = 1.0 / 12.0;

/// The sensor's last rate and its change over the last interval (body axes, before the
/// clipping repair, which is an estimate of its own and must not count as a jolt).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Unresolved {
    /// Rates seen, up to 2 (a second difference needs three).
    pub seen: u8,
    pub prev_w: [f64; 3],
    pub prev_dw: [f64; 3],
}

impl Unresolved {
    /// The next raw rate `w` (rad/s), `dt_s` after the previous one (capped by the
    /// caller as the integration is); returns the rotation over the interval the
    /// samples do not resolve about each body axis, rad (0 for the first two samples).
    #[inline]
    pub(crate) fn push(&mut self, w: [f64; 3], dt_s: f64) -> [f64; 3] {
        let mut dw = [0.0; 3];
        let mut d2 = [0.0; 3];
        if self.seen > 0 {
            for i in 0..3 {
                dw[i] = w[i] - self.prev_w[i];
                d2[i] = (dw[i] - self.prev_dw[i]).abs();
            }
        }
        let second = self.seen >= 2;
        self.seen = self.seen.saturating_add(1).min(2);
        self.prev_w = w;
        self.prev_dw = dw;
        if second {
            d2.map(|d| d * dt_s.max(0.0) * TRAPEZOID_ERROR)
        } else {
            [0.0; 3]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rate_changing_at_a_steady_pace_is_resolved() {
        let mut u = Unresolved::default();
        for k in 0..50 {
            let w = [0.3 * k as f64, -2.0, 1.0 + 0.01 * k as f64];
            assert!(u.push(w, 0.005).iter().all(|r| *r < 1e-12));
        }
    }

    #[test]
    fn a_jolt_is_not() {
        let mut u = Unresolved::default();
        for w in [[0.0; 3], [0.0; 3], [0.0; 3]] {
            u.push(w, 0.02);
        }
        let r = u.push([6.0, 0.0, 0.0], 0.02);
        assert!((r[0] - 6.0 * 0.02 / 12.0).abs() < 1e-12, "{r:?}");
        assert_eq!((r[1], r[2]), (0.0, 0.0));
    }
}
