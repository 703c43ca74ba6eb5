//! Snapshot of the [`WalkingDirection`] inside the navigator's: every nested state is
//! destructured without `..` (a field left out is a compile error) and read back into
//! named fields, checked against the bounds the engine keeps.

use super::calibration::CalibrationFilter;
use super::carrying::Carrying;
use super::gap::GapBridge;
use super::hard_iron::HardIron;
use super::history::{AttitudeHistory, Slot, HISTORY_SLOTS};
use super::magnetic::{FieldReference, YawCorrection};
use super::stride::{Stride, StrideStats};
use super::tilt::TiltCorrection;
use super::WalkingDirection;
use crate::input::limits::{
    MAX_ABS_T_S, MAX_ACCEL_NORM_MPS2, MAX_GYRO_RADS, MAX_MAG_UT, MAX_TIME_JUMP_S,
};
use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};

/// Bounds of a restored state: angles (wrapped, generously), μ's drift rate, rad/s,
/// the learned dip, rad, the leaky vertical velocity, m/s, ...
const MAX_ANGLE_RAD: f64 = 100.0;
const MAX_RATE_RADS: f64 = 1.0;
const MAX_DIP_RAD: f64 = 4.0;
const MAX_VZ_MPS: f64 = 1e3;
/// ... counts (strides averaged, samples in a slot), the calibration covariance,
/// the hard-iron sums (bounded by forgetting), low-passed unit vectors, ...
const MAX_COUNT: f64 = 1e9;
const MAX_COVARIANCE: f64 = 1e6;
const MAX_HARD_IRON_SUM: f64 = 1e20;
const MAX_UNIT: f64 = 1.5;
/// ... the samples of one stride and their sums, and the quaternion's norm error.
const MAX_STRIDE_SAMPLES: f64 = 1e7;
const MAX_STRIDE_SUM: f64 = 1e12;
const MAX_QUATERNION_NORM_ERROR: f64 = 1e-6;
/// A slot's rows are sums of `n` unit-vector components (with rounding).
const SLOT_ROWS_MARGIN: f64 = 1.01;

fn within(xs: &[f64], max: f64) -> bool {
    xs.iter().all(|x| x.abs() <= max)
}

fn bools<const N: usize>(r: &mut Reader) -> Result<[bool; N], SnapshotError> {
    let mut b = [false; N];
    for x in b.iter_mut() {
        *x = r.bool()?;
    }
    Ok(b)
}

fn time_ok(t: f64) -> bool {
    t.abs() <= MAX_ABS_T_S + 1.0
}

fn f64s<const N: usize>(r: &mut Reader) -> Result<[f64; N], SnapshotError> {
    let mut v = [0.0; N];
    r.f64s(&mut v)?;
    Ok(v)
}

