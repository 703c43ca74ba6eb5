//! Magnetic disturbance detection, rejection and recovery.
//!
//! Indoors the field is bent by steel, magnets and electronics. A disturbance adds a
//! field vector; it shows as a change of the field's magnitude or of its dip (angle
//! below the horizontal), both of which the Earth's field keeps wherever the device
//! turns. The filter learns the local field (magnitude and dip, slow means over
//! accepted samples) and takes the field as disturbed while the current values
//! (short means, 50 ms) are off by more than `mag_norm_threshold` (relative) or
//! `mag_dip_threshold_rad`. While disturbed, and for `mag_min_undisturbed_s` after,
//! the magnetometer does not touch the heading, which then follows the
//! bias-corrected gyroscope alone (flag `heading_held`).
//!
//! Recovery: a disturbance lasting longer than `mag_max_rejection_s` is taken to be
//! the new local field (the user walked into another building, or the learned field
//! was wrong): it becomes the reference and the heading re-converges to it.
//!
//! The dip is seen through the estimated inclination: while that is still converging
//! (after a start, a gap or a clipped gyroscope) the dip is not judged and not
//! learned, and the first dip learned after a start is the one measured once the
//! inclination has converged (a first sample taken in vibration or motion can be
//! tens of degrees off, and a reference learned from it would reject the field for
//! good).

use super::heading::UNKNOWN_VAR_RAD2;
use crate::ahrs::field::FieldGate;

/// Time constant of the current magnitude and dip, s.
pub const CURRENT_TIME_CONSTANT_S: f64 = 0.05;
/// Time constant of the learned field's magnitude and dip, s.
pub const REFERENCE_TIME_CONSTANT_S: f64 = 20.0;

/// Gain of a first-order low-pass over `dt` with time constant 1/`inv_tau`:
/// dt/τ (the first-order term of 1 − e^(−dt/τ); no division), at most 1.
#[inline(always)]
pub(crate) fn gain(dt: f64, inv_tau: f64) -> f64 {
    let k = dt * inv_tau;
    if k < 1.0 {
        k
    } else {
        1.0
    }
}

/// Disturbance detector state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct MagDisturbance {
    /// Learned field magnitude (µT) and dip (rad), and whether there is one.
    pub(crate) ref_norm_ut: f64,
    pub(crate) ref_dip_rad: f64,
    pub(crate) ref_valid: bool,
    /// The reference dip was measured with a converged inclination.
    pub(crate) dip_trusted: bool,
    /// Current (short-mean) magnitude, µT, and dip, rad.
    pub(crate) norm_ut: f64,
    pub(crate) dip_rad: f64,
    /// Time the field has looked undisturbed, s (capped), and the time the heading
    /// has gone without a magnetometer correction, s.
    pub(crate) undisturbed_s: f64,
    pub(crate) rejected_s: f64,
}

/// Thresholds of the detector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct MagLimits {
    pub(crate) norm_rel: f64,
    pub(crate) dip_rad: f64,
    pub(crate) min_undisturbed_s: f64,
    pub(crate) max_rejection_s: f64,
}

/// What to do with one magnetometer sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct MagVerdict {
    /// Correct the heading with it.
    pub(crate) use_it: bool,
    /// Magnitude or dip off the learned field.
    pub(crate) disturbed: bool,
    /// The disturbance lasted too long: it became the reference now.
    pub(crate) recovered: bool,
}

impl MagDisturbance {
    /// Forget the learned field (first sample, or after a gap).
    pub(crate) fn restart(&mut self, lim: &MagLimits) {
        self.ref_valid = false;
        self.dip_trusted = false;
        self.undisturbed_s = lim.min_undisturbed_s;
        self.rejected_s = 0.0;
    }

