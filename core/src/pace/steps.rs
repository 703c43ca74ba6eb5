//! The step stream: turns counts, events or cadence reports into one cumulative
//! step total over time, and answers "how many steps at t" and "cadence at t".

use super::cadence::CadenceFilter;
use super::error::{PaceError, Stream};
use super::types::StepSample;
use crate::input::{self, limits};
use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};

/// Samples kept for cadence and interpolation (covers ≥ 25 s at 6 steps/s of events).
const HISTORY: usize = 160;
/// Cadences above this are impossible for a human, steps/min (sprinters reach ~300).
pub const MAX_CADENCE_SPM: f64 = limits::MAX_CADENCE_SPM;
/// Step totals are extrapolated at most this far past the newest sample, seconds.
const EXTRAPOLATE_MAX_S: f64 = 3.0;
/// A pause in steps longer than this starts a new bout, seconds.
const BOUT_GAP_S: f64 = 2.0;
/// Cadence assumed for the steps of the first sample of a bout, steps/s (170/min).
const TYPICAL_CADENCE_HZ: f64 = 170.0 / 60.0;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Entry {
    t_s: f64,
    total: f64,
}

/// Cumulative step total with a short history.
#[derive(Clone, Debug, PartialEq)]
pub struct StepStream {
    history: Ring<Entry, HISTORY>,
    last_t_s: Option<f64>,
    /// Last raw platform count (for `Count` samples), to take differences.
    last_count: Option<u64>,
    /// Last reported cadence (for `Cadence` samples), steps/min.
    last_cadence_spm: Option<f64>,
    total: f64,
    /// Time of the last sample that added steps.
    last_step_t_s: Option<f64>,
    /// Start of the current walking/running bout: cadence windows never reach back
    /// across a stop.
    moving_since_t_s: f64,
    /// Smoothed cadence of the current bout.
    cadence: CadenceFilter,
    resets: u64,
    /// Steps per step the input reports: 1, or 2 once the tracker's cross-check found
    /// that the input counts strides (`super::crosscheck`). Applied to every sample.
    steps_per_report: f64,
}

impl Default for StepStream {
    fn default() -> Self {
        Self::new()
    }
}

impl StepStream {
    pub fn new() -> Self {
        Self {
            history: Ring::new(),
            last_t_s: None,
            last_count: None,
            last_cadence_spm: None,
            total: 0.0,
            last_step_t_s: None,
            moving_since_t_s: f64::NEG_INFINITY,
            cadence: CadenceFilter::IDLE,
            resets: 0,
            steps_per_report: 1.0,
        }
    }

    /// Steps per step the input reports (1, or 2 when it counts strides).
    pub fn steps_per_report(&self) -> f64 {
        self.steps_per_report
    }

    /// Count every step the input reports as `k` steps from now on, and the steps
    /// already counted too (totals, cadence), as if it had been so from the start:
    /// the step total stays a continuous function of time in the new unit.
    pub fn rescale(&mut self, k: f64) {
        self.steps_per_report *= k;
        self.total *= k;
        let old = self.history;
        self.history = Ring::new();
        for e in old.iter() {
            self.history.push(Entry {
                total: k * e.total,
                ..e
            });
        }
        self.last_cadence_spm = self.last_cadence_spm.map(|c| (c * k).min(MAX_CADENCE_SPM));
        self.cadence.rescale(k);
    }

    /// Whether any step sample was seen.
    pub fn has_data(&self) -> bool {
        self.last_t_s.is_some()
    }
    /// Time of the newest step sample, seconds.
    pub fn last_t_s(&self) -> Option<f64> {
        self.last_t_s
    }
    /// Cumulative steps since the first sample.
    pub fn total(&self) -> f64 {
        self.total
    }
    /// Counter resets seen (step counts that went down).
    pub fn resets(&self) -> u64 {
        self.resets
    }

    /// Validate a sample without changing state.
    pub fn check(&self, s: &StepSample) -> Result<(), PaceError> {
        input::time_after(Stream::Steps, s.t_s(), self.last_t_s)?;
        if let StepSample::Cadence { steps_per_min, .. } = *s {
            input::in_range(
                "steps_per_min",
                steps_per_min,
                0.0,
                MAX_CADENCE_SPM,
                "steps/min",
            )?;
        }
        Ok(())
    }

