//! The default step detector: works in time (not samples), confirms walking/running by
//! its regularity before counting, and rejects shaking, vehicles and cycling.
//!
//! Pipeline:
//! 1. **Low-pass in time.** The magnitude goes through two cascaded first-order
//!    low-passes (time constant τ = 1 / (2π·`lowpass_hz`)), each discretised exactly for
//!    the actual sample spacing (α = 1 − e^(−Δt/τ)), so any rate from 20 to 500 Hz and
//!    irregular timestamps give the same response. Its group delay (2τ) is subtracted
//!    from the reported step times.
//! 2. **Fixed grid.** The filtered magnitude is resampled by linear interpolation onto a
//!    50 Hz grid; everything after this runs on the grid, so thresholds, windows and
//!    cost per second do not depend on the input rate.
//! 3. **Peaks with hysteresis.** x = filtered magnitude − its slow mean (EMA, 1 s). A
//!    peak is confirmed when x falls more than δ below the running maximum, a valley
//!    when it rises δ above the running minimum; δ = max(`min_hysteresis_mps2`,
//!    `hysteresis_rel` · RMS(x)) adapts to the carrying position (a purse gives small
//!    swings, an armband large ones) and ignores the small secondary bumps of one step.
//!    Each peak with peak-to-previous-valley amplitude in
//!    [`min_amplitude_mps2`, `max_amplitude_mps2`] and at least `relative_amplitude` ×
//!    the typical recent step amplitude is a step *candidate* (vehicle vibration stays
//!    below the floor; the secondary bump of a slow step stays below the relative bar).
//!    The typical amplitude fades (τ = 8 s) once no candidate has been accepted for
//!    `max_step_interval_s`: a gentler gait after a harder one (a walk after a run) is
//!    not measured against steps that have stopped.
//! 4. **Bouts.** Candidates are buffered until a bout is confirmed. The step period
//!    comes from the signal, not from the candidates: a running autocorrelation of x
//!    over the human stride range (0.5–2.2 s, [`super::gait`]) gives the stride, and
//!    the step is half of it unless the signal is anti-correlated at half the stride
//!    (then the lag was one step of a slow symmetric walk). Extra candidates between
//!    steps (secondary bumps, noise from jittered timestamps) therefore cannot change
//!    the period; candidates closer than `refractory` × the period are merged into one
//!    (the larger peak). A bout is confirmed by `confirm_steps` consecutive merged
//!    candidates that look like gait:
//!    - the autocorrelation at the stride ≥ `min_periodicity` (walking is periodic;
//!      bumps and shaking are not), the step period inside [`min_bout_interval_s`,
//!      `max_step_interval_s`];
//!    - regular *strides*: each sum of two consecutive intervals within ±`regularity`
//!      of the stride (a phone on one side of the body sees left and right steps
//!      differently — 0.45 s / 0.65 s in a front pocket — but strides are regular), and
//!      each interval within ±50 % of the period;
//!    - a period under `running_interval_s` (running cadence) needs a median amplitude
//!      of at least `running_min_amplitude_mps2` (running shakes the body well over 1 g;
//!      small peaks at that rate are double bumps of a slow walk);
//!    - the phone held one way: the direction of the acceleration low-passed over about
//!      a stride (gravity in the sensor frame) within 45° of the newest candidate's at
//!      every candidate (putting the phone away turns it further);
//!    - a median *impact ratio* ≥ `min_impact_ratio`: RMS of the raw magnitude above
//!      8 Hz (second-order high-pass) over the step, divided by the step amplitude.
//!      Heel strikes put energy above 8 Hz; smooth periodic motion without impacts
//!      (pedalling) does not. This is a weak guard: the ratio of real walking goes down
//!      to ≈ 0.01, the threshold is 0.008, and a strong pedalling harmonic or vibration
//!      of the bike defeats it (see the report). An input slower than 32 Hz cannot
//!      resolve that band, so there the ratio is not measured and the check not made.
//!
//!    On confirmation the k checked candidates are released as steps, and older
//!    buffered ones only as far as they chain back with step-like intervals (0.5–2.4
//!    periods) and the phone held as in the bout: the irregular peaks of handling the
//!    phone before walking are dropped.
//!    If the previous bout ended by losing its periodicity (not by silence: candidates
//!    kept coming, no interval over `max_step_interval_s`) at most 10 s earlier and the
//!    new cadence is within ±30 % of the old one, the person walked on (a turn, the phone
//!    handled while walking): the steps of the gap are filled at the cadence (≤ 24).
//! 5. **In a bout** each candidate is a step unless it comes sooner than
//!    `refractory` × the step period (a double peak of one step); a gap of 1.6–2.4
//!    periods means one weak step was missed and it is filled at the midpoint; a gap
//!    longer than max(`max_step_interval_s`, 2.5 periods) or an autocorrelation at the
//!    step/stride period below `min_periodicity` / 2 ends the bout (the next one must
//!    be confirmed again). The period follows half the stride (the mean of the last
//!    two intervals: a phone on one side sees unequal left and right steps) quickly
//!    when within ±30 % of it and barely otherwise; when it has drifted to about half or twice the autocorrelation's
//!    period (a run of missed or extra peaks) it is reset to that period.
//! 6. **Dropped samples.** Input gaps up to [`MAX_INPUT_GAP_S`] (a busy phone drops
//!    samples in bursts) are bridged by the grid's interpolation; when the next step of
//!    a bout comes after such gaps, and what was seen of the interval (the interval
//!    minus the time the gaps hid) is shorter than 2.5 periods, the steps of the gaps
//!    are counted at the cadence (the walker did not stop because the phone did). Longer gaps restart the
//!    detector (the app was paused).
//!
//! Step features (duration, variance, max, min of the raw magnitude) are taken over
//! the samples between the detection of the previous candidate and this one: one full
//! step cycle, shifted by the detection latency.
//!
//! All parameters were set once for every placement, rate and user (see
//! `stridekit eval steps --sensitivity` for their sensitivity and a leave-one-user-out
//! check on the Oxford traces).

use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};

use super::event::StepEvent;
use super::gait::GaitPeriod;
use super::{Moments, Sink};