    /// A restart after a gap: the learned field (magnitude, dip and whether the dip
    /// was measured through a converged inclination) is the place's and stays; the
    /// short means start from this sample (`norm_ut`, `dip_rad`), and the heading is
    /// corrected at once if the field matches. Learning it anew from the restart's
    /// first sample would take a disturbed one for the Earth's field and reject the
    /// Earth's for [`MagLimits::max_rejection_s`] (measured: 64° on a BROAD magnet
    /// trial with 10 % of the samples dropped in bursts). A field that really changed
    /// during the gap is taken by the recovery.
    pub(crate) fn resume(&mut self, norm_ut: f64, dip_rad: f64, lim: &MagLimits) {
        self.norm_ut = norm_ut;
        self.dip_rad = dip_rad;
        self.undisturbed_s = lim.min_undisturbed_s;
        self.rejected_s = 0.0;
    }

    /// The heading error a disturbance may cause, as a variance, rad²: the current
    /// field's departure from the learned one (magnitude, and dip when `judge_dip`)
    /// over the learned horizontal field. The departure shows the disturbance along
    /// the field and across it in the vertical plane; the heading is turned by its
    /// part across it in the horizontal plane, which it does not show: taken as large
    /// as the two it shows together (measured on BROAD's magnet trials through the
    /// optical attitude: 0.3–0.6 of that for stationary magnets, up to 2.6 for
    /// attached ones).
    pub(crate) fn heading_var(&self, judge_dip: bool) -> f64 {
        let d_norm = self.norm_ut - self.ref_norm_ut;
        let d_dip = if judge_dip {
            self.ref_norm_ut * (self.dip_rad - self.ref_dip_rad)
        } else {
            0.0
        };
        let h = self.ref_norm_ut * self.ref_dip_rad.cos();
        let h2 = h * h;
        if h2 > 0.0 {
            ((d_norm * d_norm + d_dip * d_dip) / h2).min(UNKNOWN_VAR_RAD2)
        } else {
            UNKNOWN_VAR_RAD2
        }
    }

    /// The dip is judged: the inclination it is seen through has converged
    /// (`tilt_known`) and so had the one the learned dip was seen through.
    #[inline(always)]
    pub(crate) fn judges_dip(&self, tilt_known: bool) -> bool {
        tilt_known & self.dip_trusted
    }