    /// Add a sample (call [`check`](Self::check) first). Returns steps added.
    pub fn push(&mut self, s: &StepSample) -> f64 {
        let t = s.t_s();
        let k = self.steps_per_report;
        let added = k
            * match *s {
                StepSample::Event { .. } => 1.0,
                StepSample::Count { steps, .. } => {
                    // Steps a human can have taken since the previous count (10 steps/s,
                    // plus one for the count's own rounding).
                    let possible = self
                        .last_t_s
                        .map_or(0.0, |t0| limits::MAX_STEP_RATE_HZ * (t - t0) + 1.0);
                    let d = match self.last_count {
                        None => 0.0,
                        Some(prev) if steps >= prev && ((steps - prev) as f64) <= possible => {
                            (steps - prev) as f64
                        }
                        Some(prev) => {
                            // Counter reset (reboot) or a jump no runner makes: continue
                            // from the new value, adding nothing.
                            self.resets = self.resets.saturating_add(1);
                            log::warn!(
                            "step counter went from {prev} to {steps} at t = {t} s: taken as a reset"
                        );
                            0.0
                        }
                    };
                    self.last_count = Some(steps);
                    d
                }
                StepSample::Cadence { steps_per_min, .. } => {
                    // In reported units here (× k above); the cadence kept is in steps.
                    let d = match (self.last_t_s, self.last_cadence_spm) {
                        // Trapezoid between reports; gaps longer than 10 s count the
                        // newer cadence over 10 s only (device paused).
                        (Some(t0), Some(c0)) => {
                            0.5 * (c0 / k + steps_per_min) / 60.0 * (t - t0).min(10.0)
                        }
                        _ => 0.0,
                    };
                    self.last_cadence_spm = Some((k * steps_per_min).min(MAX_CADENCE_SPM));
                    d
                }
            };
        let before = self.total;
        self.total += added;
        if added > 0.0 {
            let resumed = self.last_step_t_s.is_none_or(|ls| t - ls > BOUT_GAP_S);
            if resumed {
                // The steps happened after the previous sample, at a typical cadence
                // just before t (at least the last second): a counter that reports
                // every few seconds does not put all its steps into one second.
                let span_s = (added / TYPICAL_CADENCE_HZ).max(1.0);
                let t0 = self.last_t_s.unwrap_or(t).max(t - span_s);
                self.moving_since_t_s = t0;
                let guess = if t > t0 { added / (t - t0) } else { 2.5 };
                self.cadence = CadenceFilter::start(t0, before, guess.min(MAX_CADENCE_SPM / 60.0));
            }
            self.last_step_t_s = Some(t);
        }
        if self.cadence.is_active() {
            match *s {
                StepSample::Cadence { steps_per_min, .. } => {
                    self.cadence.observe_cadence(t, k * steps_per_min / 60.0)
                }
                StepSample::Event { .. } => self.cadence.observe_total(t, self.total, true),
                StepSample::Count { .. } => self.cadence.observe_total(t, self.total, false),
            }
        }
        self.last_t_s = Some(t);
        self.history.push(Entry {
            t_s: t,
            total: self.total,
        });
        added
    }

    /// Cumulative steps at time `t` by linear interpolation of the history. After the
    /// newest sample the total is extrapolated with the smoothed cadence for up to
    /// 3 s (step data often lags GNSS by a sample); before the oldest kept sample it
    /// is held.
    pub fn total_at(&self, t: f64) -> Option<f64> {
        let newest = self.history.newest()?;
        if t >= newest.t_s {
            let ahead = (t - newest.t_s).min(EXTRAPOLATE_MAX_S);
            let moving = self.cadence.is_active() && !self.stationary_at(t, BOUT_GAP_S);
            let c = if moving {
                self.cadence.cadence().0
            } else {
                0.0
            };
            return Some(newest.total + c * ahead);
        }
        let mut later = newest;
        for e in self.history.iter().rev().skip(1) {
            if e.t_s <= t {
                let span = later.t_s - e.t_s;
                let f = if span > 0.0 { (t - e.t_s) / span } else { 1.0 };
                return Some(e.total + f * (later.total - e.total));
            }
            later = e;
        }
        Some(later.total)
    }

