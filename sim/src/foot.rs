//! Simulated foot-mounted IMU: a pedestrian walks (or runs) laps of a closed
//! rectangle with the IMU on the shoe.
//!
//! Deterministic: everything comes from [`FootScenario::seed`] through the in-tree
//! [`Rng`], one independent stream per sub-model.
//!
//! Model (see [`simulate_foot`]):
//! - **path**: footprints along a rectangle (`loop_m` East × North, counter-clockwise:
//!   East, North, West, South, back to the start), evenly spaced on each side at the
//!   stride length closest to [`FootGait::stride_length_m`]; the foot turns half of
//!   each 90° corner on the stride before the corner footprint and half on the one
//!   after; the walk starts and ends with a rest (`rest_start_s`, `rest_end_s`) at
//!   the origin, foot flat, pointing East; with `rise_per_stride_m` each footprint is
//!   that much above the one before (stairs or a ramp, on the same minimum-jerk
//!   profile as the horizontal displacement);
//! - **stride** (footprint k → k + 1): motion of duration `(1 − stance_fraction)·T`
//!   then stance of `stance_fraction·T`, `T` the stride duration (varies
//!   `stride_jitter` per stride). During the motion, with `τ ∈ [0, 1]`: horizontal
//!   displacement along the minimum-jerk profile `10τ³ − 15τ⁴ + 6τ⁵`, vertical lift
//!   `lift·64τ³(1 − τ)³`, yaw interpolated on the same profile, pitch
//!   `A·sin(2πτ)·sin(πτ)` (toes down at push-off, toes up before heel strike; the
//!   pitch rate ramps up linearly from the stance edges; peak
//!   `pitch_peak_rad`), a small roll `roll_peak·64τ³(1 − τ)³`. Every profile starts
//!   and ends with zero velocity (the translation also with zero acceleration), so
//!   the foot is exactly still and flat during stance except for the tremor;
//! - **tremor** (always on, scaled by `tremor`): two sinusoids per attitude axis
//!   (≈ 0.01° at 4–9 Hz, ≈ 0.4°/s) and per position axis (≈ 15 µm at 5–11 Hz), random phases;
//! - **sensors**: specific force `f = Rᵀ(a + g·up)` and the body angular rate from the
//!   analytic Euler-angle rates (ZYX: `ω = [φ̇ − ψ̇ sθ, θ̇ cφ + ψ̇ cθ sφ, −θ̇ sφ + ψ̇ cθ cφ]`),
//!   both exact derivatives of the trajectory, then a constant mounting rotation
//!   (`mount_rpy_rad`), constant biases (drawn with `*_bias_std_*`) and white noise;
//!   optionally reported in the pyshoe axes (x forward, y right, z down);
//! - **timing**: nominal rate, Gaussian timestamp jitter (the sample is taken at the
//!   jittered time), random dropped samples.
//!
//! Frames: body x forward along the foot, y left, z up; world ENU with the origin at
//! the first footprint; attitude body → ENU.

use nalgebra::{Rotation3, UnitQuaternion, Vector3};

use super::rng::Rng;
use stridekit_core::foot::FootSample;

/// Standard gravity, m/s² (the simulator's local gravity).
pub const GRAVITY_MPS2: f64 = 9.80665;

/// Shape of the gait.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FootGait {
    /// Stride length (footprint to footprint of the same foot), m.
    pub stride_length_m: f64,
    /// Stride duration, s.
    pub stride_duration_s: f64,
    /// Fraction of the stride the foot is flat and still, 0.1..=0.8.
    pub stance_fraction: f64,
    /// Peak height of the foot during the swing, m.
    pub lift_m: f64,
    /// Peak pitch of the foot (toes down at push-off, up before heel strike), rad.
    pub pitch_peak_rad: f64,
    /// Peak roll during the swing, rad.
    pub roll_peak_rad: f64,
}

impl FootGait {
    /// Normal walking: 1.4 m strides of 1.1 s (1.27 m/s), foot flat 40 % of the time.
    pub const WALK: Self = Self {
        stride_length_m: 1.4,
        stride_duration_s: 1.1,
        stance_fraction: 0.4,
        lift_m: 0.12,
        pitch_peak_rad: 0.6,
        roll_peak_rad: 0.05,
    };
    /// Running: 2.6 m strides of 0.72 s (3.6 m/s), foot flat 20 % of the time.
    pub const RUN: Self = Self {
        stride_length_m: 2.6,
        stride_duration_s: 0.72,
        stance_fraction: 0.2,
        lift_m: 0.3,
        pitch_peak_rad: 0.9,
        roll_peak_rad: 0.08,
    };
}

