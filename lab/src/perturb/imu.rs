//! An IMU recording as the perturbations see it, and [`perturb`]: one perturbation
//! applied to a copy. Every output sample remembers where it came from in the
//! recording (`src`, a fractional sample index), so the truth of the original
//! sample scores it, and how far the perturbation rocked the body (`wobble`), so an
//! orientation truth turns with it.

use stridekit_sim::Rng;

use super::kinds::{Perturbation, G0_MPS2};

/// Lever arm of the rocking that comes with a vibration, m: a device shaken with
/// linear acceleration A at frequency f rocks with angular acceleration A / r about an
/// axis r away (a hand or a mount 10 cm from the sensor), i.e. a rate ripple of
/// A / (r·2πf) (0.8 rad/s at 10 Hz and 5 m/s², 0.04 rad/s at 200 Hz).
pub const VIBRATION_LEVER_M: f64 = 0.1;
/// Broadband vibration: sinusoids summed, frequencies uniform in the band.
pub const BROADBAND_COMPONENTS: usize = 16;
pub const BROADBAND_HZ: (f64, f64) = (10.0, 200.0);
/// The gyroscope bias step happens this far into the recording.
pub const BIAS_STEP_AT: f64 = 1.0 / 3.0;
/// A passed magnet: one pass per this much of the recording (at least one), s.
pub const MAG_PASS_EVERY_S: f64 = 120.0;
/// A pass lasts this long, s (uniform), ramps included.
pub const MAG_PASS_S: (f64, f64) = (5.0, 60.0);
/// The passed magnet's field rises and falls as a raised cosine over this long, s
/// (a walker approaching and leaving a magnet, a door, a machine).
pub const MAG_PASS_RAMP_S: f64 = 3.0;

/// A recording's IMU streams (sensor axes, SI units).
#[derive(Clone, Debug, Default)]
pub struct Imu {
    pub t_s: Vec<f64>,
    pub gyro: Vec<[f64; 3]>,
    pub accel: Vec<[f64; 3]>,
    /// Per sample, when the recording has a magnetometer.
    pub mag: Vec<Option<[f64; 3]>>,
    /// Place of each sample in the recording (fractional index).
    pub src: Vec<f64>,
    /// Rotation of the body against the recording (rotation vector, rad), when a
    /// perturbation rocked it.
    pub wobble: Option<Vec<[f64; 3]>>,
    /// Specific force of gravity in sensor axes per sample, m/s², when known (a time
    /// stretch keeps it and scales the rest).
    pub gravity: Option<Vec<[f64; 3]>>,
    /// Orientation sensor → earth (`[w, x, y, z]`) per sample, when known (a field fixed
    /// in the earth frame is seen through it).
    pub attitude: Option<Vec<[f64; 4]>>,
}