    /// Whether the runner is standing at `t`: step data flows but no step was added in
    /// the last `after_s` seconds.
    pub fn stationary_at(&self, t: f64, after_s: f64) -> bool {
        match (self.last_t_s, self.last_step_t_s) {
            (None, _) => false,
            (Some(_), None) => true,
            (Some(_), Some(ls)) => {
                // Cadence reports of 0 mean standing even if they keep arriving.
                if matches!(self.last_cadence_spm, Some(c) if c < 1.0) {
                    return true;
                }
                // Judged on the step stream's own clock (tolerates a stream that lags
                // the GNSS stream by a few seconds), or by silence: on-change counters
                // send nothing while the runner stands.
                let last = self.last_t_s.unwrap_or(ls);
                last - ls > after_s || t - ls > after_s + 3.0
            }
        }
    }

    /// Start of the current walking/running bout, seconds (−∞ before any step).
    pub fn bout_start_t_s(&self) -> f64 {
        self.moving_since_t_s
    }

    /// Smoothed cadence of the current bout at `t`, steps/s, with its 1-σ: 0 when
    /// stationary, `None` without step data.
    pub fn smoothed_cadence(&self, t: f64, stationary_after_s: f64) -> Option<(f64, f64)> {
        if !self.has_data() {
            return None;
        }
        if self.stationary_at(t, stationary_after_s) {
            return Some((0.0, 0.0));
        }
        self.cadence.is_active().then(|| self.cadence.cadence())
    }

