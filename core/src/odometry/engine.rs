//! [`PhoneOdometry`]: the learned pipeline as one engine.
//!
//! sample → door checks → AHRS → stabilised ENU rate and linear acceleration →
//! resampling onto the model's rate → Gaussian smoothing → feature window → every
//! `hop` grid samples: regressor (per placement) → bias correction → position.
//!
//! The placement that picks the regressor comes from [`PlacementSource`]: `Auto`
//! (the default) runs an embedded [`PlacementClassifier`] (the shipped model) on the
//! same accelerometer samples and uses the classified placement's regressor while
//! the classifier's smoothed confidence is at least [`AUTO_MIN_CONFIDENCE`], else the
//! general one; `Fixed(p)` always uses `p`'s; `Unknown` always the general one.
//!
//! The estimate refers to the centre of the newest window (window/2 + smoothing
//! delay behind the newest sample: 1.06 s with the shipped model).

use super::bias::{BiasCorrector, Entry};
use super::error::OdometryError;
use super::features::{FeatureWindow, WindowFeatures, MAX_WINDOW};
use super::model::{slot, slot_placement, OdometryModel};
use super::resample::{Channels, Resampler};
use super::sample::{check, ImuSample};
use super::smooth::{Gaussian, MAX_TAPS};
use super::stabilise::stabilise;
use crate::ahrs::{Ahrs, AhrsSettings, DecoupledSettings};
use crate::batch::{self, Batch, Counts};
use crate::input::{self, Stream, TimeGuard};
use crate::placement::{Placement, PlacementClassifier, PlacementEstimate};
use crate::snapshot::{Reader, SnapshotError, Writer};

/// Snapshot engine kind of [`PhoneOdometry`].
pub const SNAPSHOT_KIND: u8 = 8;
/// Version 3: the input layer's time state (version 2 added the placement source
/// and the embedded classifier).
const SNAPSHOT_VERSION: u16 = 3;

/// Smallest smoothed classifier probability at which [`PlacementSource::Auto`] uses
/// the classified placement's regressor (below it: the general regressor). Chosen a
/// priori (a clear majority among 6 classes), not tuned on any evaluation data.
pub const AUTO_MIN_CONFIDENCE: f64 = 0.6;

/// Where the placement that picks the regressor comes from.
///
/// The default is `Unknown` (the general regressor), by measurement: the shipped
/// placement classifier is trained on real phone traces and the shipped regressors
/// on the simulator (no public phone trajectory data here); on the simulator the
/// classifier names the right placement for only 22 % of windows and `Auto` more
/// than doubles the error of `Unknown` (ATE 91 vs 38 m, docs/odometry-pipeline.md).
/// Use `Auto` with regressors trained on real recordings (`stridekit train
/// odometry --ridi/--ronin`), `Fixed` when the app knows where the phone is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PlacementSource {
    /// The embedded placement classifier (shipped model) on the engine's own
    /// accelerometer samples; its placement's regressor when its confidence is at
    /// least [`AUTO_MIN_CONFIDENCE`], else the general regressor (also before its
    /// first window, 5.12 s after the start).
    Auto,
    /// The app knows the placement: always its regressor.
    Fixed(Placement),
    /// Always the general regressor.
    #[default]
    Unknown,
}

/// Settings of the engine (the model carries the pipeline's parameters).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OdometryConfig {
    pub ahrs: AhrsSettings,
    /// Use the magnetometer when a sample has one (absolute heading).
    pub use_magnetometer: bool,
    /// Apply the bias correction (off: integrate the regressed velocity).
    pub bias_correction: bool,
    /// Where the placement comes from (default [`PlacementSource::Unknown`], see there why).
    pub placement: PlacementSource,
}

impl Default for OdometryConfig {
    fn default() -> Self {
        Self {
            ahrs: AhrsSettings {
                decoupled: DecoupledSettings {
                    // Phones hand over the field calibrated by the OS (Android's
                    // TYPE_MAGNETIC_FIELD); the online offset estimate then only
                    // learns the field gradients of a building walked through
                    // (`stridekit eval pdr --data phone-indoor`, learned odometry:
                    // median end error 8.2 % → 8.6 % with it).
                    mag_offset_max_ut: 0.0,
                    ..DecoupledSettings::default()
                },
                ..AhrsSettings::default()
            },
            use_magnetometer: true,
            bias_correction: true,
            placement: PlacementSource::Unknown,
        }
    }
}

