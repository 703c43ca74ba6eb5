//! Snapshot and restore of the [`FootNavigator`]: the configuration, the whole filter state and the latest estimate, versioned and checksummed. Exhaustive destructuring of the navigator and of its configuration makes a field that is not written a compile error.

use super::*;
use crate::foot::accel_clip::{
    AccelCeiling, ClipRun, Side as AccelSide, MAX_PEAK_SHARE, UNKNOWN_SHARE,
};
use crate::foot::hole::Hole;
use crate::foot::still::{StillFloor, STILL_CAP};
use crate::foot::unresolved::{Unresolved, TRAPEZOID_ERROR};
use crate::foot::zaru::{StillRun, StillWindow, Zaru};

mod config;

use self::config::{read_config, write_config};

/// Snapshot engine kind byte of the foot navigator.
const SNAPSHOT_KIND: u8 = 6;
/// Version 12: the still runs of the bias-jump check (`Zaru::run`, `Zaru::longest`: count, first and last time, rate sums, squared-norm sums) and the end of the last explained one (`Zaru::explained_t_s`). Version 11: the accelerometer's ceiling per axis and sign (`AccelCeiling`), its clipped runs (`ClipRun`), the specific force clipped samples did not report and a clipped impact's peak (`BodySample::clip_unknown_mps2`, `impact_mps2`). Version 10: the rotation the samples do not resolve (`Unresolved`: the last raw rate and its change; `BodySample::unresolved_rad`). Version 9: the gyroscope bias jumps' state (`Zaru`: the stance's stillest still window, the last unexplained still rate) and their count. Version 8: the hole state (`Hole`: the last stance onset's heading, the turn rate, a hole waiting for its stance) and the count of re-levelled stances. Version 7: the detector's stillness floor (`StillFloor`). Version 6: `FootConfig::level_stride_max_grade`, `Stride::levelled_m` and the gyroscope clipping repair. Version 5: `FootConfig::accel_alignment_rad`. Version 4: `FootConfig::zupt_gate_nis`. Version 3: the input layer's time state
/// ([`TimeGuard`]) replaces the last time (version 2 added `FootConfig::gyro_timing`
/// and the adaptive SHOE detector).
const SNAPSHOT_VERSION: u16 = 12;

fn write_body(w: &mut Writer, s: &BodySample) {
    let BodySample {
        t_s,
        f,
        w: rate,
        saturated,
        external,
        unresolved_rad,
        clip_unknown_mps2,
        impact_mps2,
    } = s;
    w.f64(*t_s);
    w.f64s(f);
    w.f64s(rate);
    w.bool(*saturated);
    w.u8(match external {
        None => 0,
        Some(false) => 1,
        Some(true) => 2,
    });
    w.f64s(unresolved_rad);
    w.f64s(clip_unknown_mps2);
    w.f64(*impact_mps2);
}

fn read_body(r: &mut Reader) -> Result<BodySample, SnapshotError> {
    let mut s = BodySample {
        t_s: r.f64()?,
        ..Default::default()
    };
    r.f64s(&mut s.f)?;
    r.f64s(&mut s.w)?;
    s.saturated = r.bool()?;
    s.external = match r.u8()? {
        0 => None,
        1 => Some(false),
        2 => Some(true),
        _ => return Err(SnapshotError::Invalid("external stance")),
    };
    r.f64s(&mut s.unresolved_rad)?;
    r.f64s(&mut s.clip_unknown_mps2)?;
    s.impact_mps2 = r.f64()?;
    if !(s.t_s.is_finite()
        && s.unresolved_rad.iter().all(|v| v.is_finite())
        && s.clip_unknown_mps2.iter().all(|v| v.is_finite())
        && s.impact_mps2.is_finite()
        && s.f.iter().all(|v| v.is_finite())
        && s.w.iter().all(|v| v.is_finite()))
    {
        return Err(SnapshotError::Invalid("non-finite sample"));
    }
    Ok(s)
}

