//! Snapshot and restore of the [`PaceTracker`]: the configuration, the frame, the
//! input streams' state, the filter and the raw-accelerometer steps (detector and step-length model), versioned and
//! checksummed. The tracker and its configuration are destructured exhaustively and
//! `restore` builds them field by field, so a field that is not serialised is a
//! compile error.

use super::*;

impl PaceTracker {
    /// The whole state as bytes (versioned, checksummed), for an app killed by the OS.
    pub fn snapshot(&self) -> Vec<u8> {
        // Exhaustive on purpose: a new field must be written; `restore` builds the
        // tracker field by field.
        let PaceTracker {
            config,
            frame,
            fix_time,
            step_time,
            held,
            steps,
            filter,
            accel,
            check,
        } = self;
        let mut w = Writer::new(SNAPSHOT_KIND, SNAPSHOT_VERSION);
        write_config(&mut w, config);
        crate::geo::write_frame(&mut w, frame.as_ref());
        fix_time.write(&mut w);
        step_time.write(&mut w);
        held.write(&mut w);
        steps.write(&mut w);
        match filter {
            Filter::Published(f) => f.write(&mut w),
            Filter::Adaptive(f) => f.write(&mut w),
        }
        match accel {
            Some(a) => {
                w.bool(true);
                a.write(&mut w);
            }
            None => w.bool(false),
        }
        check.write(&mut w);
        w.finish()
    }

    /// A tracker continuing exactly where the snapshot was taken.
    pub fn restore(bytes: &[u8]) -> Result<Self, PaceError> {
        // The reader refuses any other version than this build writes.
        let (mut r, _) = Reader::new(bytes, SNAPSHOT_KIND, SNAPSHOT_VERSION)?;
        let config = read_config(&mut r)?;
        config
            .validate()
            .map_err(|_| SnapshotError::Invalid("configuration"))?;
        let frame = crate::geo::read_frame(&mut r)?;
        let fix_time = TimeGuard::read(&mut r, InputStream::Gnss)?;
        let step_time = TimeGuard::read(&mut r, InputStream::Steps)?;
        let held = Held::read(
            &mut r,
            |f| f.t_s.abs() <= input::limits::MAX_ABS_T_S && input::gnss_fix(f).is_ok(),
            |s| StepStream::new().check(s).is_ok(),
        )?;
        let steps = StepStream::read(&mut r)?;
        let filter = match config.mode {
            PaceMode::AsPublished => {
                Filter::Published(published::PublishedFilter::read(&mut r, &config)?)
            }
            PaceMode::Adaptive => {
                Filter::Adaptive(adaptive::AdaptiveFilter::read(&mut r, &config)?)
            }
        };
        let accel = if r.bool()? {
            let imported = config.calibration.and_then(|c| c.accel_model);
            Some(AccelSteps::read(&mut r, imported.as_ref())?)
        } else {
            None
        };
        let check = CrossCheck::read(&mut r)?;
        r.end()?;
        Ok(Self {
            config,
            frame,
            fix_time,
            step_time,
            held,
            steps,
            filter,
            accel,
            check,
        })
    }
}

