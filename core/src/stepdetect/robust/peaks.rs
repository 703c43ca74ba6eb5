//! Peaks with hysteresis on the grid: x = filtered magnitude − its slow mean; a peak is
//! confirmed when x falls δ below the running maximum, a valley when it rises δ above
//! the running minimum, δ = max(`min_hysteresis_mps2`, `hysteresis_rel` · RMS(x)). Each
//! peak, with its amplitude over the previous valley, is a step candidate.

use super::{RobustDetector, Sink};

/// Two cascaded first-order low-pass sections: the group delay is this many τ,
/// subtracted from the reported peak times.
const LOWPASS_SECTIONS: f64 = 2.0;

impl RobustDetector {
    /// One grid sample `y` (filtered magnitude) at `t_s`; `bridged`: interpolated
    /// across a gap in the data. A bridged stretch is a straight line, not gait: the
    /// step period's autocorrelation leaves it out (two bridged gaps a few steps apart
    /// correlate with each other, line against line, and that lag could outscore the
    /// stride).
    pub(super) fn grid(&mut self, t_s: f64, y: f64, bridged: bool, out: &mut Sink<'_>) {
        self.release_tail_if_due(t_s, out);
        self.release_held_if_due(t_s, out);
        let x = self.demean(y);
        self.xs.push(x);
        self.gait.push(if bridged { f64::NAN } else { x });
        let delta = self
            .p
            .min_hysteresis_mps2
            .max(self.p.hysteresis_rel * self.ms.sqrt());
        if let Some((peak_t, amplitude)) = self.track_extremum(t_s, x, delta) {
            self.candidate(peak_t, amplitude, out);
        }
    }

    /// `y` minus its slow mean; the mean square of the result follows it.
    fn demean(&mut self, y: f64) -> f64 {
        let (a_mean, a_ms) = (self.gain_mean, self.gain_ms);
        self.mean += a_mean * (y - self.mean);
        let x = y - self.mean;
        self.ms += a_ms * (x * x - self.ms);
        x
    }

    /// Follow the running extremum; a confirmed peak (after a valley) gives its time
    /// (delay-corrected) and its peak-to-valley amplitude.
    fn track_extremum(&mut self, t_s: f64, x: f64, delta: f64) -> Option<(f64, f64)> {
        if self.seeking_peak {
            if x > self.ext_x {
                self.ext_x = x;
                self.ext_t_s = t_s;
            } else if x < self.ext_x - delta {
                let amplitude = self.ext_x - self.valley_x;
                let peak_t = self.ext_t_s - LOWPASS_SECTIONS * self.tau_lp_s;
                self.seeking_peak = false;
                self.ext_x = x;
                self.ext_t_s = t_s;
                return amplitude.is_finite().then_some((peak_t, amplitude));
            }
        } else if x < self.ext_x {
            self.ext_x = x;
            self.ext_t_s = t_s;
        } else if x > self.ext_x + delta {
            self.valley_x = self.ext_x;
            self.seeking_peak = true;
            self.ext_x = x;
            self.ext_t_s = t_s;
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::super::RobustStepParams;
    use super::*;

    #[test]
    fn a_peak_is_confirmed_after_a_valley_and_a_fall_of_delta() {
        let mut d = RobustDetector::new(RobustStepParams::default());
        let mut found = Vec::new();
        for (i, x) in [0.0, -1.0, -2.0, -1.0, 0.5, 2.0, 1.8, 1.9, 1.0, 0.0]
            .into_iter()
            .enumerate()
        {
            if let Some(p) = d.track_extremum(i as f64, x, 0.5) {
                found.push(p);
            }
        }
        // The first peak (0.0 at t = 0) has no valley before it: not a candidate. The
        // second (2.0 at t = 5, over the valley −2.0) is; the small dip 1.8 is not.
        assert_eq!(found.len(), 1);
        let (t, amplitude) = found[0];
        assert!((t - (5.0 - 2.0 * d.tau_lp_s)).abs() < 1e-12);
        assert_eq!(amplitude, 4.0);
    }
}