impl WalkingDirection {
    pub(crate) fn write(&self, w: &mut Writer) {
        let WalkingDirection {
            azimuth_rad,
            known,
            q,
            tilt: TiltCorrection { mean_force_enu },
            yaw:
                YawCorrection {
                    mu_rad,
                    mu_rate_rads,
                    mu_known,
                    mag_seen,
                    gyro_calibrated,
                    field:
                        FieldReference {
                            strength_ut,
                            dip_rad,
                            known: field_known,
                        },
                    hard_iron: HardIron { sums, h_ut },
                },
            carrying:
                Carrying {
                    forward_body,
                    forward_known,
                    calibrated,
                    axis_strides,
                    up_fast,
                    up_slow,
                    up_known,
                },
            calibration:
                CalibrationFilter {
                    offset_var,
                    cross_cov,
                    rate_var,
                },
            stride:
                Stride {
                    sums: stride,
                    steps,
                    vz_mps,
                },
            history: AttitudeHistory { slots },
            gaps,
            last_t_s,
            last_stride_t_s,
        } = self;
        w.f64s(&[
            *azimuth_rad,
            *mu_rad,
            *mu_rate_rads,
            *strength_ut,
            *dip_rad,
            *vz_mps,
            *last_t_s,
            *last_stride_t_s,
        ]);
        w.f64s(mean_force_enu);
        w.f64s(&[*offset_var, *cross_cov, *rate_var]);
        w.f64s(sums);
        w.f64s(h_ut);
        w.f64s(forward_body);
        w.f64s(up_fast);
        w.f64s(up_slow);
        w.f64s(q);
        write_stride(w, stride);
        for b in [
            known,
            mu_known,
            mag_seen,
            field_known,
            forward_known,
            calibrated,
            up_known,
            gyro_calibrated,
        ] {
            w.bool(*b);
        }
        w.u64(*steps as u64);
        w.f64(*axis_strides);
        w.u64(slots.len() as u64);
        for s in slots.iter() {
            let Slot {
                t0_s,
                t1_s,
                rows,
                n,
                mu_rad,
            } = s;
            w.f64s(&[t0_s, t1_s, n, mu_rad]);
            w.f64s(&rows);
        }
        write_gaps(w, gaps);
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let [azimuth_rad, mu_rad, mu_rate_rads, strength_ut, dip_rad, vz_mps] = f64s(r)?;
        // NaN before the first sample / stride.
        let last_t_s = r.f64_or_nan()?;
        let last_stride_t_s = r.f64_or_nan()?;
        let mean_force_enu = f64s(r)?;
        let [offset_var, cross_cov, rate_var] = f64s(r)?;
        let hard_iron = HardIron {
            sums: f64s(r)?,
            h_ut: f64s(r)?,
        };
        let forward_body = f64s(r)?;
        let up_fast = f64s(r)?;
        let up_slow = f64s(r)?;
        let q: [f64; 4] = f64s(r)?;
        let stride = read_stride(r)?;
        let [known, mu_known, mag_seen, field_known, forward_known, calibrated, up_known, gyro_calibrated] =
            bools(r)?;
        let steps = r.len(2)? as u32;
        let axis_strides = r.f64()?;
        let slots = read_history(r)?;
        let gaps = read_gaps(r)?;
        let qn = q.iter().map(|x| x * x).sum::<f64>();
        if (qn - 1.0).abs() >= MAX_QUATERNION_NORM_ERROR {
            return Err(SnapshotError::Invalid("walking direction orientation"));
        }
        let mag_max = MAX_MAG_UT * 3f64.sqrt();
        let checks = [
            within(&[azimuth_rad, mu_rad], MAX_ANGLE_RAD),
            mu_rate_rads.abs() <= MAX_RATE_RADS,
            (0.0..=mag_max).contains(&strength_ut),
            dip_rad.abs() <= MAX_DIP_RAD,
            vz_mps.abs() <= MAX_VZ_MPS,
            [last_t_s, last_stride_t_s]
                .iter()
                .all(|t| t.is_nan() || time_ok(*t)),
            (0.0..=MAX_COUNT).contains(&axis_strides),
            within(&mean_force_enu, MAX_ACCEL_NORM_MPS2),
            offset_var >= 0.0
                && rate_var >= 0.0
                && within(&[offset_var, cross_cov, rate_var], MAX_COVARIANCE),
            within(&hard_iron.sums, MAX_HARD_IRON_SUM) && within(&hard_iron.h_ut, mag_max),
            within(&forward_body, MAX_UNIT)
                && within(&up_fast, MAX_UNIT)
                && within(&up_slow, MAX_UNIT),
            (0.0..=MAX_STRIDE_SAMPLES).contains(&stride.n) && stride_sums_ok(&stride),
        ];
        if !checks.iter().all(|ok| *ok) {
            return Err(SnapshotError::Invalid("walking direction state"));
        }
        Ok(Self {
            azimuth_rad,
            known,
            q,
            tilt: TiltCorrection { mean_force_enu },
            yaw: YawCorrection {
                mu_rad,
                mu_rate_rads,
                mu_known,
                mag_seen,
                gyro_calibrated,
                field: FieldReference {
                    strength_ut,
                    dip_rad,
                    known: field_known,
                },
                hard_iron,
            },
            carrying: Carrying {
                forward_body,
                forward_known,
                calibrated,
                axis_strides,
                up_fast,
                up_slow,
                up_known,
            },
            calibration: CalibrationFilter {
                offset_var,
                cross_cov,
                rate_var,
            },
            stride: Stride {
                sums: stride,
                steps,
                vz_mps,
            },
            history: AttitudeHistory { slots },
            gaps,
            last_t_s,
            last_stride_t_s,
        })
    }
}