    /// Cadence at `t`, steps/s: least-squares slope of the step total over the last
    /// `window_s` seconds (at least two samples spanning ≥ 1 s). `None` without data.
    pub fn cadence_at(&self, t: f64, window_s: f64, stationary_after_s: f64) -> Option<f64> {
        if !self.has_data() {
            return None;
        }
        if self.stationary_at(t, stationary_after_s) {
            return Some(0.0);
        }
        if let Some(c) = self.last_cadence_spm {
            // Devices that report cadence directly: use it as is.
            return Some(c / 60.0);
        }
        let t0 = (t - window_s).max(self.moving_since_t_s);
        // Include the newest sample at or before t0 so the window is fully covered.
        let (mut n, mut st, mut sy, mut stt, mut sty) = (0.0, 0.0, 0.0, 0.0, 0.0);
        let mut first_t = f64::NAN;
        let mut last_t = f64::NAN;
        for e in self.history.iter().rev() {
            if e.t_s > t {
                continue;
            }
            if e.t_s < self.moving_since_t_s {
                break;
            }
            let dt = e.t_s - t;
            n += 1.0;
            st += dt;
            sy += e.total;
            stt += dt * dt;
            sty += dt * e.total;
            if last_t.is_nan() {
                last_t = e.t_s;
            }
            first_t = e.t_s;
            if e.t_s <= t0 {
                break;
            }
        }
        if n < 2.0 || last_t - first_t < 1.0 {
            return None;
        }
        let den = n * stt - st * st;
        if den <= 0.0 {
            return None;
        }
        let slope = (n * sty - st * sy) / den;
        Some(slope.clamp(0.0, MAX_CADENCE_SPM / 60.0))
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        w.u64(self.history.len() as u64);
        for e in self.history.iter() {
            w.f64(e.t_s);
            w.f64(e.total);
        }
        w.opt_f64(self.last_t_s);
        w.bool(self.last_count.is_some());
        w.u64(self.last_count.unwrap_or(0));
        w.opt_f64(self.last_cadence_spm);
        w.f64(self.total);
        w.opt_f64(self.last_step_t_s);
        w.f64(self.moving_since_t_s);
        self.cadence.write(w);
        w.u64(self.resets);
        w.f64(self.steps_per_report);
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let mut s = Self::new();
        let n = r.len(HISTORY)?;
        let mut prev: Option<Entry> = None;
        for _ in 0..n {
            let t_s = r.f64()?;
            let total = r.f64()?;
            // Time increases and the total never goes down.
            if prev.is_some_and(|p| !(t_s > p.t_s && total >= p.total)) || total < 0.0 {
                return Err(SnapshotError::Invalid("step history"));
            }
            prev = Some(Entry { t_s, total });
            s.history.push(Entry { t_s, total });
        }
        s.last_t_s = r.opt_f64()?;
        let has_count = r.bool()?;
        let count = r.u64()?;
        s.last_count = has_count.then_some(count);
        s.last_cadence_spm = r.opt_f64()?;
        s.total = r.f64()?;
        s.last_step_t_s = r.opt_f64()?;
        // −∞ before the first bout.
        s.moving_since_t_s = r.f64_any()?;
        s.cadence = CadenceFilter::read(r)?;
        s.resets = r.u64()?;
        s.steps_per_report = r.f64()?;
        let time_ok = |t: Option<f64>| t.is_none_or(|t| t.abs() <= limits::MAX_ABS_T_S);
        // The history ends at the newest sample with the current total; step totals
        // stay below what 10 steps/s could add in 10¹¹ s.
        let newest_ok =
            prev.is_none_or(|p| s.last_t_s.is_some_and(|t| p.t_s <= t) && p.total <= s.total);
        if !(time_ok(s.last_t_s) && time_ok(s.last_step_t_s))
            || s.moving_since_t_s.is_nan()
            || s.moving_since_t_s == f64::INFINITY
            || !(0.0..=1e12).contains(&s.total)
            || !newest_ok
            || s.last_cadence_spm
                .is_some_and(|c| !(0.0..=MAX_CADENCE_SPM).contains(&c))
            || !(s.steps_per_report == 1.0 || s.steps_per_report == 2.0)
        {
            return Err(SnapshotError::Invalid("step stream"));
        }
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_give_cadence() {
        let mut s = StepStream::new();
        for i in 0..30 {
            let e = StepSample::Event {
                t_s: i as f64 / 3.0,
            };
            s.check(&e).unwrap();
            s.push(&e);
        }
        let c = s.cadence_at(29.0 / 3.0, 5.0, 2.0).unwrap();
        assert!((c - 3.0).abs() < 1e-9, "{c}");
        assert_eq!(s.total(), 30.0);
    }

    #[test]
    fn counter_reset_keeps_total() {
        let mut s = StepStream::new();
        for (t, c) in [(0.0, 1000), (1.0, 1003), (2.0, 5), (3.0, 8)] {
            s.push(&StepSample::Count { t_s: t, steps: c });
        }
        assert_eq!(s.total(), 6.0);
        assert_eq!(s.resets(), 1);
    }

    #[test]
    fn rejects_time_reversal() {
        let mut s = StepStream::new();
        s.push(&StepSample::Event { t_s: 5.0 });
        assert!(s.check(&StepSample::Event { t_s: 5.0 }).is_err());
        assert!(s.check(&StepSample::Event { t_s: f64::NAN }).is_err());
        assert!(s
            .check(&StepSample::Cadence {
                t_s: 6.0,
                steps_per_min: -1.0
            })
            .is_err());
    }

    #[test]
    fn stationary_when_counts_stop() {
        let mut s = StepStream::new();
        for i in 0..10 {
            s.push(&StepSample::Count {
                t_s: i as f64,
                steps: 3 * i,
            });
        }
        assert!((s.cadence_at(9.0, 5.0, 2.0).unwrap() - 3.0).abs() < 1e-9);
        for i in 10..15 {
            s.push(&StepSample::Count {
                t_s: i as f64,
                steps: 27,
            });
        }
        assert_eq!(s.cadence_at(14.0, 5.0, 2.0), Some(0.0));
        // Moving again: the window does not reach back into the stop.
        for i in 15..18 {
            s.push(&StepSample::Count {
                t_s: i as f64,
                steps: 27 + 3 * (i - 14),
            });
        }
        assert!((s.cadence_at(17.0, 10.0, 2.0).unwrap() - 3.0).abs() < 1e-9);
    }
}
