//! The default step detector: works in time, not samples (a low-pass and a 50 Hz grid
//! make it rate-independent), counts steps only in bouts confirmed by their regularity,
//! and rejects shaking, vehicles and cycling. docs/phone.md ("How the default step
//! detector works") explains each stage; the files here follow them.

mod bout;
mod candidate;
mod confirm;
mod gaps;
mod held;
mod history;
mod impact;
mod params;
mod peaks;
mod pending;
mod short_walk;
mod slow_walk;
mod snapshot;
mod tail;

use crate::signal::Ring;

use self::history::History;
use self::pending::Pending;
use super::event::StepEvent;
use super::gait::GaitPeriod;
use super::{ema_gain, Moments, Sink};

pub use self::params::RobustStepParams;

/// Grid rate of the internal resampling, Hz.
pub const GRID_HZ: f64 = 50.0;
const GRID_DT_S: f64 = 1.0 / GRID_HZ;
/// Candidates buffered while a bout is not confirmed.
const PENDING: usize = 16;
/// Input gaps longer than this restart the detector (app paused), s. Shorter ones
/// (samples dropped by a busy phone) are bridged: the grid interpolates across them
/// and a bout that resumes at its cadence after the gap gets the steps of the gap.
pub const MAX_INPUT_GAP_S: f64 = 2.0;
/// Most grid points one sample can advance (MAX_INPUT_GAP_S on the grid, plus slack).
const MAX_GRID_STEPS: usize = (MAX_INPUT_GAP_S * GRID_HZ) as usize + 2;
/// A spacing between input samples longer than this is a gap in the data (samples
/// dropped), s: steps may have been lost in it.
const DATA_GAP_S: f64 = 0.1;
/// Slow mean of the filtered magnitude, time constant, s.
const MEAN_TAU_S: f64 = 1.0;
/// RMS of x, time constant, s.
const RMS_TAU_S: f64 = 2.0;
/// How the phone is held: the direction of the acceleration low-passed with this time
/// constant (about one stride, so the swing of a stride averages out), s.
const CARRY_TAU_S: f64 = 1.0;

/// State of the default detector.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RobustDetector {
    p: RobustStepParams,
    /// Time constant of each low-pass section, s.
    tau_lp_s: f64,
    /// Grid-step gains of the slow mean and of the mean square (constants).
    gain_mean: f64,
    gain_ms: f64,
    // Input stage.
    started: bool,
    lp1: f64,
    lp2: f64,
    prev_t_s: f64,
    prev_y: f64,
    next_grid_t_s: f64,
    /// Acceleration low-passed with [`CARRY_TAU_S`], sensor frame, m/s².
    carry: [f64; 3],
    // Grid stage.
    mean: f64,
    ms: f64,
    xs: History,
    seeking_peak: bool,
    ext_x: f64,
    ext_t_s: f64,
    /// Last valley value (NaN before the first).
    valley_x: f64,
    /// Raw-magnitude statistics since the previous candidate.
    moments: Moments,
    // Bout stage.
    pending: Ring<Pending, PENDING>,
    /// Candidates of a short walk that ended in silence before it was confirmed
    /// (see `short_walk`); empty if none.
    short_walk: Ring<Pending, PENDING>,
    in_bout: bool,
    period_s: f64,
    /// Interval before the newest one inside the bout, s (NaN at its start): the
    /// period follows pairs of steps (see `RobustDetector::follow_period`).
    prev_interval_s: f64,
    /// Time of the last accepted candidate (pending or emitted), NaN if none.
    last_t_s: f64,
    /// Input gaps (spacings over [`DATA_GAP_S`]) since then, total s.
    missing_s: f64,
    /// Σ of the squared high-passed magnitude and its samples since the last candidate.
    hf_sum_sq: f64,
    hf_n: f64,
    /// Low-pass states of the impact high-pass sections.
    hp: [f64; 2],
    /// Typical amplitude of recent accepted candidates (EMA), m/s²; 0 before any.
    amplitude_ref_mps2: f64,
    /// Last step and period of the bout that ended most recently (NaN if none).
    bout_end_t_s: f64,
    bout_end_period_s: f64,
    /// End of the most recent gap in the input data (NaN if none) and its length, s.
    data_gap_end_t_s: f64,
    data_gap_s: f64,
    /// Step period from the signal's autocorrelation.
    gait: GaitPeriod,
    /// A weak candidate on cadence held as the possible last step of the bout (see
    /// `tail`).
    tail: Option<StepEvent>,
    /// Steps sooner than the cadence, held one step (see `held`).
    held: Ring<StepEvent, { held::HELD }>,
}

/// The constants a detector derives from its parameters (not serialised).
struct Derived {
    tau_lp_s: f64,
    gain_mean: f64,
    gain_ms: f64,
}

impl Derived {
    fn of(p: &RobustStepParams) -> Self {
        Self {
            tau_lp_s: 1.0 / (2.0 * std::f64::consts::PI * p.lowpass_hz),
            gain_mean: 1.0 - (-GRID_DT_S / MEAN_TAU_S).exp(),
            gain_ms: 1.0 - (-GRID_DT_S / RMS_TAU_S).exp(),
        }
    }
}

