//! Snapshot and restore of the [`StepLengthEstimator`]: model, configuration, the
//! fixes and steps waiting for a calibration sample, the regression, versioned and
//! checksummed. The estimator and its configuration are destructured exhaustively
//! when written, so a field that is not serialised is a compile error.

use super::*;

impl StepLengthEstimator {
    /// The whole state as bytes (versioned, checksummed): the per-user calibration
    /// survives an app restart.
    pub fn snapshot(&self) -> Vec<u8> {
        // Exhaustive on purpose: a new field must be written (and read back below).
        let StepLengthEstimator {
            model,
            config,
            fixes,
            last_step_t_s,
            bout,
            last_f_hz,
            pending,
            block,
            block_len,
            reg,
            published,
            feature_sum,
            samples,
            fits,
            rejected_blocks,
            converged,
        } = self;
        let mut w = Writer::new(SNAPSHOT_KIND, SNAPSHOT_VERSION);
        w.u8(model.code());
        write_config(&mut w, config);
        w.u64(fixes.len() as u64);
        for Fix {
            t_s,
            east_m,
            north_m,
            good,
        } in fixes.iter()
        {
            w.f64s(&[t_s, east_m, north_m]);
            w.bool(good);
        }
        w.opt_f64(*last_step_t_s);
        w.u8(bout.code());
        w.f64(*last_f_hz);
        w.u64(pending.len() as u64);
        for s in pending.iter() {
            write_rec(&mut w, &s);
        }
        w.u64(*block_len as u64);
        for s in &block[..*block_len] {
            write_rec(&mut w, s);
        }
        reg.write(&mut w);
        published.write(&mut w);
        w.f64s(feature_sum);
        w.u64(*samples);
        w.u64(*fits as u64);
        w.u64(*rejected_blocks);
        w.bool(*converged);
        w.finish()
    }

    /// An estimator continuing exactly where the snapshot was taken.
    pub fn restore(bytes: &[u8]) -> Result<Self, StepLengthError> {
        let (mut r, _version) = Reader::new(bytes, SNAPSHOT_KIND, SNAPSHOT_VERSION)?;
        let model = StepLengthModel::from_code(r.u8()?)
            .ok_or(SnapshotError::Invalid("step-length model"))?;
        let config = read_config(&mut r)?;
        config
            .validate()
            .map_err(|_| SnapshotError::Invalid("configuration"))?;
        let mut s = Self::new(model, config)?;
        for _ in 0..r.len(FIXES)? {
            let mut v = [0.0; 3];
            r.f64s(&mut v)?;
            let good = r.bool()?;
            if !v.iter().all(|x| x.is_finite()) {
                return Err(SnapshotError::Invalid("fix").into());
            }
            s.fixes.push(Fix {
                t_s: v[0],
                east_m: v[1],
                north_m: v[2],
                good,
            });
        }
        s.last_step_t_s = r.opt_f64()?;
        s.bout = BoutPosition::from_code(r.u8()?).ok_or(SnapshotError::Invalid("bout position"))?;
        // NaN before the first step with a frequency.
        s.last_f_hz = r.f64_or_nan()?;
        for _ in 0..r.len(PENDING)? {
            s.pending.push(read_rec(&mut r)?);
        }
        s.block_len = r.len(BLOCK_STEPS)?;
        for i in 0..s.block_len {
            s.block[i] = read_rec(&mut r)?;
        }
        s.reg = Regression::read(&mut r)?;
        s.published = PublishedFit::read(&mut r)?;
        r.f64s(&mut s.feature_sum)?;
        s.samples = r.u64()?;
        s.fits = r.len(u32::MAX as usize)? as u32;
        s.rejected_blocks = r.u64()?;
        s.converged = r.bool()?;
        r.end()?;
        Ok(s)
    }
}

fn write_rec(w: &mut Writer, s: &StepRec) {
    let StepRec {
        t_s,
        f_hz,
        sv,
        w: weinberg,
        sqrt_h,
        east_m,
        north_m,
    } = s;
    w.f64s(&[*t_s, *f_hz, *sv, *weinberg, *sqrt_h, *east_m, *north_m]);
}

fn read_rec(r: &mut Reader) -> Result<StepRec, SnapshotError> {
    let mut v = [0.0; 7];
    v[0] = r.f64()?;
    // Frequency and the step's features are NaN for a step without them.
    for x in &mut v[1..5] {
        *x = r.f64_or_nan()?;
    }
    v[5] = r.f64()?;
    v[6] = r.f64()?;
    Ok(StepRec {
        t_s: v[0],
        f_hz: v[1],
        sv: v[2],
        w: v[3],
        sqrt_h: v[4],
        east_m: v[5],
        north_m: v[6],
    })
}

fn write_config(w: &mut Writer, c: &StepLengthConfig) {
    // Exhaustive on purpose: a new setting must be added to the snapshot.
    let StepLengthConfig {
        max_accuracy_m,
        max_fix_gap_s,
        max_fix_speed_mps,
        max_step_gap_s,
        max_detour_ratio,
        min_step_length_m,
        max_step_length_m,
        prior_a,
        prior_a_sigma,
        prior_b,
        prior_b_sigma,
        prior_c,
        prior_c_sigma,
        prior_step_length_m,
        prior_step_length_sigma_m,
        prior_weinberg_k,
        prior_weinberg_k_sigma,
        prior_pendulum_k,
        prior_pendulum_k_sigma,
        sample_sigma_m,
        converged_rel_sigma,
        min_fits,
        freeze_when_converged,
    } = c;
    w.f64s(&[
        *max_accuracy_m,
        *max_fix_gap_s,
        *max_fix_speed_mps,
        *max_step_gap_s,
        *max_detour_ratio,
        *min_step_length_m,
        *max_step_length_m,
        *prior_a,
        *prior_a_sigma,
        *prior_b,
        *prior_b_sigma,
        *prior_c,
        *prior_c_sigma,
        *prior_step_length_m,
        *prior_step_length_sigma_m,
        *prior_weinberg_k,
        *prior_weinberg_k_sigma,
        *prior_pendulum_k,
        *prior_pendulum_k_sigma,
        *sample_sigma_m,
        *converged_rel_sigma,
    ]);
    w.u64(*min_fits as u64);
    w.bool(*freeze_when_converged);
}

fn read_config(r: &mut Reader) -> Result<StepLengthConfig, SnapshotError> {
    let mut v = [0.0; 21];
    r.f64s(&mut v)?;
    let min_fits = r.len(u32::MAX as usize)? as u32;
    let freeze_when_converged = r.bool()?;
    Ok(StepLengthConfig {
        max_accuracy_m: v[0],
        max_fix_gap_s: v[1],
        max_fix_speed_mps: v[2],
        max_step_gap_s: v[3],
        max_detour_ratio: v[4],
        min_step_length_m: v[5],
        max_step_length_m: v[6],
        prior_a: v[7],
        prior_a_sigma: v[8],
        prior_b: v[9],
        prior_b_sigma: v[10],
        prior_c: v[11],
        prior_c_sigma: v[12],
        prior_step_length_m: v[13],
        prior_step_length_sigma_m: v[14],
        prior_weinberg_k: v[15],
        prior_weinberg_k_sigma: v[16],
        prior_pendulum_k: v[17],
        prior_pendulum_k_sigma: v[18],
        sample_sigma_m: v[19],
        converged_rel_sigma: v[20],
        min_fits,
        freeze_when_converged,
    })
}
