//! Snapshot of the default detector inside the step detector's: the writer
//! destructures every level without `..` (a new field left out is a compile error),
//! the reader builds the detector field by field, each checked against its bounds.

use super::held::HELD;
use super::history::{History, HISTORY};
use super::pending::Pending;
use super::{
    Derived, RobustDetector, RobustStepParams, StepEvent, GRID_DT_S, MAX_INPUT_GAP_S, PENDING,
};
use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};
use crate::stepdetect::gait::GaitPeriod;
use crate::stepdetect::{read_event, write_event, Moments};
use crate::vec3::dot;

/// Every signal state is a filtered acceleration magnitude (or a difference of two):
/// it stays within the magnitude limit of the door, its squares within its square.
const A: f64 = crate::input::limits::MAX_ACCEL_NORM_MPS2;
/// Times within the door's limit (and a rounding margin), s.
const T: f64 = crate::input::limits::MAX_ABS_T_S + 1.0;
/// Longest plausible step period, s.
const MAX_PERIOD_S: f64 = 60.0;
/// The grid's rounding grows with |t| (0.02 s steps at t = 1e9 s round to ~1e-7 s):
/// absolute and relative (in ε) tolerance of the grid time against the input's.
const GRID_TOL_ABS_S: f64 = 1e-9;
const GRID_TOL_EPS: f64 = 64.0;
/// A candidate's carrying is a unit vector (or zero): its squared norm within this.
const UNIT_NORM2_TOL: f64 = 1e-9;

impl RobustDetector {
    pub(crate) fn write(&self, w: &mut Writer) {
        let RobustDetector {
            // The parameters are written by the step detector, the rest derive from them.
            p: _,
            tau_lp_s: _,
            gain_mean: _,
            gain_ms: _,
            started,
            lp1,
            lp2,
            prev_t_s,
            prev_y,
            next_grid_t_s,
            carry,
            mean,
            ms,
            xs,
            seeking_peak,
            ext_x,
            ext_t_s,
            valley_x,
            moments,
            pending,
            short_walk,
            in_bout,
            period_s,
            prev_interval_s,
            last_t_s,
            missing_s,
            hf_sum_sq,
            hf_n,
            hp,
            amplitude_ref_mps2,
            bout_end_t_s,
            bout_end_period_s,
            data_gap_end_t_s,
            data_gap_s,
            gait,
            tail,
            held,
        } = self;
        w.bool(*started);
        w.f64s(&[*lp1, *lp2, *prev_t_s, *prev_y, *next_grid_t_s, *mean, *ms]);
        w.f64s(carry);
        write_history(w, xs);
        w.bool(*seeking_peak);
        w.f64s(&[*ext_x, *ext_t_s, *valley_x]);
        moments.write(w);
        for ring in [pending, short_walk] {
            write_candidates(w, ring);
        }
        w.bool(*in_bout);
        w.f64s(&[
            *period_s,
            *prev_interval_s,
            *last_t_s,
            *missing_s,
            *hf_sum_sq,
            *hf_n,
            hp[0],
            hp[1],
            *amplitude_ref_mps2,
            *bout_end_t_s,
            *bout_end_period_s,
            *data_gap_end_t_s,
            *data_gap_s,
        ]);
        gait.write(w);
        w.bool(tail.is_some());
        if let Some(ev) = tail {
            write_event(w, ev);
        }
        w.u64(held.len() as u64);
        for ev in held.iter() {
            write_event(w, &ev);
        }
    }

    pub(crate) fn read(r: &mut Reader, p: RobustStepParams) -> Result<Self, SnapshotError> {
        // In the writer's order: signal, history, peak search, candidates, bout.
        let sig = read_signal(r)?;
        let xs = read_history(r)?;
        let peak = read_peak(r)?;
        let moments = Moments::read(r)?;
        let pending = read_candidates(r)?;
        let short_walk = read_candidates(r)?;
        let bout = read_bout(r)?;
        let held = read_held(r, &bout)?;
        let Derived {
            tau_lp_s,
            gain_mean,
            gain_ms,
        } = Derived::of(&p);
        Ok(Self {
            p,
            tau_lp_s,
            gain_mean,
            gain_ms,
            started: sig.started,
            lp1: sig.lp1,
            lp2: sig.lp2,
            prev_t_s: sig.prev_t_s,
            prev_y: sig.prev_y,
            next_grid_t_s: sig.next_grid_t_s,
            carry: sig.carry,
            mean: sig.mean,
            ms: sig.ms,
            xs,
            seeking_peak: peak.seeking_peak,
            ext_x: peak.ext_x,
            ext_t_s: peak.ext_t_s,
            valley_x: peak.valley_x,
            moments,
            pending,
            short_walk,
            in_bout: bout.in_bout,
            period_s: bout.period_s,
            prev_interval_s: bout.prev_interval_s,
            last_t_s: bout.last_t_s,
            missing_s: bout.missing_s,
            hf_sum_sq: bout.hf_sum_sq,
            hf_n: bout.hf_n,
            hp: bout.hp,
            amplitude_ref_mps2: bout.amplitude_ref_mps2,
            bout_end_t_s: bout.bout_end_t_s,
            bout_end_period_s: bout.bout_end_period_s,
            data_gap_end_t_s: bout.data_gap_end_t_s,
            data_gap_s: bout.data_gap_s,
            gait: bout.gait,
            tail: bout.tail,
            held,
        })
    }
}

