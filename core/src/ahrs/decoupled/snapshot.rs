//! The decoupled filter's state in a snapshot: written field by field (every struct
//! destructured, so a new field left out is a compile error), read back in the same
//! order and checked against the ranges a running filter can reach.

use super::bias::Bias;
use super::hard_iron::{self, HardIron};
use super::heading::{Heading, UNKNOWN_VAR_RAD2};
use super::magnetic::MagDisturbance;
use super::rest::Rest;
use super::tilt::{self, Tilt};
use super::{Decoupled, SLOW_PERIOD_S};
use crate::input::limits::{MAX_ACCEL_NORM_MPS2, MAX_GYRO_RADS, MAX_MAG_UT};
use crate::snapshot::{Reader, SnapshotError, Writer};
use std::f64::consts::PI;

/// Largest |component| of the summed inclination corrections and largest bias
/// variance a restored state may hold (a backstop: real values are far smaller).
const MAX_STORED_CORRECTION: f64 = 1e6;
/// Largest |mean heading correction rate| a restored state may hold, rad/s: a
/// converged heading is corrected by at most π per update, and its updates are at
/// least [`SLOW_PERIOD_S`] apart.
const MAX_HEADING_DRIFT_RADS: f64 = PI / SLOW_PERIOD_S;
/// How far a restored quaternion's squared norm may be from 1.
const UNIT_NORM_TOLERANCE: f64 = 1e-6;

impl Decoupled {
    pub(crate) fn write_state(&self, w: &mut Writer) {
        let Decoupled {
            tilt,
            bias,
            rest,
            heading,
            mag,
            hard_iron,
            offset_applied_ut,
            offset_seen_ut,
            accel_elapsed_s,
            bias_corr,
            bias_elapsed_s,
            mag_elapsed_s,
            heading_init,
            heading_drift_rads,
            drift_learning,
            dt_typ_s,
            gyro_prev,
            plateau_run,
            clip_miss_rad,
            // Derived from the settings, or carried by the engine's own flags.
            accel_tau_s: _,
            accel_omega: _,
            motion_bias_gain: _,
            bias_q: _,
            motion_accuracy_var: _,
            heading_bias_gain: _,
            inv_rest_bias_tau: _,
            inv_mag_tau: _,
            inv_accel_tau2: _,
            heading_q: _,
            max_bias_rads: _,
            gyro_clip_rads: _,
            bias_estimation: _,
            rest_limits: _,
            mag_limits: _,
            mag_offset_max_ut: _,
            flags: _,
        } = self;
        write_tilt(w, tilt);
        let Bias { b, var } = bias;
        w.f64s(b);
        w.f64(*var);
        write_rest(w, rest);
        let Heading {
            delta_rad,
            valid,
            var_rad2,
        } = heading;
        w.f64(*delta_rad);
        w.bool(*valid);
        w.f64(*var_rad2);
        write_mag(w, mag);
        w.f64(*accel_elapsed_s);
        w.f64s(bias_corr);
        w.f64(*bias_elapsed_s);
        w.f64(*mag_elapsed_s);
        w.bool(*heading_init);
        w.f64(*dt_typ_s);
        w.f64s(gyro_prev);
        w.u8(*plateau_run);
        write_hard_iron(w, hard_iron);
        w.f64s(offset_applied_ut);
        w.f64s(offset_seen_ut);
        w.f64(*heading_drift_rads);
        w.bool(*drift_learning);
        w.f64(*clip_miss_rad);
    }

    /// Reads what [`write_state`](Self::write_state) wrote and checks it.
    pub(crate) fn read_state(&mut self, r: &mut Reader) -> Result<(), SnapshotError> {
        self.read_fields(r)?;
        self.check_restored()
    }