/// What to simulate.
#[derive(Clone, Debug, PartialEq)]
pub struct FootScenario {
    pub seed: u64,
    /// IMU rate, Hz (clamped to 20–2000).
    pub sample_rate_hz: f64,
    /// 1-σ timestamp jitter, s (clamped to ±0.3 sample periods so time increases).
    pub timestamp_jitter_s: f64,
    /// Probability that a sample is dropped (not delivered), 0..0.9.
    pub drop_probability: f64,
    /// Rest at the start (alignment) and at the end, s.
    pub rest_start_s: f64,
    pub rest_end_s: f64,
    pub gait: FootGait,
    /// Relative 1-σ variation of each stride's duration.
    pub stride_jitter: f64,
    /// Rectangle sides East × North, m (0 × 0: walk in place is not supported; the
    /// smallest side is one stride).
    pub loop_m: [f64; 2],
    pub laps: u32,
    /// White noise per sample: accelerometer m/s², gyroscope rad/s.
    pub accel_noise_mps2: f64,
    pub gyro_noise_rads: f64,
    /// 1-σ of the constant biases drawn per run.
    pub accel_bias_std_mps2: f64,
    pub gyro_bias_std_rads: f64,
    /// Tremor scale (1: default amplitudes, 0: none).
    pub tremor: f64,
    /// Sensor orientation relative to the foot (roll, pitch, yaw), rad.
    pub mount_rpy_rad: [f64; 3],
    /// Report samples in the pyshoe axes (x forward, y right, z down).
    pub sensor_z_down: bool,
    /// Time of the first sample, s.
    pub start_t_s: f64,
    /// Each footprint this much above the one before, m (stairs, a ramp: a walk up
    /// a spiral; the loop then closes horizontally only). 0: level.
    pub rise_per_stride_m: f64,
}

impl FootScenario {
    /// Laps of a 20 m × 10 m rectangle walking at 200 Hz, 2 s rest at both ends, a
    /// consumer MEMS IMU (noise 0.02 m/s², 0.002 rad/s; biases 0.02 m/s², 0.003 rad/s).
    pub fn walk(seed: u64, laps: u32) -> Self {
        Self {
            seed,
            sample_rate_hz: 200.0,
            timestamp_jitter_s: 0.0,
            drop_probability: 0.0,
            rest_start_s: 2.0,
            rest_end_s: 2.0,
            gait: FootGait::WALK,
            stride_jitter: 0.03,
            loop_m: [20.0, 10.0],
            laps,
            accel_noise_mps2: 0.02,
            gyro_noise_rads: 0.002,
            accel_bias_std_mps2: 0.02,
            gyro_bias_std_rads: 0.003,
            tremor: 1.0,
            mount_rpy_rad: [0.0; 3],
            sensor_z_down: false,
            start_t_s: 0.0,
            rise_per_stride_m: 0.0,
        }
    }

    /// The same loop running.
    pub fn run(seed: u64, laps: u32) -> Self {
        Self {
            gait: FootGait::RUN,
            loop_m: [26.0, 13.0],
            ..Self::walk(seed, laps)
        }
    }
}

/// The true state at one sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FootTruth {
    pub t_s: f64,
    /// Sensor position, ENU, m.
    pub position_m: [f64; 3],
    pub velocity_mps: [f64; 3],
    /// Sensor attitude, body (sensor after `FootConfig::axis_remap`, i.e. x forward,
    /// z up when mounted flat) → ENU, `[w, x, y, z]`.
    pub quaternion: [f64; 4],
    /// The foot is flat on the ground (no motion except tremor).
    pub stance: bool,
}

/// One true stride: footprint to footprint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrueStride {
    /// Time the foot comes to rest on the new footprint (stance onset), s.
    pub t_s: f64,
    /// Horizontal distance between the footprints, m.
    pub length_m: f64,
    /// Time since the previous stance onset (the first: since the end of the
    /// starting rest), s.
    pub duration_s: f64,
}

