//! (work in progress)
use super::{Context, LocalFix, PaceConfig, PaceEstimate, PaceSource};
use crate::snapshot::{Reader, SnapshotError, Writer};



#[derive(Clone, Debug, PartialEq)]
pub struct AdaptiveFilter {
    t_s: f64,
}

impl AdaptiveFilter {
    pub fn new(_config: &PaceConfig) -> Self {
        Self { t_s: 0.0 }
    }
    pub fn on_fix(&mut self, fix: &LocalFix, ctx: &Context) -> PaceEstimate {
        self.t_s = fix.t_s;
        self.estimate(ctx)
    }
    pub fn on_steps(&mut self, t_s: f64, _ctx: &Context) {
        self.t_s = t_s;
    }
    pub fn estimate(&self, _ctx: &Context) -> PaceEstimate {
        PaceEstimate { t_s: self.t_s, speed_mps: 0.0, pace_s_per_km: None, speed_std_mps: None, cadence_spm: None, step_length_m: None, gnss_weight: 1.0, distance_m: 0.0, source: PaceSource::Initializing }
    }
    pub fn write(&self, w: &mut Writer) {
        w.f64(self.t_s);
    }
    pub fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        Ok(Self { t_s: r.f64()? })
    }
}