/// What the engine knows after a window.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OdometryEstimate {
    /// Time the estimate refers to (centre of the window), s.
    pub t_s: f64,
    /// Horizontal velocity, ENU, m/s (after the bias correction when on).
    pub velocity_mps: [f64; 2],
    /// Regressed velocity before the correction, ENU, m/s.
    pub regressed_mps: [f64; 2],
    /// Position, ENU, m, from the origin at the first window.
    pub position_m: [f64; 2],
    /// Features of the window (training and diagnostics).
    pub features: WindowFeatures,
    /// Placement whose regressor produced this window (`None`: the general one).
    pub regressor_placement: Option<Placement>,
    /// [`PlacementSource::Auto`]: the classifier's current placement (`None` before
    /// its first window and for the other sources).
    pub detected_placement: Option<Placement>,
    /// Smoothed probability of `detected_placement` (0 when there is none).
    pub placement_confidence: f64,
}

impl OdometryEstimate {
    pub fn is_finite(&self) -> bool {
        self.t_s.is_finite()
            && self.velocity_mps.iter().all(|v| v.is_finite())
            && self.regressed_mps.iter().all(|v| v.is_finite())
            && self.position_m.iter().all(|v| v.is_finite())
            && self.placement_confidence.is_finite()
    }
}

/// A sample a batch refused, with its index.
pub type OdometryRejection = crate::batch::Rejected<OdometryError>;

/// Learned phone inertial odometry.
#[derive(Clone, Debug)]
pub struct PhoneOdometry {
    config: OdometryConfig,
    model: OdometryModel,
    ahrs: Ahrs,
    /// Runs only with [`PlacementSource::Auto`].
    classifier: PlacementClassifier,
    time: TimeGuard,
    resampler: Resampler,
    smoother: Gaussian,
    window: FeatureWindow,
    hop_count: usize,
    bias: BiasCorrector,
    yaw_rad: f64,
    started: bool,
    position_m: [f64; 2],
    latest: Option<OdometryEstimate>,
    /// Set when the last push produced an estimate.
    fresh: bool,
}

impl PhoneOdometry {
    pub fn new(config: OdometryConfig, model: OdometryModel) -> Result<Self, OdometryError> {
        model.validate()?;
        let p = model.params;
        Ok(Self {
            ahrs: Ahrs::new(config.ahrs)?,
            classifier: PlacementClassifier::shipped(),
            time: TimeGuard::new(Stream::Imu),
            resampler: Resampler::new(p.rate_hz),
            smoother: Gaussian::new(p.sigma_samples),
            window: FeatureWindow::new(p.window),
            hop_count: 0,
            bias: BiasCorrector::new(p.lambda),
            yaw_rad: 0.0,
            started: false,
            position_m: [0.0; 2],
            latest: None,
            fresh: false,
            config,
            model,
        })
    }

    /// The shipped model with `config`.
    pub fn shipped(config: OdometryConfig) -> Result<Self, OdometryError> {
        Self::new(config, OdometryModel::shipped())
    }

    pub fn config(&self) -> &OdometryConfig {
        &self.config
    }

    pub fn model(&self) -> &OdometryModel {
        &self.model
    }

    /// Change the placement source; takes effect at the next window. The embedded
    /// classifier keeps its state (it only advances while the source is `Auto`).
    pub fn set_placement(&mut self, placement: PlacementSource) {
        self.config.placement = placement;
    }

    /// The embedded classifier's current estimate (`None` before its first window
    /// or when it never ran, i.e. the source was never `Auto`).
    pub fn placement_estimate(&self) -> Option<PlacementEstimate> {
        self.classifier.estimate()
    }

    /// The placement whose regressor the next window uses (`None`: general) and the
    /// detected placement with its confidence (Auto only).
    fn choose_placement(&self) -> (Option<Placement>, Option<Placement>, f64) {
        match self.config.placement {
            PlacementSource::Unknown => (None, None, 0.0),
            PlacementSource::Fixed(p) => (Some(p), None, 0.0),
            PlacementSource::Auto => match self.classifier.estimate() {
                None => (None, None, 0.0),
                Some(e) => {
                    let ok = e.confidence >= AUTO_MIN_CONFIDENCE;
                    (ok.then_some(e.placement), Some(e.placement), e.confidence)
                }
            },
        }
    }

    /// The latest estimate (`None` before the first full window).
    pub fn estimate(&self) -> Option<OdometryEstimate> {
        self.latest
    }

