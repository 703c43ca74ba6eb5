//! Running the learned pipeline and the baselines over one recording with truth,
//! and scoring them (ATE, RTE): shared by the tests and `stridekit eval odometry`.

use super::baseline::{NaiveMode, NaiveOdometry};
use super::metrics::{align_start, ate, rte, Point};
use super::train::Truth;
use stridekit_core::odometry::ImuSample;
use stridekit_core::odometry::OdometryModel;
use stridekit_core::odometry::{OdometryConfig, PhoneOdometry, PlacementSource};

/// The methods compared, in [`Tracks::methods`] order.
pub const METHODS: [&str; 4] = [
    "learned",
    "learned, no bias correction",
    "naive, fixed orientation",
    "naive, AHRS orientation",
];

/// Trajectories at the learned pipeline's estimate times, started at the truth.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tracks {
    pub truth: Vec<Point>,
    pub methods: [Vec<Point>; 4],
    /// Samples the learned odometry refused (skipped, by reason).
    pub rejected: crate::rejected::Rejected,
}

/// (ATE, RTE over 60 s) of each method, metres.
pub type Scores = [(f64, f64); 4];

impl Tracks {
    /// Rotate every method's track about its start point so that its displacement
    /// at `fit_s` after the start points the same way as the truth's. For
    /// recordings whose truth frame is not ENU or whose heading is relative (no
    /// magnetometer): the rotation between the two frames is unknown otherwise.
    /// Uses the truth, so it is an evaluation aid, not part of the pipeline.
    pub fn align_heading(&mut self, fit_s: f64) {
        let Some(t0) = self.truth.first().copied() else {
            return;
        };
        let k = self.truth.partition_point(|p| p.0 < t0.0 + fit_s);
        let Some(tk) = self.truth.get(k).copied() else {
            return;
        };
        let want = (tk.2 - t0.2).atan2(tk.1 - t0.1);
        for m in self.methods.iter_mut() {
            let (Some(m0), Some(mk)) = (m.first().copied(), m.get(k).copied()) else {
                continue;
            };
            let have = (mk.2 - m0.2).atan2(mk.1 - m0.1);
            let (s, c) = (want - have).sin_cos();
            for p in m.iter_mut() {
                let (dx, dy) = (p.1 - m0.1, p.2 - m0.2);
                p.1 = m0.1 + c * dx - s * dy;
                p.2 = m0.2 + s * dx + c * dy;
            }
        }
    }

    pub fn scores(&self) -> Scores {
        let mut s = [(f64::NAN, f64::NAN); 4];
        for (k, m) in self.methods.iter().enumerate() {
            s[k] = (ate(m, &self.truth), rte(m, &self.truth, 60.0));
        }
        s
    }
}

/// Run every method over `samples`; the learned ones pick their regressor from
/// `placement`.
pub fn run_methods(
    samples: &[ImuSample],
    truth: &dyn Truth,
    model: &OdometryModel,
    placement: PlacementSource,
) -> Tracks {
    let cfg = OdometryConfig {
        placement,
        ..OdometryConfig::default()
    };
    let mut learned = PhoneOdometry::new(cfg, model.clone()).expect("valid model");
    let mut nobias = PhoneOdometry::new(
        OdometryConfig {
            bias_correction: false,
            ..cfg
        },
        model.clone(),
    )
    .expect("valid model");
    let mut fixed = NaiveOdometry::new(NaiveMode::FixedOrientation, cfg.ahrs, true).expect("ok");
    let mut ahrs = NaiveOdometry::new(NaiveMode::AhrsOrientation, cfg.ahrs, true).expect("ok");
    // Baseline positions per accepted sample.
    let mut base: Vec<(f64, [f64; 2], [f64; 2])> = Vec::with_capacity(samples.len());
    let mut est = [Vec::new(), Vec::new()];
    let mut rejected = crate::rejected::Rejected::default();
    for s in samples {
        match learned.push(s) {
            Ok(Some(e)) => est[0].push((e.t_s, e.position_m[0], e.position_m[1])),
            Ok(None) => {}
            Err(e) => rejected.odometry(&e),
        }
        if let Ok(Some(e)) = nobias.push(s) {
            est[1].push((e.t_s, e.position_m[0], e.position_m[1]));
        }
        if fixed.push(s).is_ok() && ahrs.push(s).is_ok() {
            base.push((s.t_s, fixed.position_m(), ahrs.position_m()));
        }
    }
    let n = est[0].len().min(est[1].len());
    let truth_pts: Vec<Point> = est[0][..n]
        .iter()
        .map(|p| {
            let (e, no) = truth.position_at(p.0);
            (p.0, e, no)
        })
        .collect();
    let at = |t: f64, k: usize| -> (f64, f64, f64) {
        let i = base.partition_point(|b| b.0 <= t).saturating_sub(1);
        let p = base
            .get(i)
            .map_or([0.0; 2], |b| if k == 0 { b.1 } else { b.2 });
        (t, p[0], p[1])
    };
    let (e0, n0) = base.first().map_or((0.0, 0.0), |b| truth.position_at(b.0));
    let shift = |mut v: Vec<Point>| {
        for p in v.iter_mut() {
            p.1 += e0;
            p.2 += n0;
        }
        v
    };
    let mut l0 = est[0][..n].to_vec();
    let mut l1 = est[1][..n].to_vec();
    align_start(&mut l0, &truth_pts);
    align_start(&mut l1, &truth_pts);
    let f: Vec<Point> = truth_pts.iter().map(|p| at(p.0, 0)).collect();
    let a: Vec<Point> = truth_pts.iter().map(|p| at(p.0, 1)).collect();
    Tracks {
        methods: [l0, l1, shift(f), shift(a)],
        truth: truth_pts,
        rejected,
    }
}