fn write_clip(w: &mut Writer, c: &AxisClip) {
    let AxisClip {
        prev,
        active,
        sign,
        ceiling,
        slope,
        t_entry,
        pending_rad,
        pending_n,
    } = c;
    for (t, m) in prev {
        w.f64(*t);
        w.f64(*m);
    }
    w.bool(*active);
    w.f64s(&[*sign, *ceiling, *slope, *t_entry, *pending_rad]);
    w.u64(u64::from(*pending_n));
}

fn read_clip(r: &mut Reader) -> Result<AxisClip, SnapshotError> {
    let mut c = AxisClip::new();
    for p in c.prev.iter_mut() {
        *p = (r.f64_or_nan()?, r.f64_or_nan()?);
    }
    c.active = r.bool()?;
    c.sign = r.f64()?;
    c.ceiling = r.f64()?;
    c.slope = r.f64_or_nan()?;
    c.t_entry = r.f64()?;
    c.pending_rad = r.f64()?;
    c.pending_n = u32::try_from(r.u64()?)
        .ok()
        .filter(|n| *n <= MAX_MEDIAN_WINDOW as u32)
        .ok_or(SnapshotError::Invalid("clip repair"))?;
    if c.pending_rad.abs() > super::super::clip::MAX_RESTORED_RAD * 2.0 {
        return Err(SnapshotError::Invalid("clip repair"));
    }
    Ok(c)
}

fn write_clip_run(w: &mut Writer, c: &ClipRun) {
    let ClipRun {
        prev,
        active,
        sign,
        ceiling,
        entry,
        rise,
        len,
        norm2,
        exit,
    } = c;
    w.f64s(prev);
    w.bool(*active);
    w.f64s(&[*sign, *ceiling, *entry, *rise]);
    w.u64(u64::from(*len));
    w.f64s(&[*norm2, *exit]);
}

fn read_clip_run(r: &mut Reader) -> Result<ClipRun, SnapshotError> {
    let mut c = ClipRun::default();
    for p in c.prev.iter_mut() {
        *p = r.f64_or_nan()?;
    }
    c.active = r.bool()?;
    c.sign = r.f64()?;
    c.ceiling = r.f64()?;
    c.entry = r.f64_or_nan()?;
    c.rise = r.f64_or_nan()?;
    c.len = u32::try_from(r.u64()?).map_err(|_| SnapshotError::Invalid("clipped run"))?;
    c.norm2 = r.f64()?;
    c.exit = r.f64_or_nan()?;
    Ok(c)
}

fn write_v3(w: &mut Writer, v: &Vector3<f64>) {
    w.f64s(v.as_slice());
}

fn read_v3(r: &mut Reader) -> Result<Vector3<f64>, SnapshotError> {
    let mut a = [0.0; 3];
    r.f64s(&mut a)?;
    Ok(Vector3::from(a))
}

fn write_estimate(w: &mut Writer, e: &FootEstimate) {
    let FootEstimate {
        t_s,
        position_m,
        velocity_mps,
        quaternion,
        roll_rad,
        pitch_rad,
        yaw_rad,
        heading_rad,
        position_std_m,
        velocity_std_mps,
        tilt_std_rad,
        heading_std_rad,
        accel_bias_mps2,
        gyro_bias_rads,
        stance,
        strides,
        distance_m,
        stride,
        saturated,
        gap,
    } = e;
    w.f64(*t_s);
    w.f64s(position_m);
    w.f64s(velocity_mps);
    w.f64s(quaternion);
    w.f64s(&[*roll_rad, *pitch_rad, *yaw_rad, *heading_rad]);
    w.f64s(position_std_m);
    w.f64s(velocity_std_mps);
    w.f64s(tilt_std_rad);
    w.f64(*heading_std_rad);
    w.f64s(accel_bias_mps2);
    w.f64s(gyro_bias_rads);
    w.bool(*stance);
    w.u64(*strides);
    w.f64(*distance_m);
    w.bool(stride.is_some());
    let s = stride.unwrap_or_default();
    w.f64s(&s.values());
    w.bool(*saturated);
    w.bool(*gap);
}