/// Grid rate of the internal resampling, Hz.
pub const GRID_HZ: f64 = 50.0;
const GRID_DT_S: f64 = 1.0 / GRID_HZ;
/// Grid samples kept for the autocorrelation (5.12 s).
const HISTORY: usize = 256;
/// Candidates buffered while a bout is not confirmed.
const PENDING: usize = 16;
/// Largest deviation of one step interval from half the stride when confirming
/// (left/right asymmetry of a phone carried on one side).
const ASYMMETRY: f64 = 0.5;
/// Corner of the high-pass that isolates heel impacts from the smooth step motion, Hz.
const IMPACT_HZ: f64 = 8.0;
/// Input slower than 4 × [`IMPACT_HZ`] (32 Hz: a Nyquist frequency under twice the
/// corner, where a phone's own anti-alias filter has already taken most of the band)
/// does not resolve impacts: on the indoor walks decimated to 25 Hz, the impact check
/// refused whole walks (52 → 23 steps, 20 → 0). There the check is not made, and the
/// detector cannot tell pedalling from walking by impacts. Mean spacing, s.
const IMPACT_MIN_SPACING_S: f64 = 1.0 / (4.0 * IMPACT_HZ);
/// Weight of a new interval in the step period: intervals within ±30 % of the period
/// follow the cadence; others (a secondary bump that passed, a missed step) barely move it.
fn period_gain(interval_s: f64, period_s: f64) -> f64 {
    if (interval_s - period_s).abs() <= 0.3 * period_s {
        0.25
    } else {
        0.03
    }
}

/// Two candidates closer than the refractory time are one step: the larger peak is
/// its time and amplitude; the step's features span both.
fn merge(a: &Pending, b: &Pending) -> Pending {
    let (big, small) = if b.amplitude_mps2 > a.amplitude_mps2 {
        (b, a)
    } else {
        (a, b)
    };
    let d = a.event.duration_s + b.event.duration_s;
    Pending {
        event: StepEvent {
            t_s: big.event.t_s,
            duration_s: if d.is_finite() {
                d
            } else {
                big.event.duration_s
            },
            accel_variance_m2ps4: big.event.accel_variance_m2ps4,
            accel_max_mps2: big.event.accel_max_mps2.max(small.event.accel_max_mps2),
            accel_min_mps2: big.event.accel_min_mps2.min(small.event.accel_min_mps2),
            vertical_displacement_m: f64::NAN,
        },
        impact: big.impact.max(small.impact),
        amplitude_mps2: big.amplitude_mps2,
        carry: big.carry,
    }
}

/// A bout period outside this ratio to the autocorrelation's step period has lost the
/// cadence (about half or double it) and is reset.
const PERIOD_LOCK_MIN: f64 = 0.7;
const PERIOD_LOCK_MAX: f64 = 1.45;

/// A bout that ended by losing its periodicity (not by silence) and is followed within
/// this time by a bout at a cadence within ±30 % of it, with candidates arriving all
/// through the gap (the phone kept moving), is one walk: the steps in the gap (a turn,
/// the phone handled while walking: a message read on the way) are filled at the
/// cadence, s. (6 s until 2026-12-03: a purse walk at 50 Hz with jittered timestamps
/// lost 14 steps to a 6.3 s gap.)
const FILL_MAX_GAP_S: f64 = 10.0;
/// Most steps filled into one gap (10 s at 2.4 steps/s).
const FILL_MAX_STEPS: usize = 24;

/// A run of at least this many regular candidates that ended in silence before it
/// could be confirmed (a few steps, then a stop: reaching a door, a shop window, a
/// surveyed point) is kept, and released as steps when a bout at the same cadence and
/// strength is confirmed within [`SHORT_WALK_MAX_GAP_S`] after it.
const SHORT_WALK_MIN: usize = 3;
/// Longest stop between a short walk and the bout that confirms it, s.
const SHORT_WALK_MAX_GAP_S: f64 = 6.0;
/// A short walk's step intervals must be within this share of the confirming bout's
/// period, and its median amplitude within this factor of the bout's.
const SHORT_WALK_CADENCE: f64 = 0.3;
const SHORT_WALK_AMPLITUDE: f64 = 2.0;

/// The last step of a walk: the foot that stops is set down gently, often under the
/// relative amplitude bar (1.3 m/s² peak to valley against the walk's typical 6.4 at
/// the end of Samsung_Dario_Hard_InHand_1). Inside a bout such a weak candidate on
/// cadence (within this share of the period after the previous step) is held; when the walk goes on,
/// the next step comes about one period later and counts the weak one anyway (a missed
/// step is filled); when no step has come [`TAIL_WAIT_PERIODS`] periods after it, the
/// walk ended with it and it is released as the bout's last step.
const TAIL_CADENCE: f64 = 0.2;
const TAIL_WAIT_PERIODS: f64 = 1.2;

/// How the phone is held: the direction of the acceleration low-passed with this time
/// constant (about one stride, so the swing of a stride averages out), s.
const CARRY_TAU_S: f64 = 1.0;
/// A bout is confirmed only if its checked candidates, and buffered older ones chain
/// back to it only if they, have the phone held within 45° of how it is held at the
/// newest checked candidate (cosine): the irregular peaks of putting the phone into a
/// pocket or bag turn it further than that, the swing of a walk in a pocket, a bag or
/// a hand does not (a stride's ±30° thigh or arm swing is averaged over the stride).
const CARRY_MIN_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if n > 0.0 {
        [v[0] / n, v[1] / n, v[2] / n]
    } else {
        [0.0; 3]
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Weight of a new candidate in the typical step amplitude.
const AMPLITUDE_GAIN: f64 = 0.2;
/// Time constant with which the typical amplitude fades once no candidate has been
/// accepted for longer than `max_step_interval_s`, s.
const AMPLITUDE_MEMORY_S: f64 = 8.0;
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

/// Parameters of the default detector (one set for every placement and rate).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RobustStepParams {
    /// Cut-off of the magnitude low-pass, Hz.
    pub lowpass_hz: f64,
    /// Smallest hysteresis of the peak detector, m/s².
    pub min_hysteresis_mps2: f64,
    /// Hysteresis relative to the RMS of the de-meaned magnitude.
    pub hysteresis_rel: f64,
    /// Smallest peak-to-valley amplitude of a step, m/s².
    pub min_amplitude_mps2: f64,
    /// Largest peak-to-valley amplitude of a step, m/s² (beyond: violent shaking).
    pub max_amplitude_mps2: f64,
    /// Shortest interval between two steps, s (5 steps/s).
    pub min_step_interval_s: f64,
    /// Shortest median step interval that can start a bout, s.
    pub min_bout_interval_s: f64,
    /// Longest interval between steps of one bout, s.
    pub max_step_interval_s: f64,
    /// Consecutive regular candidates needed to confirm a bout.
    pub confirm_steps: usize,
    /// Allowed relative deviation of the intervals from their median when confirming.
    pub regularity: f64,
    /// Least normalised autocorrelation at the step or stride period.
    pub min_periodicity: f64,
    /// A bout is refused when the median impact ratio of its candidates is below this
    /// (RMS of the magnitude above 8 Hz over the step / step amplitude): smooth motion
    /// without heel impacts, such as pedalling.
    pub min_impact_ratio: f64,
    /// Step periods shorter than this are running cadences, s ...
    pub running_interval_s: f64,
    /// ... which need at least this median amplitude to start a bout, m/s² (running
    /// shakes the body by well over 1 g; at such a cadence small peaks are the
    /// secondary bumps of a slow walk).
    pub running_min_amplitude_mps2: f64,
    /// Candidates smaller than this fraction of the typical recent step amplitude are
    /// secondary bumps, not steps.
    pub relative_amplitude: f64,
    /// In a bout, candidates sooner than this fraction of the period are double peaks.
    pub refractory: f64,
}

