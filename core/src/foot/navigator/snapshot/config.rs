//! The foot navigator's configuration in its snapshot: every setting, the zero-velocity
//! detector as a tag and its settings (a shipped SVM model by tag only, another by its
//! text). The writers destructure without `..`: a new setting not written does not
//! compile.

use super::*;

pub(super) fn write_config(w: &mut Writer, c: &FootConfig) {
    // Exhaustive on purpose: a new setting must be added to the snapshot.
    let FootConfig {
        axis_remap,
        median_window,
        detector_window_s,
        gait_window_s,
        detector,
        alignment_s,
        gyro_bias_from_alignment,
        gyro_timing,
        initial_yaw_rad,
        correction,
        accel_noise_density,
        gyro_noise_density,
        accel_bias_walk,
        gyro_bias_walk,
        zupt_noise_mps,
        zupt_gate_nis,
        initial_accel_bias_std_mps2,
        initial_gyro_bias_std_rads,
        accel_range_mps2,
        gyro_range_rads,
        max_gap_s,
        min_swing_s,
        accel_alignment_rad,
        level_stride_max_grade,
    } = c;
    axis_remap.write(w);
    w.u64(*median_window as u64);
    w.f64s(&[
        *detector_window_s,
        *gait_window_s,
        *alignment_s,
        *initial_yaw_rad,
        *accel_noise_density,
        *gyro_noise_density,
        *accel_bias_walk,
        *gyro_bias_walk,
        *zupt_noise_mps,
        *initial_accel_bias_std_mps2,
        *initial_gyro_bias_std_rads,
        *max_gap_s,
        *min_swing_s,
    ]);
    w.bool(*gyro_bias_from_alignment);
    w.u8(match correction {
        Correction::Full => 0,
        Correction::AsPublished => 1,
    });
    w.opt_f64(*accel_range_mps2);
    w.opt_f64(*gyro_range_rads);
    // Version 2.
    w.u8(match gyro_timing {
        GyroTiming::Instantaneous => 0,
        GyroTiming::IntervalMean => 1,
    });
    // Version 4.
    w.opt_f64(*zupt_gate_nis);
    // Version 5.
    w.f64s(accel_alignment_rad);
    // Version 6.
    w.opt_f64(*level_stride_max_grade);
    write_detector(w, detector);
}

/// A fixed-threshold zero-velocity detector's four thresholds.
fn write_fixed(w: &mut Writer, t: &FixedThresholds) {
    let FixedThresholds {
        acc_dev_mps2,
        gyro_rads,
        acc_std_mps2,
        gyro_std_rads,
    } = t;
    w.f64s(&[*acc_dev_mps2, *gyro_rads, *acc_std_mps2, *gyro_std_rads]);
}

fn read_fixed(r: &mut Reader) -> Result<FixedThresholds, SnapshotError> {
    let mut t = [0.0; 4];
    r.f64s(&mut t)?;
    let [acc_dev_mps2, gyro_rads, acc_std_mps2, gyro_std_rads] = t;
    Ok(FixedThresholds {
        acc_dev_mps2,
        gyro_rads,
        acc_std_mps2,
        gyro_std_rads,
    })
}

/// The zero-velocity detector: a tag, then its settings (a shipped SVM model by tag
/// only, another by its text).
fn write_detector(w: &mut Writer, detector: &ZeroVelocityDetector) {
    match detector {
        ZeroVelocityDetector::Fixed(t) => {
            w.u8(0);
            write_fixed(w, t);
        }
        ZeroVelocityDetector::Adaptive(a) => {
            let AdaptiveThresholds {
                jog_peak_mps2,
                run_peak_mps2,
                walk,
                jog,
                run,
            } = a;
            w.u8(1);
            w.f64s(&[*jog_peak_mps2, *run_peak_mps2]);
            for t in [walk, jog, run] {
                write_fixed(w, t);
            }
        }
        ZeroVelocityDetector::Svm(m) if m.is_shipped() => {
            // The shipped model: a tag, not its 80 kB text.
            w.u8(4);
        }
        ZeroVelocityDetector::Svm(m) => {
            w.u8(2);
            w.bytes(m.to_text().as_bytes());
        }
        ZeroVelocityDetector::SvmAdaptive(d) => {
            let SvmAdaptive {
                svm,
                jog_peak_mps2,
                run_peak_mps2,
                jog,
                run,
            } = d;
            if svm.is_shipped() {
                w.u8(6);
            } else {
                w.u8(5);
                w.bytes(svm.to_text().as_bytes());
            }
            w.f64s(&[*jog_peak_mps2, *run_peak_mps2]);
            write_fixed(w, jog);
            write_fixed(w, run);
        }
        ZeroVelocityDetector::Shoe(d) => {
            let ShoeDetector {
                acc_noise_mps2,
                gyro_noise_rads,
                threshold,
            } = d;
            w.u8(3);
            w.f64s(&[*acc_noise_mps2, *gyro_noise_rads, *threshold]);
        }
        ZeroVelocityDetector::AdaptiveShoe(d) => {
            let AdaptiveShoe {
                shoe:
                    ShoeDetector {
                        acc_noise_mps2,
                        gyro_noise_rads,
                        threshold,
                    },
                ref_peak_mps2,
                exponent,
            } = d;
            // Version 2.
            w.u8(7);
            w.f64s(&[
                *acc_noise_mps2,
                *gyro_noise_rads,
                *threshold,
                *ref_peak_mps2,
                *exponent,
            ]);
        }
    }
}