/// The steps held off the cadence: only inside a bout and without a held last step,
/// in time order, none after the bout's last step.
fn read_held(r: &mut Reader, bout: &BoutState) -> Result<Ring<StepEvent, HELD>, SnapshotError> {
    let n = r.len(HELD)?;
    let mut held = Ring::new();
    let mut prev_t_s = f64::NEG_INFINITY;
    for _ in 0..n {
        let ev = read_event(r)?;
        if !(ev.t_s >= prev_t_s && ev.t_s <= bout.last_t_s) {
            return Err(SnapshotError::Invalid("step detector held steps"));
        }
        prev_t_s = ev.t_s;
        held.push(ev);
    }
    if n > 0 && (!bout.in_bout || bout.tail.is_some()) {
        return Err(SnapshotError::Invalid("step detector held steps"));
    }
    Ok(held)
}

/// The signal chain's state as read (see [`read_signal`]).
struct SignalState {
    started: bool,
    lp1: f64,
    lp2: f64,
    prev_t_s: f64,
    prev_y: f64,
    next_grid_t_s: f64,
    mean: f64,
    ms: f64,
    carry: [f64; 3],
}

/// The low-passes, the grid, the running moments and the carrying, each in bounds.
fn read_signal(r: &mut Reader) -> Result<SignalState, SnapshotError> {
    let started = r.bool()?;
    let lp1 = r.f64_in(0.0, A, "step detector low-pass")?;
    let lp2 = r.f64_in(0.0, A, "step detector low-pass")?;
    let prev_t_s = r.f64_in(-T, T, "step detector time")?;
    let prev_y = r.f64_in(0.0, A, "step detector low-pass")?;
    let next_grid_t_s = r.f64_in(-T, T, "step detector grid time")?;
    let mean = r.f64_in(0.0, A, "step detector mean")?;
    let ms = r.f64_in(0.0, A * A, "step detector variance")?;
    check_grid_time(started, prev_t_s, next_grid_t_s)?;
    let mut carry = [0.0; 3];
    for v in &mut carry {
        *v = r.f64_in(-A, A, "step detector carrying")?;
    }
    Ok(SignalState {
        started,
        lp1,
        lp2,
        prev_t_s,
        prev_y,
        next_grid_t_s,
        mean,
        ms,
        carry,
    })
}

/// The peak search's state as read (see [`read_peak`]).
struct PeakState {
    seeking_peak: bool,
    ext_x: f64,
    ext_t_s: f64,
    valley_x: f64,
}

/// The peak search: ext_x starts at −∞; valley_x is NaN before the first valley.
fn read_peak(r: &mut Reader) -> Result<PeakState, SnapshotError> {
    let seeking_peak = r.bool()?;
    let ext_x = r.f64_any()?;
    if !(ext_x == f64::NEG_INFINITY || (-A..=A).contains(&ext_x)) {
        return Err(SnapshotError::Invalid("step detector extremum"));
    }
    let ext_t_s = r.f64_in(-T, T, "step detector time")?;
    let valley_x = r.f64_or_nan()?;
    if valley_x.abs() > A {
        return Err(SnapshotError::Invalid("step detector valley"));
    }
    Ok(PeakState {
        seeking_peak,
        ext_x,
        ext_t_s,
        valley_x,
    })
}

/// The bout, period, impact and gap state as read (see [`read_bout`]).
struct BoutState {
    in_bout: bool,
    period_s: f64,
    prev_interval_s: f64,
    last_t_s: f64,
    missing_s: f64,
    hf_sum_sq: f64,
    hf_n: f64,
    hp: [f64; 2],
    amplitude_ref_mps2: f64,
    bout_end_t_s: f64,
    bout_end_period_s: f64,
    data_gap_end_t_s: f64,
    data_gap_s: f64,
    gait: GaitPeriod,
    tail: Option<StepEvent>,
}