/// Output of [`simulate_foot`].
#[derive(Clone, Debug, PartialEq)]
pub struct SimulatedFoot {
    pub scenario: FootScenario,
    pub samples: Vec<FootSample>,
    /// One per sample.
    pub truth: Vec<FootTruth>,
    pub strides: Vec<TrueStride>,
    /// Total path length (sum of stride lengths), m.
    pub distance_m: f64,
    /// Biases applied, sensor axes.
    pub accel_bias_mps2: [f64; 3],
    pub gyro_bias_rads: [f64; 3],
}

impl SimulatedFoot {
    /// `n` samples: this walk repeated with shifted timestamps (one sample interval
    /// between repetitions). A walk that starts and ends at rest joins up, so long
    /// inputs for benches need no longer simulation.
    pub fn repeated_samples(&self, n: usize) -> Vec<FootSample> {
        let Some(last) = self.samples.last() else {
            return Vec::new();
        };
        let dt = if self.samples.len() > 1 {
            last.t_s - self.samples[self.samples.len() - 2].t_s
        } else {
            0.005
        };
        let span = last.t_s + dt;
        (0..n)
            .map(|k| {
                let rep = k / self.samples.len();
                let s = self.samples[k % self.samples.len()];
                FootSample {
                    t_s: s.t_s + rep as f64 * span,
                    ..s
                }
            })
            .collect()
    }

    /// Clip every accelerometer axis at `share` × the largest magnitude of the walk, as
    /// an IMU of a narrower range records it. Returns the ceiling, m/s², and how many
    /// axis values were clipped.
    pub fn clip_accel(&mut self, share: f64) -> (f64, usize) {
        let peak = self
            .samples
            .iter()
            .flat_map(|s| s.accel_mps2)
            .fold(0.0_f64, |m, a| m.max(a.abs()));
        let ceiling = share * peak;
        let mut clipped = 0;
        for a in self
            .samples
            .iter_mut()
            .flat_map(|s| s.accel_mps2.iter_mut())
        {
            if a.abs() > ceiling {
                *a = a.signum() * ceiling;
                clipped += 1;
            }
        }
        (ceiling, clipped)
    }
}

fn stream(seed: u64, k: u64) -> Rng {
    Rng::new(seed ^ k.wrapping_mul(0x9E6C_63D0_676A_9A99).rotate_left(23) ^ 0x464F_4F54)
}

/// A footprint: where the foot rests, and which way it points.
#[derive(Clone, Copy, Debug)]
struct Footprint {
    p: [f64; 2],
    /// Height, m.
    z: f64,
    yaw: f64,
}

/// Motion from footprint `from` to `from + 1` during `[t0, t0 + dur]`.
#[derive(Clone, Copy, Debug)]
struct Motion {
    t0: f64,
    dur: f64,
    from: usize,
}

struct Sinus {
    amp: f64,
    w: f64,
    ph: f64,
}

impl Sinus {
    fn eval(&self, t: f64) -> (f64, f64, f64) {
        let x = self.w * t + self.ph;
        let (s, c) = x.sin_cos();
        (
            self.amp * s,
            self.amp * self.w * c,
            -self.amp * self.w * self.w * s,
        )
    }
}

/// Value and first two time derivatives.
#[derive(Clone, Copy, Debug, Default)]
struct Jet {
    v: f64,
    d: f64,
    dd: f64,
}

impl std::ops::AddAssign<(f64, f64, f64)> for Jet {
    fn add_assign(&mut self, o: (f64, f64, f64)) {
        self.v += o.0;
        self.d += o.1;
        self.dd += o.2;
    }
}

struct Walk {
    prints: Vec<Footprint>,
    motions: Vec<Motion>,
    gait: FootGait,
    /// Tremor: attitude (roll, pitch, yaw) and position (x, y, z), two each.
    tremor_att: Vec<[Sinus; 2]>,
    tremor_pos: Vec<[Sinus; 2]>,
}

