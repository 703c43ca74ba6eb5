//! A step candidate waiting for its bout to be confirmed, and the merge of two
//! candidates closer than the refractory time (one step: the larger peak).

use crate::stepdetect::event::{StepEvent, StepOrigin};

/// A candidate waiting for its bout to be confirmed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Pending {
    pub(super) event: StepEvent,
    /// Impact ratio of the step (see `RobustStepParams::min_impact_ratio`).
    pub(super) impact: f64,
    /// Peak-to-valley amplitude, m/s².
    pub(super) amplitude_mps2: f64,
    /// How the phone was held at the candidate: the direction of the slowly
    /// low-passed acceleration (gravity) in the sensor frame, unit vector.
    pub(super) carry: [f64; 3],
    /// Input time that gaps in the data hid since the previous candidate, s.
    pub(super) missing_before_s: f64,
}

impl Default for StepEvent {
    fn default() -> Self {
        StepEvent {
            t_s: 0.0,
            duration_s: f64::NAN,
            accel_variance_m2ps4: 0.0,
            accel_max_mps2: 0.0,
            accel_min_mps2: 0.0,
            vertical_displacement_m: f64::NAN,
            origin: StepOrigin::Detected,
        }
    }
}

/// Two candidates closer than the refractory time are one step: the larger peak is
/// its time and amplitude; the step's features span both.
pub(super) fn merge(a: &Pending, b: &Pending) -> Pending {
    let (big, small) = if b.amplitude_mps2 > a.amplitude_mps2 {
        (b, a)
    } else {
        (a, b)
    };
    let d = a.event.duration_s + b.event.duration_s;
    Pending {
        event: StepEvent {
            t_s: big.event.t_s,
            duration_s: if d.is_finite() {
                d
            } else {
                big.event.duration_s
            },
            accel_variance_m2ps4: big.event.accel_variance_m2ps4,
            accel_max_mps2: big.event.accel_max_mps2.max(small.event.accel_max_mps2),
            accel_min_mps2: big.event.accel_min_mps2.min(small.event.accel_min_mps2),
            vertical_displacement_m: f64::NAN,
            origin: big.event.origin,
        },
        impact: big.impact.max(small.impact),
        amplitude_mps2: big.amplitude_mps2,
        carry: big.carry,
        missing_before_s: a.missing_before_s + b.missing_before_s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cand(t_s: f64, duration_s: f64, amplitude_mps2: f64, max: f64) -> Pending {
        Pending {
            event: StepEvent {
                t_s,
                duration_s,
                accel_max_mps2: max,
                accel_min_mps2: 9.0 - amplitude_mps2,
                ..StepEvent::default()
            },
            impact: amplitude_mps2 / 100.0,
            amplitude_mps2,
            carry: [0.0, 0.0, 1.0],
            missing_before_s: 0.0,
        }
    }

    #[test]
    fn the_larger_peak_is_the_step_and_the_features_span_both() {
        let m = merge(&cand(1.0, 0.3, 2.0, 14.0), &cand(1.1, 0.1, 5.0, 12.0));
        assert_eq!(m.event.t_s, 1.1);
        assert!((m.event.duration_s - 0.4).abs() < 1e-12);
        assert_eq!((m.amplitude_mps2, m.impact), (5.0, 0.05));
        assert_eq!(
            (m.event.accel_max_mps2, m.event.accel_min_mps2),
            (14.0, 4.0)
        );
        // The first of a bout has no duration: the larger peak's is kept.
        let m = merge(&cand(1.0, f64::NAN, 2.0, 14.0), &cand(1.1, 0.1, 5.0, 12.0));
        assert_eq!(m.event.duration_s, 0.1);
    }
}