    /// Current horizontal velocity, ENU, m/s (0 before the first window).
    pub fn velocity_mps(&self) -> [f64; 2] {
        self.latest.map_or([0.0; 2], |e| e.velocity_mps)
    }

    /// Current position, ENU, m.
    pub fn position_m(&self) -> [f64; 2] {
        self.position_m
    }

    /// One sample. Returns the new estimate when a window completed. On error the
    /// state is unchanged.
    pub fn push(&mut self, s: &ImuSample) -> Result<Option<OdometryEstimate>, OdometryError> {
        self.push_inner(s, None)
    }

    /// One sample with the attitude from outside (body → ENU quaternion `[w, x, y, z]`,
    /// e.g. the OS's rotation vector, as RIDI and RoNIN use; or the truth, for
    /// diagnosis) instead of the internal AHRS, which is not advanced. The
    /// quaternion is normalised; a norm outside 0.5..2 or a non-finite component is
    /// an error.
    pub fn push_with_attitude(
        &mut self,
        s: &ImuSample,
        attitude_wxyz: [f64; 4],
    ) -> Result<Option<OdometryEstimate>, OdometryError> {
        for v in attitude_wxyz {
            input::finite("attitude_wxyz", v)?;
        }
        let n = attitude_wxyz.iter().map(|v| v * v).sum::<f64>().sqrt();
        input::in_range("attitude norm", n, 0.5, 2.0, "")?;
        self.push_inner(s, Some(attitude_wxyz.map(|v| v / n)))
    }

    fn push_inner(
        &mut self,
        s: &ImuSample,
        attitude: Option<[f64; 4]>,
    ) -> Result<Option<OdometryEstimate>, OdometryError> {
        check(s, &self.time)?;
        let mag = if self.config.use_magnetometer {
            s.mag_ut
        } else {
            None
        };
        if attitude.is_none() {
            self.ahrs.update(s.t_s, s.gyro_rads, s.accel_mps2, mag)?;
        }
        // Nothing below fails.
        if self.config.placement == PlacementSource::Auto {
            // The classifier has its own door checks (it rejects, e.g., a window's
            // worth of samples that look like g); a sample it rejects leaves it
            // unchanged and is still used by the odometry.
            let _ = self.classifier.push(&s.into());
        }
        if let Some(last) = self.time.last_t_s() {
            if s.t_s - last > self.config.ahrs.max_gap_s {
                // The motion during a gap is unknown: restart the signal chain.
                self.resampler.reset();
                self.smoother.reset();
                self.window.reset();
                self.bias.reset();
                self.hop_count = 0;
            }
        }
        self.time.accept(s.t_s);
        let q = attitude
            .or_else(|| self.ahrs.quaternion())
            .unwrap_or([1.0, 0.0, 0.0, 0.0]);
        let st = stabilise(
            s.t_s,
            &q,
            &s.gyro_rads,
            &s.accel_mps2,
            self.config.ahrs.gravity_mps2,
        );
        self.yaw_rad = st.yaw_rad;
        let x: Channels = [
            st.gyro_enu_rads[0],
            st.gyro_enu_rads[1],
            st.gyro_enu_rads[2],
            st.accel_enu_mps2[0],
            st.accel_enu_mps2[1],
            st.accel_enu_mps2[2],
        ];
        self.fresh = false;
        let mut rs = self.resampler;
        rs.push(s.t_s, x, |t, y| self.on_grid(t, y));
        self.resampler = rs;
        Ok(if self.fresh { self.latest } else { None })
    }