pub(super) fn read_config(r: &mut Reader) -> Result<FootConfig, FootError> {
    let axis_remap = AxisRemap::read(r)?;
    let median_window = r.len(MAX_MEDIAN_WINDOW)?;
    let mut v = [0.0; 13];
    r.f64s(&mut v)?;
    let [detector_window_s, gait_window_s, alignment_s, initial_yaw_rad, accel_noise_density, gyro_noise_density, accel_bias_walk, gyro_bias_walk, zupt_noise_mps, initial_accel_bias_std_mps2, initial_gyro_bias_std_rads, max_gap_s, min_swing_s] =
        v;
    let gyro_bias_from_alignment = r.bool()?;
    let correction = match r.u8()? {
        0 => Correction::Full,
        1 => Correction::AsPublished,
        _ => return Err(SnapshotError::Invalid("correction").into()),
    };
    let accel_range_mps2 = r.opt_f64()?;
    let gyro_range_rads = r.opt_f64()?;
    let gyro_timing = match r.u8()? {
        0 => GyroTiming::Instantaneous,
        1 => GyroTiming::IntervalMean,
        _ => return Err(SnapshotError::Invalid("gyro timing").into()),
    };
    let zupt_gate_nis = r.opt_f64()?;
    let mut accel_alignment_rad = [0.0; 3];
    r.f64s(&mut accel_alignment_rad)?;
    let level_stride_max_grade = r.opt_f64()?;
    let detector = read_detector(r)?;
    Ok(FootConfig {
        axis_remap,
        median_window,
        detector_window_s,
        gait_window_s,
        detector,
        alignment_s,
        gyro_bias_from_alignment,
        gyro_timing,
        initial_yaw_rad,
        correction,
        accel_noise_density,
        gyro_noise_density,
        accel_bias_walk,
        gyro_bias_walk,
        zupt_noise_mps,
        zupt_gate_nis,
        initial_accel_bias_std_mps2,
        initial_gyro_bias_std_rads,
        accel_range_mps2,
        gyro_range_rads,
        max_gap_s,
        min_swing_s,
        accel_alignment_rad,
        level_stride_max_grade,
    })
}

/// What [`write_detector`] wrote.
fn read_detector(r: &mut Reader) -> Result<ZeroVelocityDetector, FootError> {
    let detector = match r.u8()? {
        0 => ZeroVelocityDetector::Fixed(read_fixed(r)?),
        1 => {
            let mut p = [0.0; 2];
            r.f64s(&mut p)?;
            ZeroVelocityDetector::Adaptive(AdaptiveThresholds {
                jog_peak_mps2: p[0],
                run_peak_mps2: p[1],
                walk: read_fixed(r)?,
                jog: read_fixed(r)?,
                run: read_fixed(r)?,
            })
        }
        2 => {
            let text = std::str::from_utf8(r.bytes()?)
                .map_err(|_| SnapshotError::Invalid("detector model text"))?;
            ZeroVelocityDetector::Svm(Arc::new(SvmModel::parse(text)?))
        }
        4 => ZeroVelocityDetector::Svm(SvmModel::shared_shipped()),
        tag @ (5 | 6) => {
            let svm = if tag == 6 {
                SvmModel::shared_shipped()
            } else {
                let text = std::str::from_utf8(r.bytes()?)
                    .map_err(|_| SnapshotError::Invalid("detector model text"))?;
                Arc::new(SvmModel::parse(text)?)
            };
            let mut p = [0.0; 2];
            r.f64s(&mut p)?;
            ZeroVelocityDetector::SvmAdaptive(SvmAdaptive {
                svm,
                jog_peak_mps2: p[0],
                run_peak_mps2: p[1],
                jog: read_fixed(r)?,
                run: read_fixed(r)?,
            })
        }
        3 => {
            let mut p = [0.0; 3];
            r.f64s(&mut p)?;
            ZeroVelocityDetector::Shoe(ShoeDetector {
                acc_noise_mps2: p[0],
                gyro_noise_rads: p[1],
                threshold: p[2],
            })
        }
        7 => {
            let mut p = [0.0; 5];
            r.f64s(&mut p)?;
            ZeroVelocityDetector::AdaptiveShoe(AdaptiveShoe {
                shoe: ShoeDetector {
                    acc_noise_mps2: p[0],
                    gyro_noise_rads: p[1],
                    threshold: p[2],
                },
                ref_peak_mps2: p[3],
                exponent: p[4],
            })
        }
        _ => return Err(SnapshotError::Invalid("detector kind").into()),
    };
    Ok(detector)
}