impl RobustDetector {
    pub(crate) fn new(p: RobustStepParams) -> Self {
        let Derived {
            tau_lp_s,
            gain_mean,
            gain_ms,
        } = Derived::of(&p);
        Self {
            p,
            tau_lp_s,
            gain_mean,
            gain_ms,
            started: false,
            lp1: 0.0,
            lp2: 0.0,
            prev_t_s: 0.0,
            prev_y: 0.0,
            next_grid_t_s: 0.0,
            carry: [0.0; 3],
            mean: 0.0,
            ms: 0.0,
            xs: History::new(),
            seeking_peak: true,
            ext_x: f64::NEG_INFINITY,
            ext_t_s: 0.0,
            valley_x: f64::NAN,
            moments: Moments::EMPTY,
            pending: Ring::new(),
            short_walk: Ring::new(),
            in_bout: false,
            period_s: f64::NAN,
            prev_interval_s: f64::NAN,
            last_t_s: f64::NAN,
            missing_s: 0.0,
            hf_sum_sq: 0.0,
            hf_n: 0.0,
            hp: [0.0; 2],
            amplitude_ref_mps2: 0.0,
            bout_end_t_s: f64::NAN,
            bout_end_period_s: f64::NAN,
            data_gap_end_t_s: f64::NAN,
            data_gap_s: 0.0,
            gait: GaitPeriod::new(),
            tail: None,
            held: Ring::new(),
        }
    }

    /// Process one validated sample; released steps are appended to `out`.
    pub(crate) fn push(&mut self, t_s: f64, accel_mps2: [f64; 3], mag: f64, out: &mut Sink<'_>) {
        let dt = t_s - self.prev_t_s;
        if self.started && !(dt > 0.0 && dt <= MAX_INPUT_GAP_S) {
            self.restart(out);
        }
        self.moments.add(mag);
        if !self.started {
            self.start(t_s, accel_mps2, mag, out);
            return;
        }
        self.note_data_gap(t_s, dt);
        self.follow_carry(dt, accel_mps2);
        let y = self.low_pass(dt, mag);
        self.accumulate_impact(dt, mag);
        self.resample(t_s, dt, y, out);
    }

    /// Time of the newest sample pushed, s (`None` before the first).
    pub(crate) fn last_t_s(&self) -> Option<f64> {
        self.started.then_some(self.prev_t_s)
    }

    /// Paused: nothing is known about the gap; start over (steps already released
    /// stay counted, unconfirmed candidates are dropped). The door only lets later
    /// times through; a time not after the previous one can only come from an
    /// inconsistent restored state, and starts over too. A last step held when the
    /// input stopped ended the walk.
    fn restart(&mut self, out: &mut Sink<'_>) {
        self.release_held(out);
        if let (Some(ev), true) = (self.tail, self.in_bout) {
            out.push(ev);
        }
        *self = Self::new(self.p);
    }

    /// The first sample: every filter starts at it.
    fn start(&mut self, t_s: f64, accel_mps2: [f64; 3], mag: f64, out: &mut Sink<'_>) {
        self.started = true;
        self.carry = accel_mps2;
        self.lp1 = mag;
        self.lp2 = mag;
        self.hp[0] = mag;
        self.prev_t_s = t_s;
        self.prev_y = mag;
        self.next_grid_t_s = t_s;
        self.mean = mag;
        self.grid(t_s, mag, false, out);
        self.next_grid_t_s = t_s + GRID_DT_S;
    }

    /// How the phone is held: the acceleration low-passed over about a stride.
    fn follow_carry(&mut self, dt: f64, accel_mps2: [f64; 3]) {
        let c = ema_gain(dt / CARRY_TAU_S);
        for (s, v) in self.carry.iter_mut().zip(accel_mps2) {
            *s += c * (v - *s);
        }
    }

    /// The magnitude through two cascaded first-order low-passes, each discretised
    /// exactly for the sample spacing.
    fn low_pass(&mut self, dt: f64, mag: f64) -> f64 {
        let a = ema_gain(dt / self.tau_lp_s);
        self.lp1 += a * (mag - self.lp1);
        self.lp2 += a * (self.lp1 - self.lp2);
        self.lp2
    }

    /// The filtered magnitude `y` at `t_s`, linearly interpolated onto the grid since
    /// the previous sample (across a gap in the data, the grid points are bridged: no
    /// measurement, see `grid`).
    fn resample(&mut self, t_s: f64, dt: f64, y: f64, out: &mut Sink<'_>) {
        let bridged = dt > DATA_GAP_S;
        // Bounded by construction: a sample is at most MAX_INPUT_GAP_S after the
        // previous one (longer gaps restart), so at most MAX_GRID_STEPS grid points
        // fall in between. The cap also ends the loop if adding GRID_DT_S ever stopped
        // changing the time (|t| beyond ~1e14 s; the door refuses those).
        for _ in 0..MAX_GRID_STEPS {
            if self.next_grid_t_s > t_s {
                break;
            }
            let g = self.next_grid_t_s;
            let f = (g - self.prev_t_s) / dt;
            let yg = self.prev_y + f * (y - self.prev_y);
            self.grid(g, yg, bridged, out);
            self.next_grid_t_s += GRID_DT_S;
        }
        if self.next_grid_t_s <= t_s {
            self.next_grid_t_s = t_s + GRID_DT_S;
        }
        self.prev_t_s = t_s;
        self.prev_y = y;
    }
}