    fn on_grid(&mut self, t: f64, y: &Channels) {
        let Some((ts, ys)) = self.smoother.push(t, y) else {
            return;
        };
        self.window.push(ts, &ys);
        self.hop_count = self.hop_count.saturating_add(1);
        let hop = self.model.params.hop;
        if !self.window.is_full() || self.hop_count < hop {
            return;
        }
        self.hop_count = 0;
        let Some(f) = self.window.features(self.yaw_rad) else {
            return;
        };
        if !f.is_finite() {
            return;
        }
        let (used, detected, confidence) = self.choose_placement();
        let reg = self.model.regressor(used);
        let used = used.filter(|&p| self.model.has_regressor(Some(p)));
        let v_s = reg.predict(&f);
        let (sn, cs) = f.yaw_rad.sin_cos();
        let v_r = [cs * v_s[0] - sn * v_s[1], sn * v_s[0] + cs * v_s[1]];
        // Raw increment over the hop ending at the window's centre.
        let n = self.window.ring.len();
        let centre = n - self.model.params.window / 2;
        let dt = 1.0 / self.model.params.rate_hz;
        let mut d = [0.0; 2];
        for i in centre.saturating_sub(hop)..centre {
            let (_, x) = self.window.ring.get(i).unwrap_or_default();
            d[0] += x[3] * dt;
            d[1] += x[4] * dt;
        }
        let v = if self.config.bias_correction {
            self.bias.push(v_r, d)
        } else {
            v_r
        };
        let v = if v.iter().all(|x| x.is_finite()) {
            v
        } else {
            [0.0; 2]
        };
        if self.started {
            let h = self.model.params.hop_s();
            self.position_m[0] += v[0] * h;
            self.position_m[1] += v[1] * h;
        }
        self.started = true;
        self.latest = Some(OdometryEstimate {
            t_s: 0.5 * (f.t_start_s + f.t_end_s),
            velocity_mps: v,
            regressed_mps: v_r,
            position_m: self.position_m,
            features: f,
            regressor_placement: used,
            detected_placement: detected,
            placement_confidence: confidence,
        });
        self.fresh = true;
    }

    /// Many samples in order; bad samples are skipped and reported by index. One
    /// estimate per window hop, in order.
    pub fn push_batch(&mut self, samples: &[ImuSample]) -> Batch<OdometryEstimate, OdometryError> {
        batch::run(samples, |s| self.push(s))
    }

    /// As [`push_batch`](Self::push_batch), but `on_estimate` sees every estimate
    /// instead of it being kept (a clean batch allocates nothing).
    pub fn push_batch_with(
        &mut self,
        samples: &[ImuSample],
        on_estimate: impl FnMut(&OdometryEstimate),
    ) -> Counts<OdometryError> {
        batch::counted(samples, on_estimate, |s| self.push(s))
    }

    /// The whole state (model included) as bytes; restoring continues bit-exactly.
    pub fn snapshot(&self) -> Vec<u8> {
        let mut w = Writer::new(SNAPSHOT_KIND, SNAPSHOT_VERSION);
        w.bytes(self.model.to_text().as_bytes());
        w.bytes(&self.ahrs.snapshot());
        w.bool(self.config.use_magnetometer);
        w.bool(self.config.bias_correction);
        w.u8(source_code(self.config.placement));
        w.bytes(&self.classifier.snapshot());
        self.time.write(&mut w);
        // Resampler.
        let r = &self.resampler;
        w.bool(r.prev.is_some());
        let (tp, xp) = r.prev.unwrap_or_default();
        w.f64(tp);
        w.f64s(&xp);
        w.f64(r.t0_s);
        w.u64(r.k);
        // Smoother history, window, bias block.
        w.u64(self.smoother.hist.len() as u64);
        for (t, x) in self.smoother.hist.iter() {
            w.f64(t);
            w.f64s(&x);
        }
        w.u64(self.window.ring.len() as u64);
        for (t, x) in self.window.ring.iter() {
            w.f64(t);
            w.f64s(&x);
        }
        w.u64(self.hop_count as u64);
        w.u64(self.bias.hist.len() as u64);
        for (a, b, c) in self.bias.hist.iter() {
            w.f64s(&a);
            w.f64s(&b);
            w.f64s(&c);
        }
        w.f64(self.yaw_rad);
        w.bool(self.started);
        w.f64s(&self.position_m);
        w.bool(self.latest.is_some());
        let e = self.latest.unwrap_or_default();
        w.f64(e.t_s);
        w.f64s(&e.velocity_mps);
        w.f64s(&e.regressed_mps);
        w.f64s(&e.position_m);
        w.u8(slot(e.regressor_placement) as u8);
        w.u8(slot(e.detected_placement) as u8);
        w.f64(e.placement_confidence);
        let f = &e.features;
        w.f64(f.t_start_s);
        w.f64(f.t_end_s);
        w.f64(f.yaw_rad);
        w.f64s(&f.scalars);
        for v in &f.vectors {
            w.f64s(v);
        }
        w.finish()
    }