fn write_gaps(w: &mut Writer, g: &GapBridge) {
    let GapBridge {
        dt_typ_s,
        rate_up_rads,
        field,
        field_slow,
        pending_t_s,
        before,
        after,
        gyro_err_rad,
        gyro_var_rad2,
    } = *g;
    w.f64s(&[dt_typ_s, rate_up_rads, gyro_err_rad, gyro_var_rad2]);
    w.f64s(&field);
    w.f64s(&field_slow);
    w.f64s(&before);
    w.f64s(&after);
    w.f64(pending_t_s);
}

/// The gap bridge: an interval, a rate, an angle and its variance, means of unit
/// vectors (the field's weight 0 or 1), sums of `count` unit vectors, a time or NaN.
fn read_gaps(r: &mut Reader) -> Result<GapBridge, SnapshotError> {
    let [dt_typ_s, rate_up_rads, gyro_err_rad, gyro_var_rad2] = f64s(r)?;
    let field: [f64; 3] = f64s(r)?;
    let field_slow: [f64; 2] = f64s(r)?;
    let before: [f64; 3] = f64s(r)?;
    let after: [f64; 3] = f64s(r)?;
    let pending_t_s = r.f64_or_nan()?;
    let ok = (0.0..=MAX_TIME_JUMP_S).contains(&dt_typ_s)
        && rate_up_rads.abs() <= MAX_GYRO_RADS * 3f64.sqrt()
        && gyro_err_rad.abs() <= MAX_ANGLE_RAD
        && (0.0..=MAX_COVARIANCE).contains(&gyro_var_rad2)
        && within(&field[..2], MAX_UNIT)
        && (0.0..=1.0).contains(&field[2])
        && within(&field_slow, MAX_UNIT)
        && within(&before[..2], MAX_UNIT)
        && (0.0..=MAX_COVARIANCE).contains(&before[2])
        && (0.0..=MAX_COUNT).contains(&after[2])
        && within(&after[..2], after[2] * SLOT_ROWS_MARGIN)
        && (pending_t_s.is_nan() || time_ok(pending_t_s));
    if !ok {
        return Err(SnapshotError::Invalid("walking direction gap bridge"));
    }
    Ok(GapBridge {
        dt_typ_s,
        rate_up_rads,
        field,
        field_slow,
        pending_t_s,
        before,
        after,
        gyro_err_rad,
        gyro_var_rad2,
    })
}

fn write_stride(w: &mut Writer, s: &StrideStats) {
    let StrideStats {
        n,
        se,
        sn,
        see,
        snn,
        sen,
        svz,
        sevz,
        snvz,
    } = *s;
    w.f64s(&[n, se, sn, see, snn, sen, svz, sevz, snvz]);
}

fn read_stride(r: &mut Reader) -> Result<StrideStats, SnapshotError> {
    let [n, se, sn, see, snn, sen, svz, sevz, snvz] = f64s(r)?;
    Ok(StrideStats {
        n,
        se,
        sn,
        see,
        snn,
        sen,
        svz,
        sevz,
        snvz,
    })
}

fn stride_sums_ok(s: &StrideStats) -> bool {
    within(
        &[s.se, s.sn, s.see, s.snn, s.sen, s.svz, s.sevz, s.snvz],
        MAX_STRIDE_SUM,
    )
}

/// The attitude history: slots of n ≥ 1 samples within the time limits, their rows
/// sums of n unit-vector components, their μ an angle.
fn read_history(r: &mut Reader) -> Result<Ring<Slot, HISTORY_SLOTS>, SnapshotError> {
    let mut slots = Ring::new();
    for _ in 0..r.len(HISTORY_SLOTS)? {
        let [t0_s, t1_s, n, mu_rad] = f64s(r)?;
        let rows: [f64; 6] = f64s(r)?;
        if !(time_ok(t0_s)
            && time_ok(t1_s)
            && (1.0..=MAX_COUNT).contains(&n)
            && mu_rad.abs() <= MAX_ANGLE_RAD)
            || rows.iter().any(|x| x.abs() > n * SLOT_ROWS_MARGIN)
        {
            return Err(SnapshotError::Invalid("walking direction history"));
        }
        slots.push(Slot {
            t0_s,
            t1_s,
            rows,
            n,
            mu_rad,
        });
    }
    Ok(slots)
}