fn read_estimate(r: &mut Reader) -> Result<FootEstimate, SnapshotError> {
    let mut e = FootEstimate {
        t_s: r.f64()?,
        ..Default::default()
    };
    r.f64s(&mut e.position_m)?;
    r.f64s(&mut e.velocity_mps)?;
    r.f64s(&mut e.quaternion)?;
    let mut a = [0.0; 4];
    r.f64s(&mut a)?;
    [e.roll_rad, e.pitch_rad, e.yaw_rad, e.heading_rad] = a;
    r.f64s(&mut e.position_std_m)?;
    r.f64s(&mut e.velocity_std_mps)?;
    r.f64s(&mut e.tilt_std_rad)?;
    e.heading_std_rad = r.f64()?;
    r.f64s(&mut e.accel_bias_mps2)?;
    r.f64s(&mut e.gyro_bias_rads)?;
    e.stance = r.bool()?;
    e.strides = r.u64()?;
    e.distance_m = r.f64()?;
    let has_stride = r.bool()?;
    let mut s = [0.0; 6];
    r.f64s(&mut s)?;
    e.stride = has_stride.then_some(Stride {
        t_s: s[0],
        length_m: s[1],
        duration_s: s[2],
        speed_mps: s[3],
        climb_m: s[4],
        levelled_m: s[5],
    });
    e.saturated = r.bool()?;
    e.gap = r.bool()?;
    Ok(e)
}

impl FootNavigator {
    /// The whole state as bytes (engine kind 6, versioned, checksummed): restoring
    /// continues with bit-identical estimates. The SVM detector's model is stored as
    /// its text form (a few hundred kB for the shipped model).
    pub fn snapshot(&self) -> Vec<u8> {
        // Exhaustive on purpose: a new field must be written (or said to be derived).
        let FootNavigator {
            config,
            noise: _,          // derived from the configuration at restore
            accel_rotation: _, // likewise
            time,
            units,
            median,
            clip,
            unresolved,
            accel_ceiling,
            accel_runs,
            det,
            gait,
            still,
            align,
            window,
            rate_hz,
            ins,
            ins_t,
            stance,
            swing_start_t,
            last_onset,
            hole,
            relevels,
            zaru,
            bias_jumps,
            strides,
            distance_m,
            resets,
            latest,
        } = self;
        let mut w = Writer::new(SNAPSHOT_KIND, SNAPSHOT_VERSION);
        write_config(&mut w, config);
        time.write(&mut w);
        units.write(&mut w);
        w.u64(median.samples().count() as u64);
        for s in median.samples() {
            write_body(&mut w, &s);
        }
        for c in clip {
            write_clip(&mut w, c);
        }
        let Unresolved {
            seen,
            prev_w,
            prev_dw,
        } = unresolved;
        w.u8(*seen);
        w.f64s(prev_w);
        w.f64s(prev_dw);
        let AccelCeiling { sides } = accel_ceiling;
        for side in sides.iter().flatten() {
            let AccelSide {
                peak,
                hits,
                at_level,
            } = side;
            w.f64(*peak);
            w.u64(u64::from(*hits));
            w.bool(*at_level);
        }
        for run in accel_runs {
            write_clip_run(&mut w, run);
        }
        w.u64(det.len() as u64);
        for s in det.iter() {
            write_body(&mut w, &s);
        }
        w.u64(gait.len() as u64);
        for (t, v) in gait.iter() {
            w.f64(t);
            w.f64(v);
        }
        let StillFloor { acc, gyro } = still;
        for q in [acc, gyro] {
            w.u64(q.len() as u64);
            for (t, v) in q.iter() {
                w.f64(t);
                w.f64(v);
            }
        }
        let Alignment {
            n,
            t_first,
            t_last,
            sum_f,
            sum_w,
        } = align;
        w.u64(*n);
        w.f64(*t_first);
        w.f64(*t_last);
        w.f64s(sum_f);
        w.f64s(sum_w);
        w.u64(*window as u64);
        w.f64(*rate_hz);
        w.bool(ins.is_some());
        if let Some(Strapdown {
            q,
            v,
            p,
            ba,
            bg,
            cov,
            g,
            prev_f,
            prev_w,
        }) = ins
        {
            w.f64s(q.coords.as_slice());
            for x in [v, p, ba, bg] {
                write_v3(&mut w, x);
            }
            w.f64s(cov.as_slice());
            w.f64(*g);
            write_v3(&mut w, prev_f);
            write_v3(&mut w, prev_w);
        }
        w.f64(*ins_t);
        w.bool(*stance);
        w.f64(*swing_start_t);
        w.bool(last_onset.is_some());
        let (t0, p0) = last_onset.unwrap_or_default();
        w.f64(t0);
        w.f64s(&p0);
        let Hole {
            onset,
            turn_rads,
            pending,
        } = hole;
        w.bool(onset.is_some());
        let (t, yaw) = onset.unwrap_or_default();
        w.f64s(&[t, yaw, *turn_rads]);
        w.bool(*pending);
        w.u64(*relevels);
        let Zaru {
            window: still_window,
            unexplained,
            stance_n,
            run,
            longest,
            explained_t_s,
        } = zaru;
        w.bool(still_window.is_some());
        let StillWindow {
            var_rads2,
            mean_rads,
            n: still_n,
        } = still_window.unwrap_or_default();
        w.f64(var_rads2);
        w.f64s(&mean_rads);
        w.u64(still_n as u64);
        w.bool(unexplained.is_some());
        w.f64s(&unexplained.unwrap_or_default());
        w.u64(*stance_n);
        for r in [run, longest] {
            let StillRun {
                n: run_n,
                t0_s,
                t1_s,
                sum_rads,
                sum_sq_rads2,
            } = r;
            w.u64(*run_n);
            w.f64s(&[*t0_s, *t1_s]);
            w.f64s(sum_rads);
            w.f64(*sum_sq_rads2);
        }
        w.bool(explained_t_s.is_some());
        w.f64(explained_t_s.unwrap_or_default());
        w.u64(*bias_jumps);
        w.u64(*strides);
        w.f64(*distance_m);
        w.u64(*resets);
        w.bool(latest.is_some());
        write_estimate(&mut w, &latest.unwrap_or_default());
        w.finish()
    }