    /// An engine continuing exactly where the snapshot was taken.
    pub fn restore(bytes: &[u8]) -> Result<Self, OdometryError> {
        let (mut r, _) = Reader::new(bytes, SNAPSHOT_KIND, SNAPSHOT_VERSION)?;
        let text = std::str::from_utf8(r.bytes()?).map_err(|_| SnapshotError::Invalid("model"))?;
        let model = OdometryModel::parse(text).map_err(|_| SnapshotError::Invalid("model"))?;
        let ahrs = Ahrs::restore(r.bytes()?)?;
        let use_magnetometer = r.bool()?;
        let bias_correction = r.bool()?;
        let placement = source_from_code(r.u8()?)?;
        let classifier = PlacementClassifier::restore(r.bytes()?)
            .map_err(|_| SnapshotError::Invalid("placement classifier"))?;
        let config = OdometryConfig {
            ahrs: *ahrs.settings(),
            use_magnetometer,
            bias_correction,
            placement,
        };
        let mut e = Self::new(config, model)?;
        e.ahrs = ahrs;
        e.classifier = classifier;
        e.time = TimeGuard::read(&mut r, Stream::Imu)?;
        let has_prev = r.bool()?;
        let tp = r.f64()?;
        let mut xp = [0.0; 6];
        r.f64s(&mut xp)?;
        e.resampler.prev = has_prev.then_some((tp, xp));
        e.resampler.t0_s = r.f64()?;
        e.resampler.k = r.u64()?;
        if !e.resampler.is_consistent() {
            return Err(SnapshotError::Invalid("resampler grid").into());
        }
        let n = r.len(MAX_TAPS)?;
        for _ in 0..n {
            let t = r.f64()?;
            let mut x = [0.0; 6];
            r.f64s(&mut x)?;
            e.smoother.hist.push((t, x));
        }
        let n = r.len(MAX_WINDOW)?;
        for _ in 0..n {
            let t = r.f64()?;
            let mut x = [0.0; 6];
            r.f64s(&mut x)?;
            e.window.ring.push((t, x));
        }
        e.hop_count = r.len(MAX_WINDOW)?;
        let n = r.len(super::bias::BLOCK + 1)?;
        for _ in 0..n {
            let mut v = [0.0; 6];
            r.f64s(&mut v)?;
            let entry: Entry = ([v[0], v[1]], [v[2], v[3]], [v[4], v[5]]);
            e.bias.hist.push(entry);
        }
        e.yaw_rad = r.f64()?;
        e.started = r.bool()?;
        r.f64s(&mut e.position_m)?;
        let has_latest = r.bool()?;
        let mut est = OdometryEstimate {
            t_s: r.f64()?,
            ..OdometryEstimate::default()
        };
        r.f64s(&mut est.velocity_mps)?;
        r.f64s(&mut est.regressed_mps)?;
        r.f64s(&mut est.position_m)?;
        est.regressor_placement = read_slot(&mut r)?;
        est.detected_placement = read_slot(&mut r)?;
        est.placement_confidence = r.f64()?;
        est.features.t_start_s = r.f64()?;
        est.features.t_end_s = r.f64()?;
        est.features.yaw_rad = r.f64()?;
        r.f64s(&mut est.features.scalars)?;
        for v in est.features.vectors.iter_mut() {
            r.f64s(v)?;
        }
        e.latest = has_latest.then_some(est);
        r.end()?;
        Ok(e)
    }
}

impl PartialEq for PhoneOdometry {
    /// Same state, bit for bit (the snapshots are equal).
    fn eq(&self, other: &Self) -> bool {
        self.config.ahrs == other.config.ahrs && self.snapshot() == other.snapshot()
    }
}

/// Snapshot byte of a placement source: 0 unknown, 1 auto, 2 + class id fixed.
fn source_code(s: PlacementSource) -> u8 {
    match s {
        PlacementSource::Unknown => 0,
        PlacementSource::Auto => 1,
        PlacementSource::Fixed(p) => 2 + p.index() as u8,
    }
}

fn source_from_code(c: u8) -> Result<PlacementSource, SnapshotError> {
    match c {
        0 => Ok(PlacementSource::Unknown),
        1 => Ok(PlacementSource::Auto),
        _ => Placement::ALL
            .get(c as usize - 2)
            .map(|&p| PlacementSource::Fixed(p))
            .ok_or(SnapshotError::Invalid("placement source")),
    }
}

fn read_slot(r: &mut Reader) -> Result<Option<Placement>, SnapshotError> {
    slot_placement(r.u8()? as usize).ok_or(SnapshotError::Invalid("placement"))
}