    fn read_fields(&mut self, r: &mut Reader) -> Result<(), SnapshotError> {
        let t = &mut self.tilt;
        r.f64s(&mut t.q_gyr)?;
        r.f64s(&mut t.q_inc)?;
        r.f64s(&mut t.avg)?;
        r.f64s(&mut t.avg_rate)?;
        r.f64s(&mut self.bias.b)?;
        self.bias.var = r.f64()?;
        let s = &mut self.rest;
        for v in [
            &mut s.gyro_mean,
            &mut s.accel_mean,
            &mut s.gyro_short,
            &mut s.accel_short,
            &mut s.gyro_short2,
            &mut s.accel_short2,
        ] {
            r.f64s(v)?;
        }
        s.vibration2 = r.f64()?;
        s.still_s = r.f64()?;
        self.heading.delta_rad = r.f64()?;
        self.heading.valid = r.bool()?;
        self.heading.var_rad2 = r.f64()?;
        let m = &mut self.mag;
        let mut v = [0.0; 2];
        r.f64s(&mut v)?;
        [m.ref_norm_ut, m.ref_dip_rad] = v;
        m.ref_valid = r.bool()?;
        m.dip_trusted = r.bool()?;
        let mut v = [0.0; 4];
        r.f64s(&mut v)?;
        [m.norm_ut, m.dip_rad, m.undisturbed_s, m.rejected_s] = v;
        self.accel_elapsed_s = r.f64()?;
        r.f64s(&mut self.bias_corr)?;
        self.bias_elapsed_s = r.f64()?;
        self.mag_elapsed_s = r.f64()?;
        self.heading_init = r.bool()?;
        self.dt_typ_s = r.f64()?;
        r.f64s(&mut self.gyro_prev)?;
        self.plateau_run = r.u8()?;
        read_hard_iron(r, &mut self.hard_iron)?;
        r.f64s(&mut self.offset_applied_ut)?;
        r.f64s(&mut self.offset_seen_ut)?;
        self.heading_drift_rads = r.f64()?;
        self.drift_learning = r.bool()?;
        self.clip_miss_rad = r.f64()?;
        Ok(())
    }

    /// A restored state must be one a running filter can reach: finite, unit
    /// quaternions, values in range.
    fn check_restored(&self) -> Result<(), SnapshotError> {
        if !self.all_finite() {
            return Err(SnapshotError::Invalid("non-finite state"));
        }
        let t = &self.tilt;
        for q in [&t.q_gyr, &t.q_inc] {
            let n = q.iter().map(|c| c * c).sum::<f64>();
            if n.is_nan() || (n - 1.0).abs() >= UNIT_NORM_TOLERANCE {
                return Err(SnapshotError::Invalid("quaternion not unit"));
            }
        }
        if self.bias.b.iter().any(|b| b.abs() > self.max_bias_rads) || self.bias.var < 0.0 {
            return Err(SnapshotError::Invalid("gyroscope bias out of range"));
        }
        if self.heading.delta_rad.abs() > PI
            || !(0.0..=UNKNOWN_VAR_RAD2).contains(&self.heading.var_rad2)
        {
            return Err(SnapshotError::Invalid("heading out of range"));
        }
        if self.heading_drift_rads.abs() > MAX_HEADING_DRIFT_RADS {
            return Err(SnapshotError::Invalid("heading drift rate out of range"));
        }
        if self.accel_elapsed_s < 0.0 {
            return Err(SnapshotError::Invalid("state out of range"));
        }
        if !self.offset_in_range() {
            return Err(SnapshotError::Invalid("magnetometer offset out of range"));
        }
        if !self.physical() {
            return Err(SnapshotError::Invalid("state out of physical range"));
        }
        Ok(())
    }

    /// The offset and the field it was seen through within `mag_offset_max_ut`, its
    /// covariance symmetric with a diagonal within (0, max²], the anchor a reading
    /// within the input limit with a unit strapdown, non-negative timers.
    fn offset_in_range(&self) -> bool {
        let h = &self.hard_iron;
        let max = self.mag_offset_max_ut;
        let max_var = (max * max).max(hard_iron::MIN_VAR_UT2);
        let within = |v: &[f64], max: f64| v.iter().all(|x| x.is_finite() && x.abs() <= max);
        let q2 = h.anchor_q.iter().map(|c| c * c).sum::<f64>();
        within(&h.b, max)
            && within(&self.offset_applied_ut, max)
            && within(&self.offset_seen_ut, max)
            && within(&h.anchor_ut, MAX_MAG_UT)
            && (0..3).all(|i| {
                (hard_iron::MIN_VAR_UT2..=max_var).contains(&h.p[i][i])
                    && (0..3).all(|j| h.p[i][j].is_finite() && h.p[i][j] == h.p[j][i])
            })
            && (q2 - 1.0).abs() < UNIT_NORM_TOLERANCE
            && (0.0..=f64::MAX).contains(&h.anchor_age_s)
            && (0.0..=f64::MAX).contains(&h.unpredicted_s)
            && (0.0..=1.0).contains(&h.refused_share)
    }

    fn all_finite(&self) -> bool {
        let (t, s, m) = (&self.tilt, &self.rest, &self.mag);
        [
            t.avg,
            t.avg_rate,
            self.bias.b,
            s.gyro_mean,
            s.accel_mean,
            s.gyro_short,
            s.accel_short,
            s.gyro_short2,
            s.accel_short2,
            self.gyro_prev,
        ]
        .iter()
        .flatten()
        .chain(&[
            s.still_s,
            self.heading.delta_rad,
            self.heading.var_rad2,
            m.ref_norm_ut,
            m.ref_dip_rad,
            m.norm_ut,
            m.dip_rad,
            m.undisturbed_s,
            m.rejected_s,
            self.accel_elapsed_s,
            self.bias.var,
            self.dt_typ_s,
            self.heading_drift_rads,
        ])
        .all(|x| x.is_finite())
    }

