//! The `FootNavigator` object.

use std::sync::{Arc, Mutex, MutexGuard};
use stridekit_core::foot as core;

use super::*;
use crate::packed::{self, ImuSample};

/// Foot-mounted inertial navigation: median pre-filter, zero-velocity detector,
/// strapdown mechanisation and a 15-state error-state Kalman filter with
/// zero-velocity updates. The first `alignmentS` seconds must be a rest. Safe to call
/// from several threads: calls are serialised and a batch is applied as a whole.
#[derive(Debug, uniffi::Object)]
pub struct FootNavigator {
    inner: Mutex<core::FootNavigator>,
}

impl FootNavigator {
    fn wrap(nav: core::FootNavigator) -> Arc<Self> {
        Arc::new(Self {
            inner: Mutex::new(nav),
        })
    }

    /// The core navigator; a mutex poisoned by an earlier panic is recovered (the
    /// panic was already reported as an error) instead of panicking again.
    fn lock(&self) -> MutexGuard<'_, core::FootNavigator> {
        crate::error::lock(&self.inner)
    }

    /// Push every sample under one lock, keeping the estimates `output` asks for.
    fn batch(
        &self,
        samples: impl Iterator<Item = core::FootSample>,
        capacity: usize,
        output: FootOutput,
    ) -> FootBatchResult {
        let mut nav = self.lock();
        let mut estimates = Vec::with_capacity(match output {
            FootOutput::All => capacity,
            FootOutput::StrideEnds | FootOutput::LatestOnly => 0,
        });
        let mut produced = 0i32;
        let mut rejected = Vec::new();
        // The core's batch loop; a panic in one sample (a core bug) refuses that
        // sample and the batch goes on.
        let accepted = stridekit_core::batch::each(
            samples,
            |e: core::FootEstimate| {
                produced = produced.saturating_add(1);
                match output {
                    FootOutput::All => estimates.push(e.into()),
                    FootOutput::StrideEnds if e.stride.is_some() => estimates.push(e.into()),
                    FootOutput::StrideEnds | FootOutput::LatestOnly => {}
                }
            },
            |r: stridekit_core::batch::Rejected<FootError>| {
                rejected.push(FootRejectedSample {
                    index: i32::try_from(r.index).unwrap_or(i32::MAX),
                    reason: r.error.to_string(),
                    error: r.error,
                })
            },
            |s| guard(|| Ok(nav.push(&s)?)),
        );
        let accepted = i32::try_from(accepted).unwrap_or(i32::MAX);
        FootBatchResult {
            accepted,
            produced,
            estimates,
            rejected,
            latest: nav.estimate().map(Into::into),
        }
    }
}

#[uniffi::export]
impl FootNavigator {
    /// A navigator with the given configuration; `FootException.InvalidConfig` (or
    /// `InvalidModel` for a bad custom SVM model) when it is not usable.
    #[uniffi::constructor]
    pub fn new(config: FootConfig) -> Result<Arc<Self>, FootError> {
        guard(|| Ok(Self::wrap(core::FootNavigator::new(config.try_into()?)?)))
    }

    /// A navigator continuing exactly where `snapshot()` was taken (same
    /// configuration, same state: bit-identical estimates from there on).
    #[uniffi::constructor]
    pub fn restore(snapshot: Vec<u8>) -> Result<Arc<Self>, FootError> {
        guard(|| Ok(Self::wrap(core::FootNavigator::restore(&snapshot)?)))
    }

    /// A navigator with the default configuration (identity axes, adaptive SHOE detector).
    #[uniffi::constructor]
    pub fn with_defaults() -> Arc<Self> {
        Self::wrap(
            core::FootNavigator::new(core::FootConfig::default())
                .expect("the core default configuration is valid"),
        )
    }

    /// The configuration the navigator runs with.
    pub fn config(&self) -> FootConfig {
        self.lock().config().clone().into()
    }

    /// Push one sample (its magnetometer fields are not used). Returns the estimate of
    /// the sample the pipeline finished (`delaySamples()` back), or null while filling
    /// or aligning. A rejected sample throws and changes nothing.
    pub fn push(&self, sample: ImuSample) -> Result<Option<FootEstimate>, FootError> {
        guard(|| Ok(self.lock().push(&sample.into())?.map(Into::into)))
    }