/// The bout and its periods, the impact statistics, the gap and the held step, each in
/// bounds and checked together ([`check_statistics`]).
fn read_bout(r: &mut Reader) -> Result<BoutState, SnapshotError> {
    let in_bout = r.bool()?;
    // NaN before the first bout / step / bout end.
    let period_s = r.f64_or_nan()?;
    let prev_interval_s = r.f64_or_nan()?;
    let last_t_s = r.f64_or_nan()?;
    let missing_s = r.f64_in(0.0, 2.0 * T, "step detector missing time")?;
    let hf_sum_sq = r.f64()?;
    let hf_n = r.f64()?;
    let hp = [
        r.f64_in(0.0, A, "step detector high-pass")?,
        r.f64_in(-A, A, "step detector high-pass")?,
    ];
    let amplitude_ref_mps2 = r.f64_in(0.0, 2.0 * A, "step amplitude")?;
    let bout_end_t_s = r.f64_or_nan()?;
    let bout_end_period_s = r.f64_or_nan()?;
    // NaN before the first gap in the data.
    let data_gap_end_t_s = r.f64_or_nan()?;
    let data_gap_s = r.f64_in(0.0, MAX_INPUT_GAP_S, "step detector gap")?;
    let gait = GaitPeriod::read(r)?;
    let tail = if r.bool()? {
        Some(read_event(r)?)
    } else {
        None
    };
    let times = [last_t_s, bout_end_t_s, data_gap_end_t_s];
    let periods = [period_s, prev_interval_s, bout_end_period_s];
    check_statistics(hf_n, hf_sum_sq, periods, times, tail)?;
    Ok(BoutState {
        in_bout,
        period_s,
        prev_interval_s,
        last_t_s,
        missing_s,
        hf_sum_sq,
        hf_n,
        hp,
        amplitude_ref_mps2,
        bout_end_t_s,
        bout_end_period_s,
        data_gap_end_t_s,
        data_gap_s,
        gait,
        tail,
    })
}

/// The impact sums, the periods (NaN before the first bout), the times (NaN before the
/// first step, bout end, data gap) and the held step.
fn check_statistics(
    hf_n: f64,
    hf_sum_sq: f64,
    periods: [f64; 3],
    times: [f64; 3],
    tail: Option<StepEvent>,
) -> Result<(), SnapshotError> {
    let period_ok = |p: f64| p.is_nan() || (0.0..=MAX_PERIOD_S).contains(&p);
    let time_ok = |t: f64| t.is_nan() || t.abs() <= T;
    let ok = hf_n >= 0.0
        && (0.0..=hf_n * 4.0 * A * A).contains(&hf_sum_sq)
        && periods.into_iter().all(period_ok)
        && times.into_iter().all(time_ok)
        && tail.is_none_or(|ev| ev.t_s.abs() <= T);
    if ok {
        Ok(())
    } else {
        Err(SnapshotError::Invalid("step detector statistics"))
    }
}

/// The grid follows the input: the next grid point lies within one grid step after
/// the newest sample (to the rounding of the grid's additions).
fn check_grid_time(started: bool, prev_t_s: f64, next_grid_t_s: f64) -> Result<(), SnapshotError> {
    let tol =
        GRID_TOL_ABS_S + GRID_TOL_EPS * f64::EPSILON * prev_t_s.abs().max(next_grid_t_s.abs());
    if started && !(next_grid_t_s > prev_t_s - tol && next_grid_t_s <= prev_t_s + GRID_DT_S + tol) {
        return Err(SnapshotError::Invalid("step detector grid time"));
    }
    Ok(())
}

/// The grid history as its values, oldest first (the ring's storage and position
/// follow from them).
fn write_history(w: &mut Writer, xs: &History) {
    let History {
        buf: _,
        pos: _,
        len,
    } = xs;
    w.u64(*len as u64);
    for &v in xs.last(*len) {
        w.f64(v);
    }
}

fn read_history(r: &mut Reader) -> Result<History, SnapshotError> {
    let mut xs = History::new();
    let n = r.len(HISTORY)?;
    for _ in 0..n {
        xs.push(r.f64_in(-A, A, "step detector history")?);
    }
    Ok(xs)
}

fn write_candidates(w: &mut Writer, ring: &Ring<Pending, PENDING>) {
    w.u64(ring.len() as u64);
    for c in ring.iter() {
        let Pending {
            event,
            impact,
            amplitude_mps2,
            carry,
            missing_before_s,
        } = c;
        write_event(w, &event);
        w.f64(impact);
        w.f64(amplitude_mps2);
        w.f64s(&carry);
        w.f64(missing_before_s);
    }
}

fn read_candidates(r: &mut Reader) -> Result<Ring<Pending, PENDING>, SnapshotError> {
    let mut ring = Ring::new();
    let n = r.len(PENDING)?;
    for _ in 0..n {
        let event = read_event(r)?;
        let impact = r.f64_or_nan()?;
        let amplitude_mps2 = r.f64_or_nan()?;
        let mut carry = [0.0; 3];
        r.f64s(&mut carry)?;
        let missing_before_s = r.f64_in(0.0, 2.0 * T, "step candidate missing time")?;
        // A unit vector (or zero, when the acceleration averaged to nothing).
        if impact < 0.0
            || !(amplitude_mps2.is_nan() || (0.0..=2.0 * A).contains(&amplitude_mps2))
            || dot(carry, carry) > 1.0 + UNIT_NORM2_TOL
        {
            return Err(SnapshotError::Invalid("step candidate"));
        }
        ring.push(Pending {
            event,
            impact,
            amplitude_mps2,
            carry,
            missing_before_s,
        });
    }
    Ok(ring)
}