impl Default for RobustStepParams {
    fn default() -> Self {
        Self {
            lowpass_hz: 4.0,
            min_hysteresis_mps2: 0.3,
            hysteresis_rel: 0.5,
            min_amplitude_mps2: 1.0,
            max_amplitude_mps2: 60.0,
            min_step_interval_s: 0.2,
            min_bout_interval_s: 0.25,
            max_step_interval_s: 2.0,
            confirm_steps: 5,
            regularity: 0.3,
            min_periodicity: 0.4,
            min_impact_ratio: 0.008,
            refractory: 0.6,
            relative_amplitude: 0.45,
            running_interval_s: 0.45,
            running_min_amplitude_mps2: 4.0,
        }
    }
}

impl RobustStepParams {
    pub(crate) fn validate(&self) -> Result<(), String> {
        let all = self.as_array();
        if all.iter().any(|v| !v.is_finite()) {
            return Err("parameters must be finite".into());
        }
        if !(0.5..=20.0).contains(&self.lowpass_hz) {
            return Err("lowpass_hz must be 0.5..=20".into());
        }
        if self.min_hysteresis_mps2 <= 0.0 || self.hysteresis_rel < 0.0 {
            return Err("hysteresis must be positive".into());
        }
        if !(self.min_amplitude_mps2 >= 0.0 && self.max_amplitude_mps2 > self.min_amplitude_mps2) {
            return Err("need 0 ≤ min_amplitude_mps2 < max_amplitude_mps2".into());
        }
        if !(self.min_step_interval_s > 0.0
            && self.min_bout_interval_s >= self.min_step_interval_s
            && self.max_step_interval_s > self.min_bout_interval_s
            && self.max_step_interval_s <= 2.5)
        {
            return Err(
                "need 0 < min_step_interval_s ≤ min_bout_interval_s < max_step_interval_s ≤ 2.5"
                    .into(),
            );
        }
        if self.running_interval_s < 0.0 || self.running_min_amplitude_mps2 < 0.0 {
            return Err("running gate must not be negative".into());
        }
        if !(2..=PENDING).contains(&self.confirm_steps) {
            return Err(format!("confirm_steps must be 2..={PENDING}"));
        }
        if !(0.0..=1.0).contains(&self.regularity)
            || !(-1.0..=1.0).contains(&self.min_periodicity)
            || !(0.0..=1.0).contains(&self.min_impact_ratio)
            || !(0.0..1.0).contains(&self.refractory)
            || !(0.0..1.0).contains(&self.relative_amplitude)
        {
            return Err("regularity, periodicity, impact ratio, refractory or relative amplitude out of range".into());
        }
        Ok(())
    }

    /// Every numeric setting (the snapshot writes these and `confirm_steps`).
    fn as_array(&self) -> [f64; 15] {
        // Exhaustive on purpose: a new setting must be added here (and so to the
        // snapshot).
        let Self {
            lowpass_hz,
            min_hysteresis_mps2,
            hysteresis_rel,
            min_amplitude_mps2,
            max_amplitude_mps2,
            min_step_interval_s,
            min_bout_interval_s,
            max_step_interval_s,
            regularity,
            min_periodicity,
            min_impact_ratio,
            refractory,
            relative_amplitude,
            running_interval_s,
            running_min_amplitude_mps2,
            confirm_steps: _, // an integer, written on its own
        } = *self;
        [
            lowpass_hz,
            min_hysteresis_mps2,
            hysteresis_rel,
            min_amplitude_mps2,
            max_amplitude_mps2,
            min_step_interval_s,
            min_bout_interval_s,
            max_step_interval_s,
            regularity,
            min_periodicity,
            min_impact_ratio,
            refractory,
            relative_amplitude,
            running_interval_s,
            running_min_amplitude_mps2,
        ]
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        w.f64s(&self.as_array());
        w.u64(self.confirm_steps as u64);
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let mut v = [0.0; 15];
        r.f64s(&mut v)?;
        let confirm_steps = r.len(PENDING)?;
        Ok(Self {
            lowpass_hz: v[0],
            min_hysteresis_mps2: v[1],
            hysteresis_rel: v[2],
            min_amplitude_mps2: v[3],
            max_amplitude_mps2: v[4],
            min_step_interval_s: v[5],
            min_bout_interval_s: v[6],
            max_step_interval_s: v[7],
            confirm_steps,
            regularity: v[8],
            min_periodicity: v[9],
            min_impact_ratio: v[10],
            refractory: v[11],
            relative_amplitude: v[12],
            running_interval_s: v[13],
            running_min_amplitude_mps2: v[14],
        })
    }
}

/// The last grid samples, stored twice so the newest n are always one contiguous slice
/// (the autocorrelation runs over plain slices, no index arithmetic per element).
#[derive(Clone, Debug, PartialEq)]
struct History {
    buf: [f64; 2 * HISTORY],
    /// Where the next value goes, 0..HISTORY.
    pos: usize,
    len: usize,
}

impl History {
    fn new() -> Self {
        Self {
            buf: [0.0; 2 * HISTORY],
            pos: 0,
            len: 0,
        }
    }
    fn push(&mut self, v: f64) {
        self.buf[self.pos] = v;
        self.buf[self.pos + HISTORY] = v;
        self.pos = (self.pos + 1) % HISTORY;
        self.len = (self.len + 1).min(HISTORY);
    }
    /// The newest `n` values (n ≤ len), oldest first.
    fn last(&self, n: usize) -> &[f64] {
        let end = self.pos + HISTORY;
        &self.buf[end - n..end]
    }
}

/// A candidate waiting for its bout to be confirmed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Pending {
    event: StepEvent,
    /// Impact ratio of the step (see [`RobustStepParams::min_impact_ratio`]).
    impact: f64,
    /// Peak-to-valley amplitude, m/s².
    amplitude_mps2: f64,
    /// How the phone was held at the candidate: the direction of the slowly
    /// low-passed acceleration (gravity) in the sensor frame, unit vector.
    carry: [f64; 3],
}

impl Default for StepEvent {
    fn default() -> Self {
        StepEvent {
            t_s: 0.0,
            duration_s: f64::NAN,
            accel_variance_m2ps4: 0.0,
            accel_max_mps2: 0.0,
            accel_min_mps2: 0.0,
            vertical_displacement_m: f64::NAN,
        }
    }
}