    /// Push one sample whose stance is known from outside (a pressure insole, data-set
    /// labels): the detector is bypassed for it. Otherwise like `push`.
    pub fn push_with_stance(
        &self,
        sample: ImuSample,
        stance: bool,
    ) -> Result<Option<FootEstimate>, FootError> {
        guard(|| {
            Ok(self
                .lock()
                .push_with_stance(&sample.into(), stance)?
                .map(Into::into))
        })
    }

    /// Push samples in time order (magnetometer fields not used). Rejected samples are
    /// skipped and reported by index; the others are processed as if pushed one by one.
    pub fn push_samples(&self, samples: Vec<ImuSample>, output: FootOutput) -> FootBatchResult {
        let n = samples.len();
        self.batch(samples.into_iter().map(Into::into), n, output)
    }

    /// Fast path: samples packed as 56-byte (6-axis) little-endian records of seven f64
    /// `t_s, accel_x, accel_y, accel_z (m/s²), gyro_x, gyro_y, gyro_z (rad/s)`, the
    /// 80-byte phone record without the magnetometer (`packFootSamples` builds them).
    /// Fails as a whole only if the length is not a multiple of 56; otherwise behaves
    /// like `pushSamples`.
    pub fn push_packed(
        &self,
        data: Vec<u8>,
        output: FootOutput,
    ) -> Result<FootBatchResult, FootError> {
        guard(|| {
            let samples = packed::imu6_samples(&data)
                .map_err(|reason| FootError::InvalidBuffer { reason })?;
            let n = samples.len();
            Ok(self.batch(samples, n, output))
        })
    }

    /// The newest estimate (null before the alignment is complete).
    pub fn estimate(&self) -> Option<FootEstimate> {
        self.lock().estimate().map(Into::into)
    }

    /// How many samples the estimates lag the newest input (median filter and
    /// detector windows are centred; 0 before alignment).
    pub fn delay_samples(&self) -> i32 {
        i32::try_from(self.lock().delay_samples()).unwrap_or(i32::MAX)
    }

    /// The alignment rest is over and samples are being integrated.
    pub fn is_aligned(&self) -> bool {
        self.lock().is_aligned()
    }

    /// Sample rate measured during alignment, Hz (0 before).
    pub fn sample_rate_hz(&self) -> f64 {
        self.lock().sample_rate_hz()
    }

    /// Times the divergence guard zeroed an absurd velocity (0 in normal use).
    pub fn divergence_resets(&self) -> i64 {
        i64::try_from(self.lock().divergence_resets()).unwrap_or(i64::MAX)
    }

    /// Gyroscope bias jumps taken: two consecutive still stances that agreed and that
    /// the bias estimate could not explain set the bias anew (docs/foot.md, "Gyroscope
    /// bias jumps"; 0 while the bias holds).
    pub fn bias_jumps(&self) -> i64 {
        i64::try_from(self.lock().bias_jumps()).unwrap_or(i64::MAX)
    }

    /// The accelerometer's ceiling in use, m/s²: samples at it count as clipped (their
    /// velocity is not trusted; the detector takes a clipped impact's peak from its
    /// flanks). 99 % of `config.accelRangeMps2` when the app set the range, else the
    /// lowest ceiling found in the data so far (the same value on one axis and sign
    /// reached again and again, nothing above it); null while no clipping has been
    /// seen and no range is set (docs/foot.md, "Accelerometer clipping").
    pub fn accel_ceiling_mps2(&self) -> Option<f64> {
        self.lock().accel_ceiling_mps2()
    }

