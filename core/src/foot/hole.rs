//! Samples lost mid-swing (a foot IMU over Bluetooth drops packets): what the
//! navigator knows across the hole. The heading keeps turning at the last stride's
//! rate over the time it cannot integrate, and the next stance checks the tilt.

/// Longest stride of a walk, s: a stride that took longer, or began longer ago, says
/// the foot had stopped, and a hole after it does not turn.
pub(crate) const MAX_STRIDE_S: f64 = 2.5;

/// The walker's turn rate and a hole waiting for its stance.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Hole {
    /// The last stance onset: its time and the heading of the foot's x axis (ENU,
    /// counter-clockwise from East), rad.
    pub onset: Option<(f64, f64)>,
    /// How fast the heading turned over the last stride, rad/s.
    pub turn_rads: f64,
    /// Samples were lost mid-swing and no stance has checked the tilt since.
    pub pending: bool,
}

impl Hole {
    /// A stance begins at `t_s` with the foot's heading `yaw_rad`.
    pub fn onset(&mut self, t_s: f64, yaw_rad: f64) {
        self.turn_rads = match self.onset {
            Some((t0, y0)) if t_s > t0 && t_s - t0 <= MAX_STRIDE_S => {
                wrap(yaw_rad - y0) / (t_s - t0)
            }
            _ => 0.0,
        };
        self.onset = Some((t_s, yaw_rad));
    }

    /// The heading change over `span_s` lost at `t_s` had the walker kept turning as
    /// over the last stride (none if the foot had stopped), rad.
    pub fn turn_over(&self, t_s: f64, span_s: f64) -> f64 {
        match self.onset {
            Some((t0, _)) if t_s - t0 <= MAX_STRIDE_S => self.turn_rads * span_s,
            _ => 0.0,
        }
    }
}

/// An angle into [−π, π).
fn wrap(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    (a + PI).rem_euclid(TAU) - PI
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_turn_rate_is_the_last_strides_and_stops_with_the_walker() {
        let mut h = Hole::default();
        h.onset(10.0, 3.0);
        assert_eq!(h.turn_over(10.5, 1.0), 0.0);
        // Across ±π: a small left turn, not a full circle.
        h.onset(11.0, -3.0);
        let rate = (std::f64::consts::TAU - 6.0) / 1.0;
        assert!((h.turn_over(11.5, 0.5) - 0.5 * rate).abs() < 1e-12);
        // The foot stopped (no onset for longer than a stride): no turn.
        assert_eq!(h.turn_over(11.0 + MAX_STRIDE_S + 0.1, 0.5), 0.0);
        // A stride too slow to be walking: no turn either.
        h.onset(11.0 + MAX_STRIDE_S + 1.0, 0.0);
        assert_eq!(h.turn_over(14.6, 0.5), 0.0);
    }
}