/// State of the default detector.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RobustDetector {
    p: RobustStepParams,
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
    /// (see [`SHORT_WALK_MIN`]); empty if none.
    short_walk: Ring<Pending, PENDING>,
    in_bout: bool,
    period_s: f64,
    /// Interval before the newest one inside the bout, s (NaN at its start): the
    /// period follows pairs of steps (see [`RobustDetector::follow_period`]).
    prev_interval_s: f64,
    /// Time of the last accepted candidate (pending or emitted), NaN if none.
    last_t_s: f64,
    /// Input gaps (spacings over [`DATA_GAP_S`]) since then, total s.
    missing_s: f64,
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
    /// [`TAIL_CADENCE`]).
    tail: Option<StepEvent>,
}

impl RobustDetector {
    pub(crate) fn new(p: RobustStepParams) -> Self {
        Self {
            p,
            tau_lp_s: 1.0 / (2.0 * std::f64::consts::PI * p.lowpass_hz),
            gain_mean: 1.0 - (-GRID_DT_S / MEAN_TAU_S).exp(),
            gain_ms: 1.0 - (-GRID_DT_S / RMS_TAU_S).exp(),
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
        }
    }

    /// Process one validated sample; released steps are appended to `out`.
    pub(crate) fn push(&mut self, t_s: f64, accel_mps2: [f64; 3], mag: f64, out: &mut Sink<'_>) {
        let dt = t_s - self.prev_t_s;
        if self.started && !(dt > 0.0 && dt <= MAX_INPUT_GAP_S) {
            // Paused: nothing is known about the gap; start over (steps already
            // released stay counted, unconfirmed candidates are dropped). The door
            // only lets later times through; a time not after the previous one can
            // only come from an inconsistent restored state, and starts over too.
            // A last step held when the input stopped ended the walk.
            if let (Some(ev), true) = (self.tail, self.in_bout) {
                out.push(ev);
            }
            *self = Self::new(self.p);
        }
        self.moments.add(mag);
        if !self.started {
            self.started = true;
            self.carry = accel_mps2;
            self.lp1 = mag;
            self.lp2 = mag;
            self.hp[0] = mag;
            self.prev_t_s = t_s;
            self.prev_y = mag;
            self.next_grid_t_s = t_s;
            self.mean = mag;
            self.grid(t_s, mag, out);
            self.next_grid_t_s = t_s + GRID_DT_S;
            return;
        }
        if dt > DATA_GAP_S {
            self.data_gap_end_t_s = t_s;
            self.data_gap_s = dt;
            self.missing_s += dt;
        }
        let c = super::ema_gain(dt / CARRY_TAU_S);
        for (s, v) in self.carry.iter_mut().zip(accel_mps2) {
            *s += c * (v - *s);
        }
        let a = super::ema_gain(dt / self.tau_lp_s);
        self.lp1 += a * (mag - self.lp1);
        self.lp2 += a * (self.lp1 - self.lp2);
        let y = self.lp2;
        let b = super::ema_gain(dt * 2.0 * std::f64::consts::PI * IMPACT_HZ);
        // Second-order high-pass: two first-order sections (each: input − its low-pass).
        // Steeper filters remove too much of the impact content at 50 Hz.
        let mut h = mag;
        for lp in &mut self.hp {
            *lp += b * (h - *lp);
            h -= *lp;
        }
        let hf = h;
        self.hf_sum_sq += hf * hf;
        self.hf_n += 1.0;
        // Bounded by construction: a sample is at most MAX_INPUT_GAP_S after the
        // previous one (longer gaps restart above), so at most MAX_GRID_STEPS grid
        // points fall in between. The cap also ends the loop if adding GRID_DT_S
        // ever stopped changing the time (|t| beyond ~1e14 s; the door refuses those).
        for _ in 0..MAX_GRID_STEPS {
            if self.next_grid_t_s > t_s {
                break;
            }
            let g = self.next_grid_t_s;
            let f = (g - self.prev_t_s) / dt;
            let yg = self.prev_y + f * (y - self.prev_y);
            self.grid(g, yg, out);
            self.next_grid_t_s += GRID_DT_S;
        }
        if self.next_grid_t_s <= t_s {
            self.next_grid_t_s = t_s + GRID_DT_S;
        }
        self.prev_t_s = t_s;
        self.prev_y = y;
    }

    fn grid(&mut self, t_s: f64, y: f64, out: &mut Sink<'_>) {
        if let Some(ev) = self.tail {
            if t_s - ev.t_s > TAIL_WAIT_PERIODS * self.period_s {
                // No step followed: the walk ended with this one.
                self.tail = None;
                if self.in_bout {
                    // The statistics since the previous step are kept for the next
                    // one (as after a rejected candidate): it always has samples.
                    out.push(ev);
                    self.last_t_s = ev.t_s;
                }
            }
        }
        let (a_mean, a_ms) = (self.gain_mean, self.gain_ms);
        self.mean += a_mean * (y - self.mean);
        let x = y - self.mean;
        self.ms += a_ms * (x * x - self.ms);
        self.xs.push(x);
        self.gait.push(x);
        let delta = self
            .p
            .min_hysteresis_mps2
            .max(self.p.hysteresis_rel * self.ms.sqrt());
        if self.seeking_peak {
            if x > self.ext_x {
                self.ext_x = x;
                self.ext_t_s = t_s;
            } else if x < self.ext_x - delta {
                let amplitude = self.ext_x - self.valley_x;
                let peak_t = self.ext_t_s - 2.0 * self.tau_lp_s;
                self.seeking_peak = false;
                self.ext_x = x;
                self.ext_t_s = t_s;
                if amplitude.is_finite() {
                    self.candidate(peak_t, amplitude, out);
                }
            }
        } else if x < self.ext_x {
            self.ext_x = x;
            self.ext_t_s = t_s;
        } else if x > self.ext_x + delta {
            self.valley_x = self.ext_x;
            self.seeking_peak = true;
            self.ext_x = x;
            self.ext_t_s = t_s;
        }
    }

    /// Normalised autocorrelation of the last grid samples at `lag_s`.
    fn acf(&self, lag_s: f64) -> f64 {
        let lag = (lag_s / GRID_DT_S).round() as usize;
        if lag == 0 {
            return 1.0;
        }
        let want = ((3.0f64).max(2.5 * lag_s) / GRID_DT_S) as usize;
        let n = want.min(self.xs.len.saturating_sub(lag));
        if n < 2 * lag.min(25) {
            return f64::NAN;
        }
        let (mut sa, mut sb, mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0, 0.0, 0.0);
        let recent = self.xs.last(n + lag);
        for (&a, &b) in recent[lag..].iter().zip(&recent[..n]) {
            sa += a;
            sb += b;
            sab += a * b;
            saa += a * a;
            sbb += b * b;
        }
        let nf = n as f64;
        let cov = sab - sa * sb / nf;
        let va = saa - sa * sa / nf;
        let vb = sbb - sb * sb / nf;
        if va <= 0.0 || vb <= 0.0 {
            return 0.0;
        }
        cov / (va * vb).sqrt()
    }