    /// Physical ranges: means of readings within the door's limits, a rate of the
    /// averaged acceleration no faster than the door's largest change per short
    /// sample, field magnitudes and dip angles, non-negative timers.
    fn physical(&self) -> bool {
        let a = MAX_ACCEL_NORM_MPS2;
        let w_max = MAX_GYRO_RADS * 3f64.sqrt();
        let m_max = MAX_MAG_UT * 3f64.sqrt();
        let within = |v: &[f64], max: f64| v.iter().all(|x| x.abs() <= max);
        let (t, s, m) = (&self.tilt, &self.rest, &self.mag);
        within(&t.avg, tilt::MAX_AVG_MPS2)
            && within(&t.avg_rate, tilt::MAX_AVG_RATE_MPS3)
            && within(&s.gyro_mean, w_max)
            && within(&s.accel_mean, a)
            && within(&s.gyro_short, w_max)
            && within(&s.accel_short, a)
            && within(&s.gyro_short2, w_max)
            && within(&s.accel_short2, a)
            && (0.0..=4.0 * a * a).contains(&s.vibration2)
            && within(&self.gyro_prev, MAX_GYRO_RADS)
            && self.dt_typ_s >= 0.0
            && within(&self.bias_corr, MAX_STORED_CORRECTION)
            && self.bias.var <= MAX_STORED_CORRECTION
            && s.still_s >= 0.0
            && (0.0..=m_max).contains(&m.ref_norm_ut)
            && (0.0..=m_max).contains(&m.norm_ut)
            && m.ref_dip_rad.abs() <= PI
            && m.dip_rad.abs() <= PI
            && m.undisturbed_s >= 0.0
            && m.rejected_s >= 0.0
            && (0.0..=f64::MAX).contains(&self.clip_miss_rad)
            && self.bias_elapsed_s >= 0.0
            && self.mag_elapsed_s >= 0.0
    }
}

fn write_tilt(w: &mut Writer, t: &Tilt) {
    let Tilt {
        q_gyr,
        q_inc,
        avg,
        avg_rate,
    } = t;
    w.f64s(q_gyr);
    w.f64s(q_inc);
    w.f64s(avg);
    w.f64s(avg_rate);
}

fn write_rest(w: &mut Writer, r: &Rest) {
    let Rest {
        gyro_mean,
        accel_mean,
        gyro_short,
        accel_short,
        gyro_short2,
        accel_short2,
        vibration2,
        still_s,
    } = r;
    for v in [
        gyro_mean,
        accel_mean,
        gyro_short,
        accel_short,
        gyro_short2,
        accel_short2,
    ] {
        w.f64s(v);
    }
    w.f64(*vibration2);
    w.f64(*still_s);
}

fn write_mag(w: &mut Writer, m: &MagDisturbance) {
    let MagDisturbance {
        ref_norm_ut,
        ref_dip_rad,
        ref_valid,
        dip_trusted,
        norm_ut,
        dip_rad,
        undisturbed_s,
        rejected_s,
    } = m;
    w.f64s(&[*ref_norm_ut, *ref_dip_rad]);
    w.bool(*ref_valid);
    w.bool(*dip_trusted);
    w.f64s(&[*norm_ut, *dip_rad, *undisturbed_s, *rejected_s]);
}

fn write_hard_iron(w: &mut Writer, h: &HardIron) {
    let HardIron {
        b,
        p,
        anchor_ut,
        anchor_q,
        anchored,
        anchor_age_s,
        unpredicted_s,
        refused_share,
    } = h;
    w.f64s(b);
    for row in p {
        w.f64s(row);
    }
    w.f64s(anchor_ut);
    w.f64s(anchor_q);
    w.bool(*anchored);
    w.f64(*anchor_age_s);
    w.f64(*unpredicted_s);
    w.f64(*refused_share);
}

/// Reads what [`write_hard_iron`] wrote, in the same order (checked with the rest in
/// `offset_in_range`).
fn read_hard_iron(r: &mut Reader, h: &mut HardIron) -> Result<(), SnapshotError> {
    r.f64s(&mut h.b)?;
    for row in h.p.iter_mut() {
        r.f64s(row)?;
    }
    r.f64s(&mut h.anchor_ut)?;
    r.f64s(&mut h.anchor_q)?;
    h.anchored = r.bool()?;
    h.anchor_age_s = r.f64()?;
    h.unpredicted_s = r.f64()?;
    h.refused_share = r.f64()?;
    Ok(())
}