    /// The whole state as bytes (configuration included; versioned, checksummed), to
    /// survive the app being killed; give them to `FootNavigator.restore`. With the
    /// SVM detector the model travels as text (a few hundred kB).
    pub fn snapshot(&self) -> Vec<u8> {
        self.lock().snapshot()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stridekit_core::ahrs::AxisRemap;

    fn rest(t_s: f64) -> ImuSample {
        ImuSample {
            t_s,
            accel_x_mps2: 0.0,
            accel_y_mps2: 0.0,
            accel_z_mps2: 9.81,
            gyro_x_rads: 0.0,
            gyro_y_rads: 0.0,
            gyro_z_rads: 0.0,
            mag_x_ut: None,
            mag_y_ut: None,
            mag_z_ut: None,
        }
    }

    #[test]
    fn config_round_trips_and_defaults_agree() {
        let d = foot_config_default();
        let core: core::FootConfig = d.clone().try_into().unwrap();
        assert_eq!(core, core::FootConfig::default());
        assert_eq!(FootConfig::from(core), d);
        for kind in [
            FootDetectorKind::Fixed,
            FootDetectorKind::Adaptive,
            FootDetectorKind::Svm,
            FootDetectorKind::SvmAdaptive,
            FootDetectorKind::Shoe,
            FootDetectorKind::AdaptiveShoe,
        ] {
            let det = foot_detector_default(kind);
            let c: core::ZeroVelocityDetector = det.clone().try_into().unwrap();
            assert_eq!(FootDetector::from(c), det);
        }
        // The record's literal defaults (used by Kotlin/Swift constructors).
        let t = core::FixedThresholds::WALK;
        assert_eq!(
            (t.acc_dev_mps2, t.gyro_rads, t.acc_std_mps2, t.gyro_std_rads),
            (2.0, 0.6, 2.4, 0.3)
        );
        let c = core::FootConfig::default();
        assert_eq!(c.axis_remap, AxisRemap::IDENTITY);
        assert_eq!(
            (
                c.median_window,
                c.detector_window_s,
                c.gait_window_s,
                c.alignment_s,
                c.gyro_bias_from_alignment,
                c.initial_yaw_rad
            ),
            (1, 0.025, 1.0, 0.25, true, 0.0)
        );
        assert_eq!(
            (
                c.accel_noise_density,
                c.gyro_noise_density,
                c.accel_bias_walk,
                c.gyro_bias_walk,
                c.zupt_noise_mps,
                c.initial_accel_bias_std_mps2,
                c.initial_gyro_bias_std_rads
            ),
            (0.035, 0.0006, 0.0001, 0.00001, 0.01, 0.1, 0.005)
        );
        assert_eq!(
            (
                c.accel_range_mps2,
                c.gyro_range_rads,
                c.max_gap_s,
                c.min_swing_s
            ),
            (None, None, 0.1, 0.1)
        );
    }

    #[test]
    fn custom_model_text_round_trips_and_bad_text_is_invalid_model() {
        let text = foot_shipped_svm_model();
        let det = FootDetector::Svm {
            model_text: Some(text),
        };
        let c: core::ZeroVelocityDetector = det.try_into().unwrap();
        // The shipped model given as text reads back as "the shipped model".
        assert_eq!(
            FootDetector::from(c),
            FootDetector::Svm { model_text: None }
        );
        let bad = FootConfig {
            detector: FootDetector::Svm {
                model_text: Some("not a model".into()),
            },
            ..foot_config_default()
        };
        assert!(matches!(
            FootNavigator::new(bad),
            Err(FootError::InvalidModel { .. })
        ));
    }

    #[test]
    fn bad_config_and_mirror_axes_are_invalid_config() {
        let mut c = foot_config_default();
        c.median_window = 4;
        assert!(matches!(
            FootNavigator::new(c),
            Err(FootError::InvalidConfig { field, .. }) if field == "median_window"
        ));
        let mut c = foot_config_default();
        c.axis_remap.negate_z = true;
        assert!(matches!(
            FootNavigator::new(c),
            Err(FootError::InvalidConfig { field, .. }) if field == "axis_remap"
        ));
        assert_eq!(
            AxisRemap::try_from(foot_axes_pyshoe()).unwrap(),
            core::FootConfig::pyshoe_axes()
        );
    }

    #[test]
    fn packed_and_records_agree_and_rejections_are_reported() {
        let mut samples: Vec<ImuSample> = (0..200).map(|i| rest(i as f64 * 0.005)).collect();
        samples[50].accel_y_mps2 = f64::NAN;
        samples[60].t_s = 0.0;
        let a = FootNavigator::with_defaults();
        let b = FootNavigator::with_defaults();
        let ra = a.push_samples(samples.clone(), FootOutput::All);
        let rb = b
            .push_packed(packed::pack_foot_samples(samples), FootOutput::All)
            .unwrap();
        assert_eq!(ra, rb);
        assert_eq!(ra.rejected.len(), 2);
        assert_eq!(ra.rejected[0].index, 50);
        assert!(matches!(ra.rejected[0].error, FootError::NonFinite { .. }));
        assert!(matches!(
            ra.rejected[1].error,
            FootError::TimeNotIncreasing { .. }
        ));
        assert!(a.is_aligned());
        assert_eq!(ra.produced as usize, ra.estimates.len());
        assert!(ra.produced > 100);
        assert_eq!(ra.latest, a.estimate());
        let only = FootNavigator::with_defaults()
            .push_packed(
                packed::pack_foot_samples((0..200).map(|i| rest(i as f64 * 0.005)).collect()),
                FootOutput::LatestOnly,
            )
            .unwrap();
        assert!(only.estimates.is_empty());
        assert!(only.produced >= ra.produced);
        assert!(matches!(
            a.push_packed(vec![0; 55], FootOutput::All),
            Err(FootError::InvalidBuffer { .. })
        ));
    }

    #[cfg(feature = "testing")]
    #[test]
    fn simulated_walk_matches_the_ffi_path_and_snapshots_resume() {
        use crate::testing::simulate_foot_walk;
        let sim = simulate_foot_walk(7, 1).unwrap();
        assert_eq!(sim.reference_rejected, 0);
        assert_eq!(
            sim.samples_packed.len(),
            sim.sample_count as usize * packed::IMU6_RECORD_BYTES
        );
        let nav = FootNavigator::with_defaults();
        let half =
            sim.samples_packed.len() / 2 / packed::IMU6_RECORD_BYTES * packed::IMU6_RECORD_BYTES;
        let a = nav
            .push_packed(sim.samples_packed[..half].to_vec(), FootOutput::LatestOnly)
            .unwrap();
        let restored = FootNavigator::restore(nav.snapshot()).unwrap();
        assert_eq!(restored.snapshot(), nav.snapshot());
        let rest = sim.samples_packed[half..].to_vec();
        let b = nav.push_packed(rest.clone(), FootOutput::All).unwrap();
        let c = restored.push_packed(rest, FootOutput::All).unwrap();
        assert_eq!(b, c);
        assert_eq!(a.produced + b.produced, sim.reference_produced);
        assert_eq!(b.latest, sim.reference_final);
        assert!(matches!(
            FootNavigator::restore(vec![1, 2, 3]),
            Err(FootError::InvalidSnapshot { .. })
        ));
        assert!(simulate_foot_walk(1, 0).is_err());
    }

    #[cfg(feature = "testing")]
    #[test]
    fn a_clipped_run_reports_its_ceiling_through_the_ffi() {
        use crate::testing::simulate_clipped_foot_run;
        let run = simulate_clipped_foot_run(3, 1, 0.7).unwrap();
        let nav = FootNavigator::with_defaults();
        assert_eq!(nav.accel_ceiling_mps2(), None);
        nav.push_packed(run.samples_packed, FootOutput::LatestOnly)
            .unwrap();
        let c = nav.accel_ceiling_mps2().expect("the ceiling is found");
        assert_eq!(Some(c), run.reference_ceiling_mps2);
        assert!((c - run.clip_mps2).abs() <= 0.01 * run.clip_mps2, "{c}");
        assert!(simulate_clipped_foot_run(3, 1, 0.0).is_err());
        assert!(simulate_clipped_foot_run(3, 1, f64::NAN).is_err());
    }

    #[test]
    fn a_poisoned_mutex_is_recovered() {
        let n = FootNavigator::with_defaults();
        let n2 = Arc::clone(&n);
        let poisoner = std::thread::spawn(move || {
            let _guard = n2.inner.lock().unwrap();
            panic!("poisoning the navigator's mutex on purpose");
        });
        assert!(poisoner.join().is_err());
        assert!(n.inner.is_poisoned());
        assert!(n.push(rest(0.0)).unwrap().is_none());
        assert!(!n.inner.is_poisoned());
    }
}