    /// Whether the autocorrelation at the step or at the stride period reaches `min`
    /// (the stride lag is only computed when the step lag fails; NaN never passes).
    fn periodic(&self, period_s: f64, min: f64) -> bool {
        self.acf(period_s) >= min || self.acf(2.0 * period_s) >= min
    }

    fn candidate(&mut self, t_s: f64, amplitude: f64, out: &mut Sink<'_>) {
        let p = self.p;
        // The mean input spacing since the previous candidate: an input too slow to
        // resolve the band above IMPACT_HZ cannot show impacts, so the ratio is not
        // measured there (NaN, which no impact check refuses).
        let spacing = (t_s - self.last_t_s) / self.moments.n; // NaN without a previous
        let impact = if spacing > IMPACT_MIN_SPACING_S {
            f64::NAN
        } else if self.hf_n > 0.0 {
            (self.hf_sum_sq / self.hf_n).sqrt() / amplitude
        } else {
            0.0
        };
        if amplitude >= p.min_amplitude_mps2 {
            self.hf_sum_sq = 0.0;
            self.hf_n = 0.0;
        }
        if !(p.min_amplitude_mps2..=p.max_amplitude_mps2).contains(&amplitude) {
            return;
        }
        // The typical amplitude is of the steps of *now*: after a silence longer than a
        // step interval (no candidate accepted) it fades, so that a gentler gait after a
        // harder one (a walk after a run, the phone then in a bag) is not measured
        // against steps that have stopped.
        // (Computed from the last accepted candidate's time: rejected ones change
        // nothing.)
        let silent = t_s - self.last_t_s - p.max_step_interval_s; // NaN without a previous
        let reference = if silent > 0.0 {
            self.amplitude_ref_mps2 * (-silent / AMPLITUDE_MEMORY_S).exp()
        } else {
            self.amplitude_ref_mps2
        };
        let interval = t_s - self.last_t_s; // NaN without a previous candidate
        if amplitude < p.relative_amplitude * reference {
            // A secondary bump of the previous step (or of the swing), or, on cadence
            // inside a bout, perhaps the walk's last step (held, see TAIL_CADENCE).
            if self.in_bout
                && self.tail.is_none()
                && self.moments.n > 0.0
                && (interval - self.period_s).abs() <= TAIL_CADENCE * self.period_s
            {
                self.tail = Some(self.moments.event(t_s, interval));
            }
            return;
        }
        // A step-strength candidate: the walk went on (or this one decides), the held
        // weak one is not a last step.
        self.tail = None;
        self.amplitude_ref_mps2 = reference;
        if interval < p.min_step_interval_s {
            return;
        }
        if interval.is_nan() || interval > p.max_step_interval_s {
            // Silence (or the first candidate): no walk continues across it.
            self.bout_end_t_s = f64::NAN;
        }
        if self.in_bout {
            // The bout's period follows the candidates; when it has drifted to twice or
            // half the period of the signal itself (a run of missed or extra peaks), it
            // is reset from the autocorrelation.
            // Not right after dropped samples: the gap bridged by interpolation is in
            // the correlation's window.
            let clean = t_s - self.data_gap_end_t_s >= super::gait::ACF_TAU_S
                || self.data_gap_end_t_s.is_nan();
            let clean = clean && self.gait.settled();
            let acf = self.gait.step_period(p.min_periodicity).filter(|_| clean);
            if let Some((acf_period, _, _)) = acf {
                let ratio = acf_period / self.period_s;
                // A shorter period must itself be a correlated lag: half a slow step is
                // anti-correlated (peak against valley) and is not taken.
                let shorter_ok = self.gait.rho_at(acf_period) > 0.0;
                if ratio > PERIOD_LOCK_MAX || (ratio < PERIOD_LOCK_MIN && shorter_ok) {
                    self.period_s = acf_period;
                }
            }
            if interval < p.refractory * self.period_s {
                return;
            }
            let gap_end = p.max_step_interval_s.max(2.5 * self.period_s);
            // Samples were dropped since the previous step (a busy phone): the walk
            // went on through the gap, its steps are counted at the cadence. Several
            // gaps close together count by the time they hid: what was seen of the
            // interval must be short of a step-less stretch (2.5 periods).
            let across_gap = self.data_gap_end_t_s > self.last_t_s
                && interval <= 2.5 * self.period_s + self.missing_s.max(MAX_INPUT_GAP_S)
                && interval <= FILL_MAX_GAP_S;
            // While a bridged gap is inside the correlation window (the interpolated
            // stretch is not periodic, the walk may well be), steps that keep coming
            // at the cadence continue the bout.
            let on_cadence = (interval - self.period_s).abs() <= 0.3 * self.period_s;
            let periodic = self.periodic(self.period_s, p.min_periodicity * 0.5)
                || across_gap
                || (on_cadence && t_s - self.data_gap_end_t_s < super::gait::ACF_TAU_S);
            if (interval <= gap_end || across_gap) && periodic {
                let ev = self.moments.event(t_s, interval);
                self.moments = Moments::EMPTY;
                let period = self.period_s;
                let n = (interval / period).round();
                if (interval > 1.6 * period && interval < 2.4 * period) || (across_gap && n >= 2.0)
                {
                    // Missed steps (a weak one, or samples dropped): fill them evenly.
                    let n = n.clamp(2.0, FILL_MAX_STEPS as f64 + 1.0) as usize;
                    let step = interval / n as f64;
                    let t0 = t_s - interval;
                    for i in 1..n {
                        out.push(StepEvent {
                            t_s: t0 + i as f64 * step,
                            duration_s: step,
                            ..ev
                        });
                    }
                    out.push(StepEvent {
                        duration_s: step,
                        ..ev
                    });
                    self.follow_period(step, false);
                } else {
                    out.push(ev);
                    self.follow_period(interval, true);
                }
                self.last_t_s = t_s;
                self.missing_s = self.missing_after(t_s);
                self.amplitude_ref_mps2 += AMPLITUDE_GAIN * (amplitude - self.amplitude_ref_mps2);
                return;
            }
            // The bout ended (long gap or lost periodicity): this candidate may start
            // the next one.
            self.in_bout = false;
            self.prev_interval_s = f64::NAN;
            if interval <= p.max_step_interval_s {
                self.bout_end_t_s = self.last_t_s;
                self.bout_end_period_s = self.period_s;
            }
            self.pending.clear();
        }
        let duration = if interval <= p.max_step_interval_s {
            interval
        } else {
            self.keep_short_walk();
            self.pending.clear();
            f64::NAN
        };
        let ev = self.moments.event(t_s, duration);
        self.moments = Moments::EMPTY;
        self.pending.push(Pending {
            event: ev,
            impact,
            amplitude_mps2: amplitude,
            carry: unit(self.carry),
        });
        self.amplitude_ref_mps2 = if self.amplitude_ref_mps2 > 0.0 {
            self.amplitude_ref_mps2 + AMPLITUDE_GAIN * (amplitude - self.amplitude_ref_mps2)
        } else {
            amplitude
        };
        self.last_t_s = t_s;
        self.missing_s = self.missing_after(t_s);
        self.try_confirm(out);
    }