impl Walk {
    /// Position (x, y, z) and Euler angles (roll, pitch, yaw) of the foot at `t`, and
    /// whether it is in stance.
    #[allow(clippy::needless_range_loop)] // parallel per-axis arrays
    fn state(&self, t: f64) -> ([Jet; 3], [Jet; 3], bool) {
        let mut pos = [Jet::default(); 3];
        let mut att = [Jet::default(); 3];
        // The motion that starts last at or before t.
        let k = self.motions.partition_point(|m| m.t0 <= t);
        let mut stance = true;
        let (print, moving) = if k == 0 {
            (self.prints[0], None)
        } else {
            let m = self.motions[k - 1];
            if t < m.t0 + m.dur {
                (self.prints[m.from], Some(m))
            } else {
                (self.prints[m.from + 1], None)
            }
        };
        pos[0].v = print.p[0];
        pos[1].v = print.p[1];
        pos[2].v = print.z;
        att[2].v = print.yaw;
        if let Some(m) = moving {
            stance = false;
            let b = self.prints[m.from + 1];
            let a = self.prints[m.from];
            let tau = ((t - m.t0) / m.dur).clamp(0.0, 1.0);
            let (tt, t2) = (m.dur, m.dur * m.dur);
            let s = tau * tau * tau * (10.0 + tau * (-15.0 + 6.0 * tau));
            let s1 = 30.0 * tau * tau * (1.0 - tau) * (1.0 - tau);
            let s2 = 60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau);
            for i in 0..2 {
                let dl = b.p[i] - a.p[i];
                pos[i] = Jet {
                    v: a.p[i] + s * dl,
                    d: s1 / tt * dl,
                    dd: s2 / t2 * dl,
                };
            }
            let dyaw = b.yaw - a.yaw;
            att[2] = Jet {
                v: a.yaw + s * dyaw,
                d: s1 / tt * dyaw,
                dd: 0.0,
            };
            // Bump 64 u³ with u = τ(1 − τ).
            let u = tau * (1.0 - tau);
            let u1 = 1.0 - 2.0 * tau;
            let bump = 64.0 * u * u * u;
            let bump1 = 192.0 * u * u * u1;
            let bump2 = 384.0 * u * (u1 * u1 - u);
            let h = self.gait.lift_m;
            let dz = b.z - a.z;
            pos[2] = Jet {
                v: a.z + s * dz + h * bump,
                d: (s1 * dz + h * bump1) / tt,
                dd: (s2 * dz + h * bump2) / t2,
            };
            let r = self.gait.roll_peak_rad;
            att[0] = Jet {
                v: r * bump,
                d: r * bump1 / tt,
                dd: 0.0,
            };
            // Pitch A·sin(2x)·sin(x), x = πτ (peak of sin 2x sin x is 0.7698): the
            // rate ramps up linearly from the stance edges, as at heel-off and after
            // heel strike.
            let amp = self.gait.pitch_peak_rad / 0.769_800_358_919_501;
            let x = std::f64::consts::PI * tau;
            let (sx, cx) = x.sin_cos();
            let (s2x, c2x) = (2.0 * x).sin_cos();
            att[1] = Jet {
                v: amp * s2x * sx,
                d: amp * (2.0 * c2x * sx + s2x * cx) * std::f64::consts::PI / tt,
                dd: 0.0,
            };
        }
        for i in 0..3 {
            for s in &self.tremor_pos[i] {
                pos[i] += s.eval(t);
            }
            for s in &self.tremor_att[i] {
                att[i] += s.eval(t);
            }
        }
        (pos, att, stance)
    }
}