fn write_config(w: &mut Writer, c: &PaceConfig) {
    // Exhaustive on purpose: a new setting must be added to the snapshot.
    let PaceConfig {
        mode,
        initial_step_length_m,
        stationary_after_s,
        calibration,
        published,
        adaptive,
    } = c;
    w.u8(match mode {
        PaceMode::AsPublished => 0,
        PaceMode::Adaptive => 1,
    });
    w.opt_f64(*initial_step_length_m);
    w.f64(*stationary_after_s);
    match calibration {
        Some(PaceCalibration {
            step_length_m,
            cadence_spm,
            slope_m_per_spm,
            step_length_std_m,
            accel_model,
        }) => {
            w.bool(true);
            w.f64s(&[
                *step_length_m,
                *cadence_spm,
                *slope_m_per_spm,
                *step_length_std_m,
            ]);
            match accel_model {
                Some(AccelStepModel {
                    a_m_s,
                    b_m_per_m2ps4,
                    c_m,
                    ref_frequency_hz,
                    ref_variance_m2ps4,
                    a_std_m_s,
                    b_std_m_per_m2ps4,
                    length_std_m,
                }) => {
                    w.bool(true);
                    w.f64s(&[
                        *a_m_s,
                        *b_m_per_m2ps4,
                        *c_m,
                        *ref_frequency_hz,
                        *ref_variance_m2ps4,
                        *a_std_m_s,
                        *b_std_m_per_m2ps4,
                        *length_std_m,
                    ]);
                }
                None => w.bool(false),
            }
        }
        None => w.bool(false),
    }
    let PublishedParams {
        window_n,
        cadence_h,
        variance_threshold_m2,
        sigmoid_beta_per_m2,
        ema_alpha,
    } = published;
    w.u64(*window_n as u64);
    w.u64(*cadence_h as u64);
    w.f64s(&[*variance_threshold_m2, *sigmoid_beta_per_m2, *ema_alpha]);
    let AdaptiveParams {
        accel_noise_mps2,
        turn_accel_noise_mps2,
        default_gnss_sigma_m,
        gnss_bias_sigma_m,
        gnss_bias_tau_s,
        pedometer_rel_sigma,
        outage_reset_s,
        learn_max_accuracy_m,
        step_length_rw_m_per_sqrt_s,
    } = adaptive;
    w.f64s(&[
        *accel_noise_mps2,
        *turn_accel_noise_mps2,
        *default_gnss_sigma_m,
        *gnss_bias_sigma_m,
        *gnss_bias_tau_s,
        *pedometer_rel_sigma,
        *outage_reset_s,
        *learn_max_accuracy_m,
        *step_length_rw_m_per_sqrt_s,
    ]);
}

fn read_config(r: &mut Reader) -> Result<PaceConfig, SnapshotError> {
    let mode = match r.u8()? {
        0 => PaceMode::AsPublished,
        1 => PaceMode::Adaptive,
        _ => return Err(SnapshotError::Invalid("mode")),
    };
    let initial_step_length_m = r.opt_f64()?;
    let stationary_after_s = r.f64()?;
    let calibration = if r.bool()? {
        let mut k = [0.0; 4];
        r.f64s(&mut k)?;
        let accel_model = if r.bool()? {
            let mut v = [0.0; 8];
            r.f64s(&mut v)?;
            Some(AccelStepModel {
                a_m_s: v[0],
                b_m_per_m2ps4: v[1],
                c_m: v[2],
                ref_frequency_hz: v[3],
                ref_variance_m2ps4: v[4],
                a_std_m_s: v[5],
                b_std_m_per_m2ps4: v[6],
                length_std_m: v[7],
            })
        } else {
            None
        };
        Some(PaceCalibration {
            step_length_m: k[0],
            cadence_spm: k[1],
            slope_m_per_spm: k[2],
            step_length_std_m: k[3],
            accel_model,
        })
    } else {
        None
    };
    let window_n = r.len(published::MAX_WINDOW)?;
    let cadence_h = r.len(published::MAX_WINDOW)?;
    let mut p = [0.0; 3];
    r.f64s(&mut p)?;
    let mut a = [0.0; 9];
    r.f64s(&mut a)?;
    Ok(PaceConfig {
        mode,
        initial_step_length_m,
        stationary_after_s,
        calibration,
        published: PublishedParams {
            window_n,
            cadence_h,
            variance_threshold_m2: p[0],
            sigmoid_beta_per_m2: p[1],
            ema_alpha: p[2],
        },
        adaptive: AdaptiveParams {
            accel_noise_mps2: a[0],
            turn_accel_noise_mps2: a[1],
            default_gnss_sigma_m: a[2],
            gnss_bias_sigma_m: a[3],
            gnss_bias_tau_s: a[4],
            pedometer_rel_sigma: a[5],
            outage_reset_s: a[6],
            learn_max_accuracy_m: a[7],
            step_length_rw_m_per_sqrt_s: a[8],
        },
    })
}