    /// Whether a restored state is one the navigator can be in: samples within the
    /// door's limits, sums within what that many samples can add up to, the
    /// navigation state within the divergence guard, a covariance.
    fn check_state(&self) -> Result<(), &'static str> {
        use crate::input::limits::{MAX_ABS_T_S, MAX_ACCEL_NORM_MPS2 as A};
        let w_max = crate::input::limits::MAX_GYRO_RADS * 3f64.sqrt();
        let t_ok = |t: f64| t.abs() <= MAX_ABS_T_S + 1.0;
        // The second difference of rates within the door's limits, over the longest
        // interval integrated.
        let unresolved_max = 4.0 * w_max * self.config.max_gap_s * TRAPEZOID_ERROR;
        let sample_ok = |s: &BodySample| {
            t_ok(s.t_s)
                && s.f.iter().all(|v| v.abs() <= A)
                && s.w.iter().all(|v| v.abs() <= w_max)
                && s.unresolved_rad
                    .iter()
                    .all(|v| (0.0..=unresolved_max).contains(v))
                && s.clip_unknown_mps2
                    .iter()
                    .all(|v| (0.0..=UNKNOWN_SHARE * A).contains(v))
                && (0.0..=MAX_PEAK_SHARE * A * 3f64.sqrt()).contains(&s.impact_mps2)
        };
        // Clipped runs of values the door lets through.
        let within = |v: f64| v.is_nan() || v.abs() <= A;
        if !self.accel_runs.iter().all(|c| {
            c.prev.iter().all(|&v| within(v))
                && [-1.0, 0.0, 1.0].contains(&c.sign)
                && (0.0..=A).contains(&c.ceiling)
                && within(c.entry)
                && (c.rise.is_nan() || c.rise.abs() <= 2.0 * A)
                && (0.0..=3.0 * A * A).contains(&c.norm2)
                && within(c.exit)
        }) {
            return Err("clipped run");
        }
        // A largest magnitude the door lets through (0 before any sample).
        if !self
            .accel_ceiling
            .sides
            .iter()
            .flatten()
            .all(|s| (0.0..=A).contains(&s.peak))
        {
            return Err("accelerometer ceiling");
        }
        let u = &self.unresolved;
        if !(u.seen <= 2
            && u.prev_w.iter().all(|v| v.abs() <= w_max)
            && u.prev_dw.iter().all(|v| v.abs() <= 2.0 * w_max))
        {
            return Err("unresolved rotation");
        }
        if !self.median.samples().all(|s| sample_ok(&s)) || !self.det.iter().all(|s| sample_ok(&s))
        {
            return Err("buffered sample");
        }
        if !self
            .gait
            .iter()
            .all(|(t, v)| t_ok(t) && (0.0..=A).contains(&v))
        {
            return Err("gait queue");
        }
        let floor_ok = |q: &crate::signal::Ring<(f64, f64), STILL_CAP>, max: f64| {
            q.iter().all(|(t, v)| t_ok(t) && (0.0..=max).contains(&v))
        };
        if !(floor_ok(&self.still.acc, 4.0 * A * A)
            && floor_ok(&self.still.gyro, 4.0 * w_max * w_max))
        {
            return Err("stillness floor");
        }
        let a = &self.align;
        let n = a.n as f64;
        if !(t_ok(a.t_first) && t_ok(a.t_last))
            || a.sum_f.iter().any(|v| v.abs() > n * A)
            || a.sum_w.iter().any(|v| v.abs() > n * w_max)
        {
            return Err("alignment sums");
        }
        if !(0.0..=100_000.0).contains(&self.rate_hz) {
            return Err("sample rate");
        }
        if let Some(ins) = &self.ins {
            let m = |v: &Vector3<f64>, max: f64| v.iter().all(|x| x.abs() <= max);
            // Variances and positions as large as the guard's speed over the longest
            // session allows; gravity as the alignment clamps it.
            let diag_ok = (0..15).all(|i| (0.0..=1e20).contains(&ins.cov[(i, i)]));
            let checks = [
                (m(&ins.v, MAX_SPEED_MPS), "navigation state: velocity"),
                (
                    m(&ins.p, MAX_SPEED_MPS * MAX_ABS_T_S),
                    "navigation state: position",
                ),
                // The guard holds biases of a running filter below its limits, but
                // the alignment may start the gyroscope bias anywhere the door allows.
                (m(&ins.ba, A), "navigation state: accelerometer bias"),
                (m(&ins.bg, w_max), "navigation state: gyroscope bias"),
                (
                    m(&ins.prev_f, A) && m(&ins.prev_w, w_max),
                    "navigation state: last sample",
                ),
                (
                    (0.5 * G_MPS2..=1.5 * G_MPS2).contains(&ins.g),
                    "navigation state: gravity",
                ),
                (diag_ok, "navigation state: covariance"),
            ];
            if let Some((_, what)) = checks.iter().find(|(ok, _)| !ok) {
                return Err(what);
            }
        }
        if !(t_ok(self.swing_start_t) && self.distance_m >= 0.0)
            || self.last_onset.is_some_and(|(t, p)| {
                !(t_ok(t) && p.iter().all(|v| v.abs() <= MAX_SPEED_MPS * MAX_ABS_T_S))
            })
        {
            return Err("stride state");
        }
        // A heading in [−π, π]; a turn rate the gyroscope could report.
        let h = &self.hole;
        if h.onset
            .is_some_and(|(t, yaw)| !(t_ok(t) && yaw.abs() <= std::f64::consts::PI))
            || h.turn_rads.abs() > w_max
        {
            return Err("hole state");
        }
        // A still window's variance and rates, and an unexplained rate, the gyroscope
        // could report.
        let z = &self.zaru;
        let rates_ok = |w: &[f64; 3]| w.iter().all(|v| v.is_finite() && v.abs() <= w_max);
        if z.window.is_some_and(|s| {
            !((0.0..=4.0 * w_max * w_max).contains(&s.var_rads2)
                && rates_ok(&s.mean_rads)
                && s.n >= 1)
        }) || z.unexplained.is_some_and(|w| !rates_ok(&w))
            || z.explained_t_s.is_some_and(|t| !t_ok(t))
            || [z.run, z.longest].iter().any(|r| {
                let n = r.n.max(1) as f64;
                !(rates_ok(&r.mean_rads())
                    && t_ok(r.t0_s)
                    && t_ok(r.t1_s)
                    && (0.0..=3.0 * w_max * w_max * n).contains(&r.sum_sq_rads2))
            })
        {
            return Err("zero-angular-rate state");
        }
        Ok(())
    }

    /// A navigator continuing exactly where the snapshot was taken.
    pub fn restore(bytes: &[u8]) -> Result<Self, FootError> {
        let (mut r, _) = Reader::new(bytes, SNAPSHOT_KIND, SNAPSHOT_VERSION)?;
        let config = read_config(&mut r)?;
        let mut n = FootNavigator::new(config).map_err(|e| match e {
            FootError::Snapshot(s) => FootError::Snapshot(s),
            _ => FootError::Snapshot(SnapshotError::Invalid("configuration")),
        })?;
        let invalid = |what| FootError::Snapshot(SnapshotError::Invalid(what));
        n.time = TimeGuard::read(&mut r, Stream::Imu)?;
        n.units = AccelUnits::read(&mut r)?;
        let len = r.len(n.config.median_window)?;
        for _ in 0..len {
            n.median.restore_push(read_body(&mut r)?);
        }
        for c in n.clip.iter_mut() {
            *c = read_clip(&mut r)?;
        }
        n.unresolved.seen = r.u8()?;
        r.f64s(&mut n.unresolved.prev_w)?;
        r.f64s(&mut n.unresolved.prev_dw)?;
        for side in n.accel_ceiling.sides.iter_mut().flatten() {
            side.peak = r.f64()?;
            side.hits = u32::try_from(r.u64()?).map_err(|_| invalid("accelerometer ceiling"))?;
            side.at_level = r.bool()?;
        }
        for run in n.accel_runs.iter_mut() {
            *run = read_clip_run(&mut r)?;
        }
        let len = r.len(MAX_DETECTOR_WINDOW)?;
        for _ in 0..len {
            n.det.push(read_body(&mut r)?);
        }
        let len = r.len(GAIT_CAP)?;
        for _ in 0..len {
            let t = r.f64()?;
            let v = r.f64()?;
            if !(t.is_finite() && v.is_finite()) {
                return Err(invalid("gait queue"));
            }
            n.gait.push((t, v));
        }
        for q in [&mut n.still.acc, &mut n.still.gyro] {
            let len = r.len(STILL_CAP)?;
            for _ in 0..len {
                let t = r.f64()?;
                let v = r.f64()?;
                if !(t.is_finite() && v.is_finite() && v >= 0.0) {
                    return Err(invalid("stillness floor"));
                }
                q.push((t, v));
            }
        }
        n.align.n = r.u64()?;
        n.align.t_first = r.f64()?;
        n.align.t_last = r.f64()?;
        r.f64s(&mut n.align.sum_f)?;
        r.f64s(&mut n.align.sum_w)?;
        n.window = r.len(MAX_DETECTOR_WINDOW)?;
        n.rate_hz = r.f64()?;
        if r.bool()? {
            n.ins = Some(read_strapdown(&mut r)?);
        }
        // −∞ before the first sample.
        n.ins_t = r.f64_any()?;
        if n.ins_t.is_nan() || n.ins_t == f64::INFINITY {
            return Err(invalid("integration time"));
        }
        n.stance = r.bool()?;
        n.swing_start_t = r.f64()?;
        let has_onset = r.bool()?;
        let t0 = r.f64()?;
        let mut p0 = [0.0; 3];
        r.f64s(&mut p0)?;
        n.last_onset = has_onset.then_some((t0, p0));
        let has_onset = r.bool()?;
        let mut h = [0.0; 3];
        r.f64s(&mut h)?;
        if !h.iter().all(|v| v.is_finite()) {
            return Err(invalid("hole state"));
        }
        n.hole = Hole {
            onset: has_onset.then_some((h[0], h[1])),
            turn_rads: h[2],
            pending: r.bool()?,
        };
        n.relevels = r.u64()?;
        let has_window = r.bool()?;
        let mut still = StillWindow {
            var_rads2: r.f64()?,
            ..Default::default()
        };
        r.f64s(&mut still.mean_rads)?;
        still.n = r.len(MAX_DETECTOR_WINDOW)?;
        let has_unexplained = r.bool()?;
        let mut unexplained = [0.0; 3];
        r.f64s(&mut unexplained)?;
        n.zaru = Zaru {
            window: has_window.then_some(still),
            unexplained: has_unexplained.then_some(unexplained),
            stance_n: r.u64()?,
            run: read_run(&mut r)?,
            longest: read_run(&mut r)?,
            explained_t_s: {
                let has = r.bool()?;
                let t = r.f64()?;
                has.then_some(t)
            },
        };
        n.bias_jumps = r.u64()?;
        n.strides = r.u64()?;
        n.distance_m = r.f64()?;
        n.resets = r.u64()?;
        let has_latest = r.bool()?;
        let latest = read_estimate(&mut r)?;
        n.latest = has_latest.then_some(latest);
        r.end()?;
        let finite = n.align.t_first.is_finite()
            && n.align.t_last.is_finite()
            && n.align.sum_f.iter().all(|v| v.is_finite())
            && n.align.sum_w.iter().all(|v| v.is_finite())
            && n.rate_hz.is_finite()
            && n.rate_hz >= 0.0
            && !n.ins_t.is_nan()
            && n.swing_start_t.is_finite()
            && t0.is_finite()
            && p0.iter().all(|v| v.is_finite())
            && n.distance_m.is_finite();
        if !finite {
            return Err(invalid("non-finite state"));
        }
        if n.ins.is_some() != (n.window > 0) || (n.window > 0 && n.window % 2 == 0) {
            return Err(invalid("detector window"));
        }
        n.check_state().map_err(invalid)?;
        if n.latest.as_ref().is_some_and(|e| !estimate_ok(e)) {
            return Err(invalid("stored estimate"));
        }
        if let Some(ins) = &n.ins {
            crate::snapshot::check_covariance(&ins.cov).map_err(invalid)?;
        }
        Ok(n)
    }
}