/// Simulate the scenario.
pub fn simulate_foot(scenario: &FootScenario) -> SimulatedFoot {
    let sc = scenario;
    let fin = |v: f64, d: f64| if v.is_finite() { v } else { d };
    let rate = fin(sc.sample_rate_hz, 200.0).clamp(20.0, 2000.0);
    let gait = FootGait {
        stride_length_m: fin(sc.gait.stride_length_m, 1.4).clamp(0.1, 5.0),
        stride_duration_s: fin(sc.gait.stride_duration_s, 1.1).clamp(0.3, 5.0),
        stance_fraction: fin(sc.gait.stance_fraction, 0.4).clamp(0.1, 0.8),
        lift_m: fin(sc.gait.lift_m, 0.1).clamp(0.0, 1.0),
        pitch_peak_rad: fin(sc.gait.pitch_peak_rad, 0.5).clamp(-1.4, 1.4),
        roll_peak_rad: fin(sc.gait.roll_peak_rad, 0.0).clamp(-1.0, 1.0),
    };
    let mut gait_rng = stream(sc.seed, 1);
    let mut tremor_rng = stream(sc.seed, 2);
    let mut bias_rng = stream(sc.seed, 3);
    let mut noise_rng = stream(sc.seed, 4);
    let mut time_rng = stream(sc.seed, 5);

    // Footprints around the rectangle.
    let half_pi = std::f64::consts::FRAC_PI_2;
    let sides = [
        fin(sc.loop_m[0], 20.0).max(gait.stride_length_m * 0.5),
        fin(sc.loop_m[1], 10.0).max(gait.stride_length_m * 0.5),
    ];
    let rise = fin(sc.rise_per_stride_m, 0.0).clamp(-1.0, 1.0);
    let mut prints = vec![Footprint {
        p: [0.0, 0.0],
        z: 0.0,
        yaw: 0.0,
    }];
    let n_sides = 4 * sc.laps as usize;
    for side in 0..n_sides {
        let len = sides[side % 2];
        let n = (len / gait.stride_length_m).round().max(1.0) as usize;
        let dir = half_pi * side as f64;
        let (sd, cd) = dir.sin_cos();
        let start = prints.last().map_or([0.0; 2], |p| p.p);
        for j in 1..=n {
            let d = len * j as f64 / n as f64;
            let corner = j == n && side + 1 < n_sides;
            let z = prints.len() as f64 * rise;
            prints.push(Footprint {
                p: [start[0] + d * cd, start[1] + d * sd],
                z,
                yaw: if corner { dir + 0.5 * half_pi } else { dir },
            });
        }
        // Snap the end of a lap exactly onto the origin (no rounding drift).
        if side % 4 == 3 {
            if let Some(p) = prints.last_mut() {
                p.p = [0.0, 0.0];
            }
        }
    }

    // Timeline.
    let t_start = fin(sc.start_t_s, 0.0);
    let mut t = t_start + fin(sc.rest_start_s, 2.0).max(0.0);
    let walk_start = t;
    let mut motions = Vec::with_capacity(prints.len());
    let mut strides = Vec::with_capacity(prints.len());
    let mut last_onset = walk_start;
    let mut distance = 0.0;
    let jitter = fin(sc.stride_jitter, 0.0).clamp(0.0, 0.2);
    for k in 0..prints.len().saturating_sub(1) {
        let period = gait.stride_duration_s * (1.0 + jitter * gait_rng.normal().clamp(-3.0, 3.0));
        let dur = period * (1.0 - gait.stance_fraction);
        motions.push(Motion {
            t0: t,
            dur,
            from: k,
        });
        let onset = t + dur;
        let (a, b) = (prints[k].p, prints[k + 1].p);
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        distance += len;
        strides.push(TrueStride {
            t_s: onset,
            length_m: len,
            duration_s: onset - last_onset,
        });
        last_onset = onset;
        t += period;
    }
    let t_end = t + fin(sc.rest_end_s, 2.0).max(0.0);

    let tremor = fin(sc.tremor, 1.0).clamp(0.0, 100.0);
    let mut sinus = |amp: f64, f_lo: f64, f_hi: f64| Sinus {
        amp: amp * tremor * tremor_rng.range(0.6, 1.0),
        w: std::f64::consts::TAU * tremor_rng.range(f_lo, f_hi),
        ph: tremor_rng.range(0.0, std::f64::consts::TAU),
    };
    let att_amp = 0.01_f64.to_radians();
    let tremor_att = (0..3)
        .map(|_| [sinus(att_amp, 4.0, 9.0), sinus(att_amp, 4.0, 9.0)])
        .collect();
    let tremor_pos = (0..3)
        .map(|_| [sinus(15e-6, 5.0, 11.0), sinus(15e-6, 5.0, 11.0)])
        .collect();
    let walk = Walk {
        prints,
        motions,
        gait,
        tremor_att,
        tremor_pos,
    };

    let ab_std = fin(sc.accel_bias_std_mps2, 0.0).abs();
    let gb_std = fin(sc.gyro_bias_std_rads, 0.0).abs();
    let accel_bias = [0; 3].map(|_| ab_std * bias_rng.normal());
    let gyro_bias = [0; 3].map(|_| gb_std * bias_rng.normal());
    let an = fin(sc.accel_noise_mps2, 0.0).abs();
    let gn = fin(sc.gyro_noise_rads, 0.0).abs();
    let m = sc.mount_rpy_rad.map(|v| fin(v, 0.0));
    let mount = Rotation3::from_euler_angles(m[0], m[1], m[2]);
    let mount_q = UnitQuaternion::from_rotation_matrix(&mount);
    let drop_p = fin(sc.drop_probability, 0.0).clamp(0.0, 0.9);
    let jit = fin(sc.timestamp_jitter_s, 0.0).abs();
    let dt = 1.0 / rate;

    let n = ((t_end - t_start) * rate).floor() as usize + 1;
    let mut samples = Vec::with_capacity(n);
    let mut truth = Vec::with_capacity(n);
    for i in 0..n {
        let j = (jit * time_rng.normal()).clamp(-0.3 * dt, 0.3 * dt);
        let dropped = time_rng.uniform() < drop_p;
        // Always draw the noise so the streams do not depend on the drops.
        let na = [0; 3].map(|_| an * noise_rng.normal());
        let ng = [0; 3].map(|_| gn * noise_rng.normal());
        if dropped {
            continue;
        }
        let ts = t_start + i as f64 * dt + j;
        let (pos, att, stance) = walk.state(ts);
        let (phi, th, psi) = (att[0].v, att[1].v, att[2].v);
        let (sp, cp) = phi.sin_cos();
        let (st, ct) = th.sin_cos();
        let w_foot = Vector3::new(
            att[0].d - att[2].d * st,
            att[1].d * cp + att[2].d * ct * sp,
            -att[1].d * sp + att[2].d * ct * cp,
        );
        let q_foot = UnitQuaternion::from_euler_angles(phi, th, psi);
        let q = q_foot * mount_q;
        let acc = Vector3::new(pos[0].dd, pos[1].dd, pos[2].dd + GRAVITY_MPS2);
        let f_s = q.inverse_transform_vector(&acc);
        let w_s = mount.inverse_transform_vector(&w_foot);
        let mut f = [0.0; 3];
        let mut w = [0.0; 3];
        for k in 0..3 {
            f[k] = f_s[k] + accel_bias[k] + na[k];
            w[k] = w_s[k] + gyro_bias[k] + ng[k];
        }
        if sc.sensor_z_down {
            f = [f[0], -f[1], -f[2]];
            w = [w[0], -w[1], -w[2]];
        }
        samples.push(FootSample {
            t_s: ts,
            accel_mps2: f,
            gyro_rads: w,
        });
        let qc = q.coords;
        truth.push(FootTruth {
            t_s: ts,
            position_m: [pos[0].v, pos[1].v, pos[2].v],
            velocity_mps: [pos[0].d, pos[1].d, pos[2].d],
            quaternion: [qc.w, qc.x, qc.y, qc.z],
            stance,
        });
    }
    let (accel_bias, gyro_bias) = if sc.sensor_z_down {
        (
            [accel_bias[0], -accel_bias[1], -accel_bias[2]],
            [gyro_bias[0], -gyro_bias[1], -gyro_bias[2]],
        )
    } else {
        (accel_bias, gyro_bias)
    };
    SimulatedFoot {
        scenario: sc.clone(),
        samples,
        truth,
        strides,
        distance_m: distance,
        accel_bias_mps2: accel_bias,
        gyro_bias_rads: gyro_bias,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deterministic_closed_and_consistent() {
        let a = simulate_foot(&FootScenario::walk(3, 1));
        let b = simulate_foot(&FootScenario::walk(3, 1));
        assert_eq!(a, b);
        assert!((a.distance_m - 60.0).abs() < 1e-9, "{}", a.distance_m);
        let last = a.truth.last().unwrap();
        assert!(last.position_m[0].abs() < 1e-3 && last.position_m[1].abs() < 1e-3);
        // Velocity is the derivative of position (finite differences).
        for w in a.truth.windows(2).step_by(37) {
            let dt = w[1].t_s - w[0].t_s;
            for i in 0..3 {
                let fd = (w[1].position_m[i] - w[0].position_m[i]) / dt;
                let mid = 0.5 * (w[1].velocity_mps[i] + w[0].velocity_mps[i]);
                assert!((fd - mid).abs() < 0.02, "{fd} {mid}");
            }
        }
        // At rest the accelerometer reads gravity up.
        let s = a.samples[10];
        assert!((s.accel_mps2[2] - GRAVITY_MPS2).abs() < 0.2, "{s:?}");
    }
}
