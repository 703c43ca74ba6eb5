//! Heel impacts: the RMS of the raw magnitude above 8 Hz (second-order high-pass) over
//! a step, divided by the step's amplitude. Heel strikes put energy above 8 Hz; smooth
//! periodic motion without impacts (pedalling) does not. A weak guard (see
//! `RobustStepParams::min_impact_ratio`).

use super::{ema_gain, RobustDetector};

/// Corner of the high-pass that isolates heel impacts from the smooth step motion, Hz.
const IMPACT_HZ: f64 = 8.0;
/// Input slower than 4 × [`IMPACT_HZ`] (32 Hz: a Nyquist frequency under twice the
/// corner, where a phone's own anti-alias filter has already taken most of the band)
/// does not resolve impacts: on the indoor walks decimated to 25 Hz, the impact check
/// refused whole walks (52 → 23 steps, 20 → 0). There the check is not made, and the
/// detector cannot tell pedalling from walking by impacts. Mean spacing, s.
const IMPACT_MIN_SPACING_S: f64 = 1.0 / (4.0 * IMPACT_HZ);

impl RobustDetector {
    /// One sample of the raw magnitude through the high-pass (two first-order
    /// sections, each: input − its low-pass; steeper filters remove too much of the
    /// impact content at 50 Hz), its square summed.
    pub(super) fn accumulate_impact(&mut self, dt: f64, mag: f64) {
        let b = ema_gain(dt * 2.0 * std::f64::consts::PI * IMPACT_HZ);
        let mut h = mag;
        for lp in &mut self.hp {
            *lp += b * (h - *lp);
            h -= *lp;
        }
        let hf = h;
        self.hf_sum_sq += hf * hf;
        self.hf_n += 1.0;
    }

    /// The impact ratio of a candidate at `t_s` of `amplitude`, m/s²: NaN (no check)
    /// when the input since the previous candidate was too slow to resolve the band;
    /// a step-strength candidate starts the next sum.
    pub(super) fn impact_ratio(&mut self, t_s: f64, amplitude: f64) -> f64 {
        let spacing = (t_s - self.last_t_s) / self.moments.n; // NaN without a previous
        let impact = if spacing > IMPACT_MIN_SPACING_S {
            f64::NAN
        } else if self.hf_n > 0.0 {
            (self.hf_sum_sq / self.hf_n).sqrt() / amplitude
        } else {
            0.0
        };
        if amplitude >= self.p.min_amplitude_mps2 {
            self.hf_sum_sq = 0.0;
            self.hf_n = 0.0;
        }
        impact
    }
}

#[cfg(test)]
mod tests {
    use super::super::RobustStepParams;
    use super::*;

    #[test]
    fn impacts_pass_the_high_pass_and_smooth_motion_does_not() {
        let rms = |f_hz: f64| {
            let mut d = RobustDetector::new(RobustStepParams::default());
            d.hp = [9.81, 0.0];
            for i in 0..1000 {
                let t = i as f64 * 0.005;
                d.accumulate_impact(0.005, 9.81 + (2.0 * std::f64::consts::PI * f_hz * t).sin());
            }
            (d.hf_sum_sq / d.hf_n).sqrt()
        };
        // 2 Hz (a step's swing) against 25 Hz (an impact's ringing), amplitude 1.
        assert!(rms(2.0) < 0.1, "{}", rms(2.0));
        assert!(rms(25.0) > 0.4, "{}", rms(25.0));
    }

    #[test]
    fn slow_input_measures_no_ratio() {
        let mut d = RobustDetector::new(RobustStepParams::default());
        d.last_t_s = 0.0;
        d.hf_sum_sq = 4.0;
        d.hf_n = 4.0;
        for _ in 0..10 {
            d.moments.add(9.8);
        }
        // 10 samples over 0.5 s (20 Hz): too slow.
        assert!(d.impact_ratio(0.5, 2.0).is_nan());
        d.hf_sum_sq = 4.0;
        d.hf_n = 4.0;
        // 10 samples over 0.2 s (50 Hz): RMS 1 over an amplitude of 2.
        assert_eq!(d.impact_ratio(0.2, 2.0), 0.5);
        assert_eq!((d.hf_sum_sq, d.hf_n), (0.0, 0.0));
    }
}