impl Imu {
    /// A recording as recorded (`mag` empty or one per sample).
    pub fn new(
        t_s: Vec<f64>,
        gyro: Vec<[f64; 3]>,
        accel: Vec<[f64; 3]>,
        mag: Vec<Option<[f64; 3]>>,
    ) -> Self {
        let n = t_s.len();
        let mag = if mag.len() == n { mag } else { vec![None; n] };
        Self {
            src: (0..n).map(|i| i as f64).collect(),
            t_s,
            gyro,
            accel,
            mag,
            wobble: None,
            gravity: None,
            attitude: None,
        }
    }

    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// Duration, s.
    fn span_s(&self) -> f64 {
        match (self.t_s.first(), self.t_s.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }

    /// Mean sample spacing, s.
    pub fn spacing_s(&self) -> f64 {
        self.span_s() / (self.len().max(2) - 1) as f64
    }

    /// The original sample index a perturbed sample stands for.
    pub fn source_index(&self, k: usize) -> usize {
        self.src[k].round().max(0.0) as usize
    }

    /// Keep the samples `keep` says yes to.
    fn retain(&self, keep: impl Fn(usize) -> bool) -> Imu {
        let idx: Vec<usize> = (0..self.len()).filter(|&i| keep(i)).collect();
        let pick = |v: &[[f64; 3]]| idx.iter().map(|&i| v[i]).collect::<Vec<_>>();
        Imu {
            t_s: idx.iter().map(|&i| self.t_s[i]).collect(),
            gyro: pick(&self.gyro),
            accel: pick(&self.accel),
            mag: idx.iter().map(|&i| self.mag[i]).collect(),
            src: idx.iter().map(|&i| self.src[i]).collect(),
            wobble: self.wobble.as_ref().map(|w| pick(w)),
            gravity: self.gravity.as_ref().map(|g| pick(g)),
            attitude: self
                .attitude
                .as_ref()
                .map(|a| idx.iter().map(|&i| a[i]).collect()),
        }
    }

    /// Linear interpolation onto the times `grid` (within the recording).
    fn resample(&self, grid: &[f64]) -> Imu {
        let mut out = Imu {
            wobble: self.wobble.as_ref().map(|_| Vec::new()),
            gravity: self.gravity.as_ref().map(|_| Vec::new()),
            attitude: self.attitude.as_ref().map(|_| Vec::new()),
            ..Imu::default()
        };
        let mut j = 0;
        for &t in grid {
            while j + 2 < self.len() && self.t_s[j + 1] < t {
                j += 1;
            }
            let k = (j + 1).min(self.len() - 1);
            let (ta, tb) = (self.t_s[j], self.t_s[k]);
            let f = if tb > ta {
                ((t - ta) / (tb - ta)).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let lerp3 = |v: &[[f64; 3]]| -> [f64; 3] {
                std::array::from_fn(|i| v[j][i] + f * (v[k][i] - v[j][i]))
            };
            out.t_s.push(t);
            out.gyro.push(lerp3(&self.gyro));
            out.accel.push(lerp3(&self.accel));
            out.mag.push(match (self.mag[j], self.mag[k]) {
                (Some(a), Some(b)) => Some(std::array::from_fn(|i| a[i] + f * (b[i] - a[i]))),
                (a, b) => {
                    if f < 0.5 {
                        a.or(b)
                    } else {
                        b.or(a)
                    }
                }
            });
            out.src.push(self.src[j] + f * (self.src[k] - self.src[j]));
            if let (Some(o), Some(w)) = (out.wobble.as_mut(), self.wobble.as_ref()) {
                o.push(lerp3(w));
            }
            if let (Some(o), Some(g)) = (out.gravity.as_mut(), self.gravity.as_ref()) {
                o.push(lerp3(g));
            }
            if let (Some(o), Some(a)) = (out.attitude.as_mut(), self.attitude.as_ref()) {
                o.push(if f < 0.5 { a[j] } else { a[k] });
            }
        }
        out
    }
}

/// A random unit vector.
pub fn unit(rng: &mut Rng) -> [f64; 3] {
    loop {
        let v = [rng.normal(), rng.normal(), rng.normal()];
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if n > 1e-6 {
            return v.map(|c| c / n);
        }
    }
}

fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// A unit vector perpendicular to `u`.
fn perpendicular(u: &[f64; 3], rng: &mut Rng) -> [f64; 3] {
    let c = cross(u, &unit(rng));
    let n = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt().max(1e-12);
    c.map(|x| x / n)
}

/// One sinusoid of a vibration: linear part along `u`, rocking about `v`.
struct Shake {
    hz: f64,
    amplitude_mps2: f64,
    u: [f64; 3],
    v: [f64; 3],
    phase: f64,
    rock_phase: f64,
}

fn shakes(hz: Option<f64>, mps2: f64, rng: &mut Rng) -> Vec<Shake> {
    let one = |hz: f64, a: f64, rng: &mut Rng| {
        let u = unit(rng);
        Shake {
            hz,
            amplitude_mps2: a,
            v: perpendicular(&u, rng),
            u,
            phase: rng.range(0.0, std::f64::consts::TAU),
            rock_phase: rng.range(0.0, std::f64::consts::TAU),
        }
    };
    match hz {
        Some(f) => vec![one(f, mps2, rng)],
        None => {
            // K sinusoids of amplitude a have a mean square K·a²/2: RMS `mps2`.
            let a = mps2 * (2.0 / BROADBAND_COMPONENTS as f64).sqrt();
            (0..BROADBAND_COMPONENTS)
                .map(|_| {
                    let f = rng.range(BROADBAND_HZ.0, BROADBAND_HZ.1);
                    one(f, a, rng)
                })
                .collect()
        }
    }
}

/// Shake the recording: accelerometer + linear vibration, every reading turned by the
/// rocking angle θ (v − θ × v), gyroscope + θ̇.
fn vibrate(imu: &Imu, hz: Option<f64>, mps2: f64, rng: &mut Rng) -> Imu {
    let sh = shakes(hz, mps2, rng);
    let mut out = imu.clone();
    let mut wobble = imu
        .wobble
        .clone()
        .unwrap_or_else(|| vec![[0.0; 3]; imu.len()]);
    let t0 = imu.t_s.first().copied().unwrap_or(0.0);
    for i in 0..imu.len() {
        let t = imu.t_s[i] - t0;
        let (mut lin, mut th, mut th_dot) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        for s in &sh {
            let w = std::f64::consts::TAU * s.hz;
            let a = s.amplitude_mps2 * (w * t + s.phase).sin();
            let rock = s.amplitude_mps2 / (VIBRATION_LEVER_M * w * w);
            let (sn, cs) = (w * t + s.rock_phase).sin_cos();
            for c in 0..3 {
                lin[c] += a * s.u[c];
                th[c] += rock * sn * s.v[c];
                th_dot[c] += rock * w * cs * s.v[c];
            }
        }
        let turn = |v: [f64; 3]| {
            let c = cross(&th, &v);
            [v[0] - c[0], v[1] - c[1], v[2] - c[2]]
        };
        let a = turn(imu.accel[i]);
        out.accel[i] = [a[0] + lin[0], a[1] + lin[1], a[2] + lin[2]];
        let g = turn(imu.gyro[i]);
        out.gyro[i] = [g[0] + th_dot[0], g[1] + th_dot[1], g[2] + th_dot[2]];
        out.mag[i] = imu.mag[i].map(turn);
        if let Some(gr) = out.gravity.as_mut() {
            gr[i] = turn(gr[i]);
        }
        for c in 0..3 {
            wobble[i][c] += th[c];
        }
    }
    out.wobble = Some(wobble);
    out
}

/// `share` of the span dropped in bursts of `min_s`–`max_s`, placed uniformly.
pub fn bursts(
    t0: f64,
    span: f64,
    share: f64,
    min_s: f64,
    max_s: f64,
    rng: &mut Rng,
) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut covered = 0.0;
    while covered < share * span {
        let start = t0 + rng.uniform() * span;
        let len = rng.range(min_s, max_s);
        out.push((start, start + len));
        covered += len;
    }
    out
}

/// Order-keeping jitter of timestamps: t + σ·N(0, 1).
pub fn jittered(t: &[f64], sigma_s: f64, rng: &mut Rng) -> Vec<f64> {
    t.iter().map(|&t| t + sigma_s * rng.normal()).collect()
}

/// The passes of a magnet over a recording from `t0` spanning `span` s: (start, end)
/// of each, s, placed uniformly.
fn mag_passes(t0: f64, span: f64, rng: &mut Rng) -> Vec<(f64, f64)> {
    let n = ((span / MAG_PASS_EVERY_S).floor() as usize).max(1);
    (0..n)
        .map(|_| {
            let len = rng.range(MAG_PASS_S.0, MAG_PASS_S.1).min(span);
            let start = t0 + rng.uniform() * (span - len);
            (start, start + len)
        })
        .collect()
}

/// How much of a pass's field is on at `t`: 0 outside, raised-cosine ramps of
/// [`MAG_PASS_RAMP_S`] at both ends, 1 between.
fn pass_share(t: f64, (a, b): (f64, f64)) -> f64 {
    let ramp = MAG_PASS_RAMP_S.min(0.5 * (b - a)).max(1e-9);
    let edge = (t - a).min(b - t);
    if edge <= 0.0 {
        0.0
    } else if edge >= ramp {
        1.0
    } else {
        0.5 - 0.5 * (std::f64::consts::PI * edge / ramp).cos()
    }
}

/// v seen in the sensor frame of the orientation `q` (sensor → earth): q⁻¹ v q.
fn to_sensor(q: &[f64; 4], v: &[f64; 3]) -> [f64; 3] {
    let u = [q[1], q[2], q[3]];
    // v' = v − 2w (u × v) + 2 u × (u × v) for the conjugate rotation.
    let t = cross(&u, v).map(|c| 2.0 * c);
    let ut = cross(&u, &t);
    std::array::from_fn(|c| v[c] - q[0] * t[c] + ut[c])
}

/// The recording with `p` applied (seeded by `rng`). `Speed` needs
/// [`Imu::gravity`] and `MagPass` [`Imu::attitude`]; without it the copy is returned
/// unchanged and `None` says so.
pub fn perturb(imu: &Imu, p: &Perturbation, rng: &mut Rng) -> Option<Imu> {
    if imu.len() < 2 {
        return Some(imu.clone());
    }
    let t0 = imu.t_s[0];
    let span = imu.span_s();
    let mut out = imu.clone();
    match *p {
        Perturbation::Vibration { hz, mps2 } => return Some(vibrate(imu, hz, mps2, rng)),
        Perturbation::MagOffset { ut } => {
            let u = unit(rng);
            for m in out.mag.iter_mut().flatten() {
                for c in 0..3 {
                    m[c] += ut * u[c];
                }
            }
        }
        Perturbation::MagDrift { ut } => {
            let u = unit(rng);
            for (m, t) in out.mag.iter_mut().zip(&imu.t_s) {
                if let Some(m) = m {
                    let s = ut * (t - t0) / span;
                    for c in 0..3 {
                        m[c] += s * u[c];
                    }
                }
            }
        }
        Perturbation::MagPass { ut } => {
            let attitude = imu.attitude.as_ref()?;
            let passes = mag_passes(t0, span, rng);
            let dirs: Vec<[f64; 3]> = passes.iter().map(|_| unit(rng)).collect();
            for (i, m) in out.mag.iter_mut().enumerate() {
                let Some(m) = m else { continue };
                let mut w = [0.0; 3];
                for (pass, u) in passes.iter().zip(&dirs) {
                    let s = ut * pass_share(imu.t_s[i], *pass);
                    for c in 0..3 {
                        w[c] += s * u[c];
                    }
                }
                let d = to_sensor(&attitude[i], &w);
                for c in 0..3 {
                    m[c] += d[c];
                }
            }
        }
        Perturbation::GyroBiasStep { dps } => {
            let b = unit(rng).map(|c| c * dps.to_radians());
            let at = t0 + BIAS_STEP_AT * span;
            for (g, t) in out.gyro.iter_mut().zip(&imu.t_s) {
                if *t >= at {
                    for c in 0..3 {
                        g[c] += b[c];
                    }
                }
            }
        }
        Perturbation::GyroScale { pct } => {
            let s: [f64; 3] = std::array::from_fn(|_| {
                let sign = if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
                1.0 + sign * pct / 100.0
            });
            for g in out.gyro.iter_mut() {
                for c in 0..3 {
                    g[c] *= s[c];
                }
            }
        }
        Perturbation::Rate { hz } => {
            let n = (span * hz).floor() as usize + 1;
            let grid: Vec<f64> = (0..n).map(|k| t0 + k as f64 / hz).collect();
            return Some(imu.resample(&grid));
        }
        Perturbation::Jitter { share } => {
            out.t_s = jittered(&imu.t_s, share * imu.spacing_s(), rng);
        }
        Perturbation::Bursts {
            share,
            min_s,
            max_s,
        } => {
            let b = bursts(t0, span, share, min_s, max_s, rng);
            return Some(imu.retain(|i| {
                let t = imu.t_s[i];
                !b.iter().any(|&(x, y)| t >= x && t < y)
            }));
        }
        Perturbation::ClipAccel { g } => {
            let lim = g * G0_MPS2;
            for a in out.accel.iter_mut() {
                *a = a.map(|x| x.clamp(-lim, lim));
            }
        }
        Perturbation::ClipGyro { dps } => {
            let lim = dps.to_radians();
            for w in out.gyro.iter_mut() {
                *w = w.map(|x| x.clamp(-lim, lim));
            }
        }
        Perturbation::Speed { factor } => {
            let gravity = imu.gravity.as_ref()?;
            let k = factor;
            for (i, g) in gravity.iter().enumerate() {
                out.t_s[i] = t0 + (imu.t_s[i] - t0) / k;
                out.gyro[i] = imu.gyro[i].map(|w| w * k);
                let a = imu.accel[i];
                out.accel[i] = std::array::from_fn(|c| k * k * (a[c] - g[c]) + g[c]);
            }
            let dt = imu.spacing_s();
            let n = (span / k / dt).floor() as usize + 1;
            let grid: Vec<f64> = (0..n).map(|j| t0 + j as f64 * dt).collect();
            return Some(out.resample(&grid));
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn still(n: usize, hz: f64) -> Imu {
        let t: Vec<f64> = (0..n).map(|i| i as f64 / hz).collect();
        let mut imu = Imu::new(
            t,
            vec![[0.0; 3]; n],
            vec![[0.0, 0.0, 9.81]; n],
            vec![Some([20.0, 0.0, -40.0]); n],
        );
        imu.gravity = Some(vec![[0.0, 0.0, 9.81]; n]);
        imu
    }

    #[test]
    fn vibration_has_the_asked_amplitude_and_a_consistent_rocking() {
        let imu = still(20_000, 1000.0);
        let mut rng = Rng::new(1);
        let v = perturb(
            &imu,
            &Perturbation::Vibration {
                hz: Some(50.0),
                mps2: 2.0,
            },
            &mut rng,
        )
        .unwrap();
        let peak = v
            .accel
            .iter()
            .map(|a| ((a[0]).powi(2) + a[1].powi(2) + (a[2] - 9.81).powi(2)).sqrt())
            .fold(0.0, f64::max);
        assert!((peak - 2.0).abs() < 0.05, "{peak}");
        // The integrated gyroscope ripple is the wobble angle.
        let w = v.wobble.as_ref().unwrap();
        let mut th = w[0];
        let mut worst: f64 = 0.0;
        for (g, wi) in v.gyro.windows(2).zip(&w[1..]) {
            for c in 0..3 {
                th[c] += 0.5 * (g[0][c] + g[1][c]) * 1e-3;
                worst = worst.max((th[c] - wi[c]).abs());
            }
        }
        let amp = 2.0 / (VIBRATION_LEVER_M * (std::f64::consts::TAU * 50.0).powi(2));
        assert!(worst < 0.02 * amp, "{worst} vs amplitude {amp}");
        let mut rng = Rng::new(1);
        let b = perturb(
            &imu,
            &Perturbation::Vibration {
                hz: None,
                mps2: 2.0,
            },
            &mut rng,
        )
        .unwrap();
        let ms = b
            .accel
            .iter()
            .map(|a| a[0].powi(2) + a[1].powi(2) + (a[2] - 9.81).powi(2))
            .sum::<f64>()
            / b.len() as f64;
        assert!((ms.sqrt() - 2.0).abs() < 0.3, "broadband RMS {}", ms.sqrt());
    }

    #[test]
    fn grids_bursts_and_stretches_keep_their_sources() {
        let imu = still(2_000, 200.0);
        let mut rng = Rng::new(2);
        let r = perturb(&imu, &Perturbation::Rate { hz: 50.0 }, &mut rng).unwrap();
        assert_eq!(r.len(), 500);
        assert!((r.src[10] - 40.0).abs() < 1e-9);
        let b = perturb(
            &imu,
            &Perturbation::Bursts {
                share: 0.1,
                min_s: 0.05,
                max_s: 1.0,
            },
            &mut rng,
        )
        .unwrap();
        assert!(b.len() < 1_850 && b.len() > 1_500, "{}", b.len());
        let s = perturb(&imu, &Perturbation::Speed { factor: 2.0 }, &mut rng).unwrap();
        assert_eq!(s.len(), 1_000);
        assert!((s.src[100] - 200.0).abs() < 1e-6);
        assert!((s.accel[5][2] - 9.81).abs() < 1e-9, "gravity kept");
        let mut no_g = imu.clone();
        no_g.gravity = None;
        assert!(perturb(&no_g, &Perturbation::Speed { factor: 2.0 }, &mut rng).is_none());
    }

    #[test]
    fn a_passed_magnet_is_fixed_in_the_earth_frame_and_ramps_on_and_off() {
        // Turning about the vertical at 10°/s: the earth-fixed field turns the other
        // way in the sensor frame, its size kept.
        let n = 20_000;
        let hz = 100.0;
        let mut imu = still(n, hz);
        let yaw = |i: usize| (10.0f64 * i as f64 / hz).to_radians();
        imu.attitude = Some(
            (0..n)
                .map(|i| [(0.5 * yaw(i)).cos(), 0.0, 0.0, (0.5 * yaw(i)).sin()])
                .collect(),
        );
        let mut rng = Rng::new(3);
        let p = perturb(&imu, &Perturbation::MagPass { ut: 10.0 }, &mut rng).unwrap();
        let extra: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let (a, b) = (imu.mag[i].unwrap(), p.mag[i].unwrap());
                std::array::from_fn(|c| b[c] - a[c])
            })
            .collect();
        let size = |v: &[f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let on: Vec<usize> = (0..n).filter(|&i| size(&extra[i]) > 1e-9).collect();
        let (first, last) = (on[0], *on.last().unwrap());
        let len_s = (last - first) as f64 / hz;
        assert!((5.0..=60.0).contains(&len_s), "{len_s}");
        assert!((size(&extra[(first + last) / 2]) - 10.0).abs() < 1e-9);
        // Half on in the middle of the ramp.
        let mid_ramp = first + (MAG_PASS_RAMP_S * hz / 2.0) as usize;
        assert!((size(&extra[mid_ramp]) - 5.0).abs() < 0.1);
        // Back in the earth frame (q v q⁻¹) the field's direction stands still.
        let earth = |i: usize| {
            let (s, c) = yaw(i).sin_cos();
            let v = extra[i].map(|x| x / size(&extra[i]));
            [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]
        };
        let a = earth(first + 10);
        let b = earth(last - 10);
        for c in 0..3 {
            assert!((a[c] - b[c]).abs() < 1e-9, "{a:?} {b:?}");
        }
        // Without an attitude there is no such copy.
        assert!(perturb(
            &still(100, hz),
            &Perturbation::MagPass { ut: 10.0 },
            &mut rng
        )
        .is_none());
    }
}