    /// The step period from the newest `k` candidates themselves (half their median
    /// stride), when the signal's own autocorrelation is periodic at it: used only
    /// while the autocorrelation has not yet seen [`super::gait::ACF_TAU_S`] of signal
    /// (a recording that starts in mid-walk), so the first steps are not lost waiting
    /// for it.
    fn candidate_period(&self, k: usize) -> Option<f64> {
        let mut strides = [0.0f64; PENDING];
        let mut ns = 0;
        for j in 0..k.saturating_sub(2) {
            let (Some(a), Some(c)) = (self.pending.back(j + 2), self.pending.back(j)) else {
                break;
            };
            strides[ns] = c.event.t_s - a.event.t_s;
            ns += 1;
        }
        if ns == 0 {
            return None;
        }
        let st = &mut strides[..ns];
        st.sort_by(f64::total_cmp);
        let period = 0.5 * st[ns / 2];
        // Anti-correlated at the claimed step: the candidates were half steps (a
        // secondary bump between heel strikes), not steps.
        let half_steps = self.acf(period) < super::gait::HALF_LAG_ANTI;
        (period > 0.0 && !half_steps && self.periodic(period, self.p.min_periodicity))
            .then_some(period)
    }

    /// Time the input has been missing since `t_s`, a candidate's time (it is
    /// processed a little after its peak, when a gap may already have begun).
    fn missing_after(&self, t_s: f64) -> f64 {
        let gap_start = self.data_gap_end_t_s - self.data_gap_s;
        if self.data_gap_end_t_s > t_s {
            self.data_gap_end_t_s - gap_start.max(t_s)
        } else {
            0.0
        }
    }

    /// Follow the bout's step period with a new step interval (`measured`: between
    /// two detected steps; otherwise one of the steps filled into a gap).
    ///
    /// The period is half the stride: the mean of the last two intervals. A phone
    /// carried on one side sees its left and right steps apart unequally (0.40 s /
    /// 0.62 s in a back pocket); followed one interval at a time, the short ones
    /// (within ±30 % of the period) pull and the long ones (outside) barely do, and
    /// the period settles near the short interval. At a period that is not half the
    /// stride, the stride lag of the periodicity check misses the stride and the bout
    /// ends while the walk goes on (Samsung_Carmelo_Hard_BackPocket_2: 0.438 s for a
    /// 1.04 s stride).
    fn follow_period(&mut self, interval_s: f64, measured: bool) {
        let observed = if measured && self.prev_interval_s.is_finite() {
            0.5 * (interval_s + self.prev_interval_s)
        } else {
            interval_s
        };
        self.prev_interval_s = if measured { interval_s } else { f64::NAN };
        self.period_s += period_gain(observed, self.period_s) * (observed - self.period_s);
    }