    /// Assess one sample of magnitude `norm_ut` and dip `dip_rad`; `tilt_known`: the
    /// inclination the dip was measured with has converged.
    #[inline(always)]
    pub(crate) fn assess(
        &mut self,
        norm_ut: f64,
        dip_rad: f64,
        dt: f64,
        tilt_known: bool,
        lim: &MagLimits,
    ) -> MagVerdict {
        if !self.ref_valid {
            self.norm_ut = norm_ut;
            self.dip_rad = dip_rad;
            self.ref_norm_ut = norm_ut;
            self.ref_dip_rad = dip_rad;
            self.ref_valid = true;
        } else {
            let k = gain(dt, 1.0 / CURRENT_TIME_CONSTANT_S);
            self.norm_ut += k * (norm_ut - self.norm_ut);
            self.dip_rad += k * (dip_rad - self.dip_rad);
        }
        if tilt_known & !self.dip_trusted {
            // The first dip seen through a converged inclination (this sample's: the
            // short mean still carries the unconverged ones).
            self.dip_rad = dip_rad;
            self.ref_dip_rad = dip_rad;
            self.dip_trusted = true;
        }
        let judge_dip = self.judges_dip(tilt_known);
        // The dip is judged only through a converged inclination (an infinite gate
        // otherwise).
        let gate = FieldGate {
            strength_ut: lim.norm_rel * self.ref_norm_ut,
            dip_rad: if judge_dip {
                lim.dip_rad
            } else {
                f64::INFINITY
            },
        };
        let disturbed = gate.departs(
            self.norm_ut,
            self.dip_rad,
            self.ref_norm_ut,
            self.ref_dip_rad,
        );
        self.undisturbed_s = if disturbed {
            0.0
        } else if self.undisturbed_s < lim.min_undisturbed_s {
            self.undisturbed_s + dt
        } else {
            lim.min_undisturbed_s
        };
        let mut v = MagVerdict {
            use_it: !disturbed & (self.undisturbed_s >= lim.min_undisturbed_s),
            disturbed,
            recovered: false,
        };
        if v.use_it {
            self.rejected_s = 0.0;
            let k = gain(dt, 1.0 / REFERENCE_TIME_CONSTANT_S);
            self.ref_norm_ut += k * (self.norm_ut - self.ref_norm_ut);
            if judge_dip {
                self.ref_dip_rad += k * (self.dip_rad - self.ref_dip_rad);
            }
        } else {
            self.rejected_s += dt;
            if self.rejected_s > lim.max_rejection_s {
                self.ref_norm_ut = self.norm_ut;
                self.ref_dip_rad = self.dip_rad;
                self.dip_trusted = tilt_known;
                self.rejected_s = 0.0;
                self.undisturbed_s = lim.min_undisturbed_s;
                v = MagVerdict {
                    use_it: true,
                    disturbed: false,
                    recovered: true,
                };
            }
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIM: MagLimits = MagLimits {
        norm_rel: 0.1,
        dip_rad: 0.17,
        min_undisturbed_s: 0.5,
        max_rejection_s: 60.0,
    };

    #[test]
    fn rejects_a_disturbance_then_waits_then_recovers_for_good() {
        let mut m = MagDisturbance::default();
        m.restart(&LIM);
        let dt = 0.01;
        assert!(m.assess(45.0, 1.2, dt, true, &LIM).use_it);
        for _ in 0..100 {
            assert!(m.assess(45.0, 1.2, dt, true, &LIM).use_it);
        }
        // A magnet: 60 µT for 2 s.
        let mut seen = 0;
        for _ in 0..200 {
            let v = m.assess(60.0, 1.2, dt, true, &LIM);
            seen += v.disturbed as usize;
            assert!(!v.use_it || seen == 0);
        }
        assert!(seen > 190);
        // Gone: trusted again only after 0.5 s undisturbed.
        let used: Vec<bool> = (0..100)
            .map(|_| m.assess(45.0, 1.2, dt, true, &LIM).use_it)
            .collect();
        let first = used.iter().position(|&u| u).unwrap();
        assert!((50..=60).contains(&first), "{first}");
        // A new field for longer than the rejection limit becomes the reference.
        let mut recovered_at = None;
        for i in 0..7000 {
            let v = m.assess(30.0, 1.0, dt, true, &LIM);
            if v.recovered {
                recovered_at = Some(i);
            }
        }
        let i = recovered_at.unwrap();
        assert!((5990..6010).contains(&i), "{i}");
        assert!(m.assess(30.0, 1.0, dt, true, &LIM).use_it);
    }

    #[test]
    fn the_dip_is_judged_only_through_a_converged_inclination() {
        let mut m = MagDisturbance::default();
        m.restart(&LIM);
        let dt = 0.01;
        // A first inclination 30° off: the dip reads 0.7 rad while it converges.
        for _ in 0..100 {
            assert!(m.assess(45.0, 0.7, dt, false, &LIM).use_it);
        }
        // Converged: the true dip (1.2 rad) becomes the reference, not a disturbance.
        for _ in 0..100 {
            assert!(m.assess(45.0, 1.2, dt, true, &LIM).use_it);
        }
        assert!((m.ref_dip_rad - 1.2).abs() < 0.01, "{}", m.ref_dip_rad);
        // Later, while the inclination re-converges (a gap), a wrong dip is not judged
        // and not learned; a wrong magnitude still is.
        for _ in 0..50 {
            assert!(m.assess(45.0, 0.8, dt, false, &LIM).use_it);
        }
        assert!((m.ref_dip_rad - 1.2).abs() < 0.01);
        assert!(
            m.assess(60.0, 1.2, dt, false, &LIM).disturbed || {
                (0..20).any(|_| m.assess(60.0, 1.2, dt, false, &LIM).disturbed)
            }
        );
    }
}