/// The strapdown and error-state filter, checked: finite, a unit quaternion, positive
/// gravity, non-negative variances.
fn read_strapdown(r: &mut Reader) -> Result<Strapdown, FootError> {
    let mut q = [0.0; 4];
    r.f64s(&mut q)?;
    let q = UnitQuaternion::new_unchecked(Quaternion::new(q[3], q[0], q[1], q[2]));
    let v = read_v3(r)?;
    let p = read_v3(r)?;
    let ba = read_v3(r)?;
    let bg = read_v3(r)?;
    let mut cov = [0.0; 225];
    r.f64s(&mut cov)?;
    let g = r.f64()?;
    let prev_f = read_v3(r)?;
    let prev_w = read_v3(r)?;
    let ins = Strapdown {
        q,
        v,
        p,
        ba,
        bg,
        cov: Cov::from_column_slice(&cov),
        g,
        prev_f,
        prev_w,
    };
    let qn = ins.q.coords.norm_squared();
    if !ins.is_finite()
        || (qn - 1.0).abs() > 1e-6
        || !(g.is_finite() && g > 0.0)
        || (0..15).any(|i| ins.cov[(i, i)] < 0.0)
    {
        return Err(SnapshotError::Invalid("navigation state").into());
    }
    Ok(ins)
}

/// A stored estimate: a unit quaternion, non-negative uncertainties and distance.
fn estimate_ok(e: &FootEstimate) -> bool {
    let qn: f64 = e.quaternion.iter().map(|c| c * c).sum();
    let stds = e
        .position_std_m
        .iter()
        .chain(&e.velocity_std_mps)
        .chain(&e.tilt_std_rad)
        .chain(std::iter::once(&e.heading_std_rad));
    !((qn - 1.0).abs() > 1e-6 || stds.copied().any(|v| v < 0.0) || e.distance_m < 0.0)
}

/// A still run of the bias-jump check (`Zaru`).
fn read_run(r: &mut Reader) -> Result<StillRun, SnapshotError> {
    let n = r.u64()?;
    let mut t = [0.0; 2];
    r.f64s(&mut t)?;
    let mut sum_rads = [0.0; 3];
    r.f64s(&mut sum_rads)?;
    Ok(StillRun {
        n,
        t0_s: t[0],
        t1_s: t[1],
        sum_rads,
        sum_sq_rads2: r.f64()?,
    })
}