    /// Confirm a bout from the newest `confirm_steps` pending candidates.
    ///
    /// The step period comes from the autocorrelation of the signal (see
    /// [`GaitPeriod`]), not from the candidates: secondary bumps or noise that add
    /// candidates between steps do not change it. Candidates closer than
    /// `refractory` × that period are one step (the larger is kept); the newest k that
    /// remain must then be spaced like steps of that period.
    fn try_confirm(&mut self, out: &mut Sink<'_>) {
        let p = self.p;
        let k = p.confirm_steps;
        if self.pending.len() < k {
            return;
        }
        let period = match self.gait.step_period(p.min_periodicity) {
            Some((period, _, _)) => period,
            None if !self.gait.ready() => match self.candidate_period(k) {
                Some(period) => period,
                None => return,
            },
            None => return,
        };
        if !(p.min_bout_interval_s..=p.max_step_interval_s).contains(&period) {
            return;
        }
        let mut kept: Ring<Pending, PENDING> = Ring::new();
        for c in self.pending.iter() {
            match kept.newest_mut() {
                Some(last) if c.event.t_s - last.event.t_s < p.refractory * period => {
                    *last = merge(last, &c);
                }
                _ => kept.push(c),
            }
        }
        if kept.len() < k {
            return;
        }
        // Intervals of the newest k candidates, oldest first.
        let mut iv = [0.0f64; PENDING];
        for (j, slot) in iv.iter_mut().enumerate().take(k - 1) {
            let a = kept.back(k - 1 - j).map(|c| c.event.t_s).unwrap_or(0.0);
            let b = kept.back(k - 2 - j).map(|c| c.event.t_s).unwrap_or(0.0);
            *slot = b - a;
        }
        let ivs = &iv[..k - 1];
        // Strides (two consecutive steps): left and right steps of a phone carried on
        // one side differ (0.45 s / 0.65 s in a front pocket), strides do not.
        let stride = 2.0 * period;
        if ivs
            .windows(2)
            .any(|w| (w[0] + w[1] - stride).abs() > p.regularity * stride)
        {
            return;
        }
        if ivs.iter().any(|&i| (i - period).abs() > ASYMMETRY * period) {
            return;
        }
        let mut amp = [0.0f64; PENDING];
        for (j, slot) in amp.iter_mut().enumerate().take(k) {
            *slot = kept.back(j).map(|c| c.amplitude_mps2).unwrap_or(0.0);
        }
        let amp = &mut amp[..k];
        amp.sort_by(f64::total_cmp);
        if period < p.running_interval_s && amp[k / 2] < p.running_min_amplitude_mps2 {
            // Running cadence without running impacts: secondary bumps of a slow walk.
            return;
        }
        let mut imp = [0.0f64; PENDING];
        for (j, slot) in imp.iter_mut().enumerate().take(k) {
            *slot = kept.back(j).map(|c| c.impact).unwrap_or(0.0);
        }
        let imp = &mut imp[..k];
        imp.sort_by(f64::total_cmp);
        if imp[k / 2] < p.min_impact_ratio {
            return;
        }
        // How the phone is held while walking: as at the newest candidate. Every
        // checked candidate must have it held the same way (within 45°); otherwise the
        // phone was handled or put away in between.
        let bout_carry = kept.newest().map_or([0.0; 3], |c| c.carry);
        if (0..k).any(|j| {
            kept.back(j)
                .is_some_and(|c| dot(c.carry, bout_carry) < CARRY_MIN_COS)
        }) {
            return;
        }
        self.pending = kept;
        self.in_bout = true;
        self.period_s = period;
        self.prev_interval_s = f64::NAN;
        // Only the newest k candidates were checked. Older ones waiting in the buffer
        // (handling the phone before walking, a stumble) are steps only if they chain
        // back from the bout with step-like intervals; the first that does not and all
        // before it are dropped.
        let n = self.pending.len();
        let mut keep = k;
        while keep < n {
            let (Some(older), Some(newer)) = (self.pending.back(keep), self.pending.back(keep - 1))
            else {
                break;
            };
            let iv = newer.event.t_s - older.event.t_s;
            // A step (±50 % of the period) or a step and a missed one (< 2.4 periods).
            if !((1.0 - ASYMMETRY) * period..2.4 * period).contains(&iv) {
                break;
            }
            // Held another way than while walking: the phone was being put away.
            if dot(older.carry, bout_carry) < CARRY_MIN_COS {
                break;
            }
            keep += 1;
        }
        let mut dropped: Ring<Pending, PENDING> = Ring::new();
        for _ in keep..n {
            if let Some(c) = self.pending.pop_front() {
                dropped.push(c);
            }
        }
        // The dropped candidates may be a short walk that a brief stop (under the
        // silence that keeps one, `max_step_interval_s`) parted from the bout: a
        // surveyor pausing at a waypoint, a walker at a door. They are kept as a short
        // walk when all of them form one (as before a longer stop) with the phone held
        // as in the bout, and released below on the same terms.
        if self.short_walk.is_empty()
            && self.is_short_walk(&dropped)
            && dropped
                .iter()
                .all(|c| dot(c.carry, bout_carry) >= CARRY_MIN_COS)
        {
            self.short_walk = dropped;
        }
        if let Some(first) = self.pending.get(0) {
            let gap = first.event.t_s - self.bout_end_t_s; // NaN without a previous bout
            let same_cadence =
                (period - self.bout_end_period_s).abs() <= 0.3 * self.bout_end_period_s;
            if gap <= FILL_MAX_GAP_S && same_cadence {
                let m = ((gap / period).round() as usize)
                    .saturating_sub(1)
                    .min(FILL_MAX_STEPS);
                let step = gap / (m + 1) as f64;
                if m > 0 {
                    // The gap is filled at the cadence: a short walk inside it is
                    // counted by the fill.
                    self.short_walk = Ring::new();
                }
                for i in 1..=m {
                    out.push(StepEvent {
                        t_s: self.bout_end_t_s + i as f64 * step,
                        duration_s: step,
                        ..first.event
                    });
                }
            }
        }
        self.bout_end_t_s = f64::NAN;
        self.bout_end_period_s = f64::NAN;
        self.release_short_walk(period, out);
        while let Some(c) = self.pending.pop_front() {
            out.push(c.event);
        }
    }

    /// The pending candidates are about to be dropped by a silence: keep them as a
    /// short walk if they look like one (at least [`SHORT_WALK_MIN`], spaced like
    /// steps: every interval within ±[`ASYMMETRY`] of their median, inside the bout
    /// interval range).
    fn keep_short_walk(&mut self) {
        if self.is_short_walk(&self.pending) {
            self.short_walk = self.pending;
        }
    }

    /// Whether the candidates of `ring` look like a short walk (at least
    /// [`SHORT_WALK_MIN`], every interval within ±[`ASYMMETRY`] of their median, the
    /// median inside the bout interval range).
    fn is_short_walk(&self, ring: &Ring<Pending, PENDING>) -> bool {
        let n = ring.len();
        if n < SHORT_WALK_MIN {
            return false;
        }
        let mut iv = [0.0f64; PENDING];
        for (j, slot) in iv.iter_mut().enumerate().take(n - 1) {
            let (Some(a), Some(b)) = (ring.get(j), ring.get(j + 1)) else {
                return false;
            };
            *slot = b.event.t_s - a.event.t_s;
        }
        let mut sorted = iv;
        let ivs = &mut sorted[..n - 1];
        ivs.sort_by(f64::total_cmp);
        let median = ivs[(n - 1) / 2];
        let p = self.p;
        (p.min_bout_interval_s..=p.max_step_interval_s).contains(&median)
            && iv[..n - 1]
                .iter()
                .all(|&i| (i - median).abs() <= ASYMMETRY * median)
    }

    /// A bout was just confirmed at `period` with the candidates in `pending`: release
    /// the kept short walk first if it ended at most [`SHORT_WALK_MAX_GAP_S`] before
    /// the bout, at its cadence and strength, with heel impacts (the same walker
    /// walking before a stop); drop it either way.
    fn release_short_walk(&mut self, period: f64, out: &mut Sink<'_>) {
        let short = std::mem::replace(&mut self.short_walk, Ring::new());
        let (Some(first), Some(last)) = (self.pending.get(0), short.newest()) else {
            return;
        };
        let gap = first.event.t_s - last.event.t_s;
        if !(gap > 0.0 && gap <= SHORT_WALK_MAX_GAP_S) {
            return;
        }
        let n = short.len();
        let mut prev = f64::NAN;
        let (mut amp, mut imp) = ([0.0f64; PENDING], [0.0f64; PENDING]);
        for (j, c) in short.iter().enumerate() {
            let iv = c.event.t_s - prev;
            if (iv - period).abs() > SHORT_WALK_CADENCE * period {
                return;
            }
            prev = c.event.t_s;
            amp[j] = c.amplitude_mps2;
            imp[j] = c.impact;
        }
        let mut bout = [0.0f64; PENDING];
        let m = self.pending.len();
        for (j, c) in self.pending.iter().enumerate() {
            bout[j] = c.amplitude_mps2;
        }
        let med = |v: &mut [f64]| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let (a_short, a_bout) = (med(&mut amp[..n]), med(&mut bout[..m]));
        if !(a_short * SHORT_WALK_AMPLITUDE >= a_bout && a_short <= SHORT_WALK_AMPLITUDE * a_bout)
            || med(&mut imp[..n]) < self.p.min_impact_ratio
        {
            return;
        }
        for c in short.iter() {
            out.push(c.event);
        }
    }

