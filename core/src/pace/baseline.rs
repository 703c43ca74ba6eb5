//! GNSS-only speed baselines the evaluation compares the fusion filters against.
//! Not meant for apps: they ignore steps and do no input checking beyond finiteness.

use super::published::PublishedFilter;
use super::steps::StepStream;
use super::{Context, GnssFix, LocalFix, PaceConfig};
use crate::geo::LocalFrame;

/// Which GNSS-only baseline.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BaselineKind {
    /// Distance between consecutive raw fixes over their time difference.
    RawDifferentiation,
    /// The paper's GNSS smoothing: quadratic fit over N fixes + EMA (the pace paper's Fig. 4 "EMA").
    GnssEma,
}

/// A GNSS-only speed estimator.
pub struct Baseline {
    kind: BaselineKind,
    frame: Option<LocalFrame>,
    last: Option<LocalFix>,
    ema: PublishedFilter,
    config: PaceConfig,
    no_steps: StepStream,
}

impl Baseline {
    pub fn new(kind: BaselineKind) -> Self {
        let config = PaceConfig::as_published();
        Self {
            kind,
            frame: None,
            last: None,
            ema: PublishedFilter::gnss_ema(&config),
            config,
            no_steps: StepStream::new(),
        }
    }

    /// Speed after this fix, m/s (`None` for the first fix or a non-increasing time).
    pub fn push(&mut self, fix: &GnssFix) -> Option<f64> {
        if !(fix.t_s.is_finite() && fix.lat_deg.is_finite() && fix.lon_deg.is_finite()) {
            return None;
        }
        if self.last.is_some_and(|l| fix.t_s <= l.t_s) {
            return None;
        }
        let frame = *self
            .frame
            .get_or_insert_with(|| LocalFrame::new(fix.lat_deg, fix.lon_deg, 0.0));
        let p = frame.to_enu(fix.lat_deg, fix.lon_deg, 0.0);
        let local = LocalFix {
            t_s: fix.t_s,
            east_m: p[0],
            north_m: p[1],
            accuracy_m: fix.horizontal_accuracy_m,
            speed: None,
        };
        let prev = self.last.replace(local);
        match self.kind {
            BaselineKind::RawDifferentiation => prev.map(|q| {
                (local.east_m - q.east_m).hypot(local.north_m - q.north_m) / (local.t_s - q.t_s)
            }),
            BaselineKind::GnssEma => {
                let ctx = Context {
                    config: &self.config,
                    steps: &self.no_steps,
                    accel: None,
                    pedometer_extra_rel_sigma: 0.0,
                };
                let e = self.ema.on_fix(&local, &ctx);
                prev.map(|_| e.speed_mps)
            }
        }
    }
}