    /// Time of the newest sample pushed, s (`None` before the first).
    pub(crate) fn last_t_s(&self) -> Option<f64> {
        self.started.then_some(self.prev_t_s)
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        w.bool(self.started);
        w.f64s(&[
            self.lp1,
            self.lp2,
            self.prev_t_s,
            self.prev_y,
            self.next_grid_t_s,
            self.mean,
            self.ms,
        ]);
        w.f64s(&self.carry);
        w.u64(self.xs.len as u64);
        for &v in self.xs.last(self.xs.len) {
            w.f64(v);
        }
        w.bool(self.seeking_peak);
        w.f64s(&[self.ext_x, self.ext_t_s, self.valley_x]);
        self.moments.write(w);
        for ring in [&self.pending, &self.short_walk] {
            w.u64(ring.len() as u64);
            for c in ring.iter() {
                super::write_event(w, &c.event);
                w.f64(c.impact);
                w.f64(c.amplitude_mps2);
                w.f64s(&c.carry);
            }
        }
        w.bool(self.in_bout);
        w.f64s(&[
            self.period_s,
            self.prev_interval_s,
            self.last_t_s,
            self.missing_s,
            self.hf_sum_sq,
            self.hf_n,
            self.hp[0],
            self.hp[1],
            self.amplitude_ref_mps2,
            self.bout_end_t_s,
            self.bout_end_period_s,
            self.data_gap_end_t_s,
            self.data_gap_s,
        ]);
        self.gait.write(w);
        w.bool(self.tail.is_some());
        if let Some(ev) = &self.tail {
            super::write_event(w, ev);
        }
    }

    pub(crate) fn read(r: &mut Reader, p: RobustStepParams) -> Result<Self, SnapshotError> {
        // Every signal state is a filtered acceleration magnitude (or a difference of
        // two): it stays within the magnitude limit of the door, its squares within
        // the square of it.
        const A: f64 = crate::input::limits::MAX_ACCEL_NORM_MPS2;
        const T: f64 = crate::input::limits::MAX_ABS_T_S + 1.0;
        let mut d = Self::new(p);
        d.started = r.bool()?;
        d.lp1 = r.f64_in(0.0, A, "step detector low-pass")?;
        d.lp2 = r.f64_in(0.0, A, "step detector low-pass")?;
        d.prev_t_s = r.f64_in(-T, T, "step detector time")?;
        d.prev_y = r.f64_in(0.0, A, "step detector low-pass")?;
        d.next_grid_t_s = r.f64_in(-T, T, "step detector grid time")?;
        d.mean = r.f64_in(0.0, A, "step detector mean")?;
        d.ms = r.f64_in(0.0, A * A, "step detector variance")?;
        // The grid follows the input: the next grid point lies within one grid step
        // after the newest sample (to the rounding of the grid's additions, which
        // grows with |t|: 0.02 s steps at t = 1e9 s round to ~1e-7 s).
        let tol = 1e-9 + 64.0 * f64::EPSILON * d.prev_t_s.abs().max(d.next_grid_t_s.abs());
        if d.started
            && !(d.next_grid_t_s > d.prev_t_s - tol
                && d.next_grid_t_s <= d.prev_t_s + GRID_DT_S + tol)
        {
            return Err(SnapshotError::Invalid("step detector grid time"));
        }
        for v in &mut d.carry {
            *v = r.f64_in(-A, A, "step detector carrying")?;
        }
        let n = r.len(HISTORY)?;
        for _ in 0..n {
            d.xs.push(r.f64_in(-A, A, "step detector history")?);
        }
        d.seeking_peak = r.bool()?;
        // ext_x starts at −∞; valley_x is NaN before the first valley.
        d.ext_x = r.f64_any()?;
        if !(d.ext_x == f64::NEG_INFINITY || (-A..=A).contains(&d.ext_x)) {
            return Err(SnapshotError::Invalid("step detector extremum"));
        }
        d.ext_t_s = r.f64_in(-T, T, "step detector time")?;
        d.valley_x = r.f64_or_nan()?;
        if d.valley_x.abs() > A {
            return Err(SnapshotError::Invalid("step detector valley"));
        }
        d.moments = Moments::read(r)?;
        for ring in [&mut d.pending, &mut d.short_walk] {
            let n = r.len(PENDING)?;
            for _ in 0..n {
                let event = super::read_event(r)?;
                let impact = r.f64_or_nan()?;
                let amplitude_mps2 = r.f64_or_nan()?;
                let mut carry = [0.0; 3];
                r.f64s(&mut carry)?;
                // A unit vector (or zero, when the acceleration averaged to nothing).
                if impact < 0.0
                    || !(amplitude_mps2.is_nan() || (0.0..=2.0 * A).contains(&amplitude_mps2))
                    || dot(carry, carry) > 1.0 + 1e-9
                {
                    return Err(SnapshotError::Invalid("step candidate"));
                }
                ring.push(Pending {
                    event,
                    impact,
                    amplitude_mps2,
                    carry,
                });
            }
        }
        d.in_bout = r.bool()?;
        // NaN before the first bout / step / bout end.
        d.period_s = r.f64_or_nan()?;
        d.prev_interval_s = r.f64_or_nan()?;
        d.last_t_s = r.f64_or_nan()?;
        d.missing_s = r.f64_in(0.0, 2.0 * T, "step detector missing time")?;
        d.hf_sum_sq = r.f64()?;
        d.hf_n = r.f64()?;
        d.hp = [
            r.f64_in(0.0, A, "step detector high-pass")?,
            r.f64_in(-A, A, "step detector high-pass")?,
        ];
        d.amplitude_ref_mps2 = r.f64_in(0.0, 2.0 * A, "step amplitude")?;
        d.bout_end_t_s = r.f64_or_nan()?;
        d.bout_end_period_s = r.f64_or_nan()?;
        // NaN before the first gap in the data.
        d.data_gap_end_t_s = r.f64_or_nan()?;
        d.data_gap_s = r.f64_in(0.0, MAX_INPUT_GAP_S, "step detector gap")?;
        d.gait = GaitPeriod::read(r)?;
        d.tail = if r.bool()? {
            Some(super::read_event(r)?)
        } else {
            None
        };
        let period_ok = |p: f64| p.is_nan() || (0.0..=60.0).contains(&p);
        let time_ok = |t: f64| t.is_nan() || t.abs() <= T;
        let ok = d.hf_n >= 0.0
            && (0.0..=d.hf_n * 4.0 * A * A).contains(&d.hf_sum_sq)
            && period_ok(d.period_s)
            && period_ok(d.prev_interval_s)
            && period_ok(d.bout_end_period_s)
            && time_ok(d.last_t_s)
            && time_ok(d.bout_end_t_s)
            && time_ok(d.data_gap_end_t_s)
            && d.tail.is_none_or(|ev| ev.t_s.abs() <= T);
        if !ok {
            return Err(SnapshotError::Invalid("step detector statistics"));
        }
        Ok(d)
    }
}
