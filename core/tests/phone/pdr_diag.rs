//! Diagnostics of the PDR walking direction on the phone simulator (ignored by
//! default; run with `cargo test --release -p stridekit-core --test phone pdr_diag:: --
//! --ignored --nocapture`; `PDR_DIAG_NOMAG=1` without the magnetometer). Prints, per
//! placement and seed, the mean over each minute (GNSS lost after minute 5) of:
//! - `nav`: walking-azimuth error of the navigator (rad);
//! - `yaw`: error of the AHRS yaw after the navigator's correction μ, along the true
//!   walking direction (azimuth through the estimated attitude − μ, minus truth);
//! - `carry`: error of the carrying estimate alone (azimuth of the estimated
//!   body-frame forward vector through the TRUE attitude, minus truth).

use nalgebra::{UnitQuaternion, Vector3};
use stridekit_core::ahrs::ImuSample;
use stridekit_core::geo::LocalFrame;
use stridekit_core::pace::GnssFix;
use stridekit_core::pdr::wrap;
use stridekit_core::pdr::PhoneNavigator;
use stridekit_sim::phone::{navigator_config, simulate_phone, PhonePlacement, PhoneScenario};

fn quat(q: [f64; 4]) -> UnitQuaternion<f64> {
    UnitQuaternion::new_normalize(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]))
}

#[derive(Default)]
struct Mean(f64, f64);
impl Mean {
    fn add(&mut self, a: f64) {
        if a.is_finite() {
            self.0 += a.sin();
            self.1 += a.cos();
        }
    }
    fn take(&mut self) -> f64 {
        let m = self.0.atan2(self.1);
        *self = Mean::default();
        m
    }
}

#[test]
#[ignore]
fn azimuth_error_over_time() {
    let use_mag = std::env::var("PDR_DIAG_NOMAG").is_err();
    for (k, p) in PhonePlacement::ALL.iter().enumerate() {
        for s in 0..3u64 {
            let seed = 100 + 10 * k as u64 + s;
            let mut sc = PhoneScenario::walk(seed, *p, 1.4, 900.0);
            sc.gnss_outages = vec![(300.0, 900.0)];
            let sim = simulate_phone(&sc);
            let frame = LocalFrame::new(47.0, 8.0, 0.0);
            let mut nav = PhoneNavigator::new(navigator_config()).unwrap();
            let mut fi = 0;
            let mut next = 60.0;
            let (mut nav_line, mut yaw_line, mut carry_line) =
                (String::new(), String::new(), String::new());
            let mut hi_sum = Vector3::zeros();
            let mut hi_n = 0.0;
            let mut tilt_line = String::new();
            let (mut tilt_sum, mut tilt_n) = (Vector3::<f64>::zeros(), 0.0f64);
            let (mut m_nav, mut m_yaw, mut m_carry) =
                (Mean::default(), Mean::default(), Mean::default());
            for smp in &sim.samples {
                while fi < sim.fixes.len() && sim.fixes[fi].t_s <= smp.t_s {
                    let f = sim.fixes[fi];
                    let (lat, lon) = frame.to_geodetic(f.east_m, f.north_m);
                    nav.push_fix(&GnssFix::new(f.t_s, lat, lon).with_accuracy(f.accuracy_m))
                        .unwrap();
                    fi += 1;
                }
                let imu = ImuSample {
                    t_s: smp.t_s,
                    gyro_rads: smp.gyro_radps,
                    accel_mps2: smp.accel_mps2,
                    mag_ut: use_mag.then_some(smp.mag_ut),
                };
                nav.push_imu(&imu).unwrap();
                let tr = sim.truth_at(smp.t_s);
                let h = tr.heading_rad;
                let e = nav.estimate().expect("an estimate after input");
                m_nav.add(e.walking_azimuth_rad.map_or(f64::NAN, |a| wrap(a - h)));
                let q_true = quat(tr.attitude_wxyz);
                if (smp.t_s / 0.1 - (smp.t_s / 0.1).round()).abs() < 1e-6 {
                    let b = Vector3::new(0.0, 20.0, -44.0);
                    hi_sum += Vector3::from(smp.mag_ut) - q_true.inverse() * b;
                    hi_n += 1.0;
                    if let Some(q) = nav
                        .orientation()
                        .map(|_| nav.walking_direction().orientation())
                    {
                        // Tilt error in the walking frame (fwd, left, up) components
                        // of (estimated up − true up) expressed in ENU via truth.
                        let up_est_b = quat(q).inverse() * Vector3::z();
                        let d = q_true * up_est_b - Vector3::z();
                        let (s, c) = h.sin_cos();
                        tilt_sum += Vector3::new(d.x * s + d.y * c, -d.x * c + d.y * s, 0.0);
                        tilt_n += 1.0;
                    }
                }
                let wd = nav.walking_direction();
                if let Some(q) = nav
                    .orientation()
                    .map(|_| nav.walking_direction().orientation())
                {
                    let fwd_b = q_true.inverse() * Vector3::new(h.sin(), h.cos(), 0.0);
                    let v = quat(q) * fwd_b;
                    m_yaw.add(wrap(v.x.atan2(v.y) - wd.yaw_correction().0 - h));
                }
                if let Some(f) = wd.forward_body() {
                    let v = q_true * Vector3::from(f);
                    m_carry.add(wrap(v.x.atan2(v.y) - h));
                }
                if smp.t_s >= next {
                    next += 60.0;
                    nav_line += &format!("{:+.2} ", m_nav.take());
                    yaw_line += &format!("{:+.2} ", m_yaw.take());
                    carry_line += &format!("{:+.2} ", m_carry.take());
                    let tm = tilt_sum / tilt_n.max(1.0);
                    tilt_line += &format!("{:+.2}/{:+.2} ", tm.x, tm.y);
                    tilt_sum = Vector3::zeros();
                    tilt_n = 0.0;
                }
            }
            println!(
                "{p:?} seed {seed}: hard iron est {:?} true {:?}\n  nav   {nav_line}\n  yaw   {yaw_line}\n  carry {carry_line}\n  tilt fwd/left {tilt_line}",
                nav.walking_direction().hard_iron_ut().map(|x| (x * 10.0).round() / 10.0),
                (hi_sum / hi_n).map(|x| (x * 10.0).round() / 10.0)
            );
        }
    }
}

/// Rough cost split per sample (release; noisy on a busy machine): AHRS update +
/// output, step detector, whole navigator.
#[test]
#[ignore]
fn cost_split() {
    use std::time::Instant;
    use stridekit_core::ahrs::{Ahrs, AhrsSettings};
    use stridekit_core::stepdetect::{StepDetector, StepDetectorConfig};
    let sim = simulate_phone(&PhoneScenario::walk(
        7,
        PhonePlacement::FrontPocket,
        1.4,
        300.0,
    ));
    let n = sim.samples.len() as f64;
    for _ in 0..3 {
        let mut a = Ahrs::new(AhrsSettings::default()).unwrap();
        let t0 = Instant::now();
        for s in &sim.samples {
            a.update(s.t_s, s.gyro_radps, s.accel_mps2, None).unwrap();
            std::hint::black_box(a.output());
        }
        let ahrs_ns = t0.elapsed().as_nanos() as f64 / n;
        let mut d = StepDetector::new(StepDetectorConfig::default()).unwrap();
        let t0 = Instant::now();
        for s in &sim.samples {
            std::hint::black_box(d.push_accel(s.t_s, s.accel_mps2).unwrap());
            while d.pop_step().is_some() {}
        }
        let det_ns = t0.elapsed().as_nanos() as f64 / n;
        for use_mag in [true, false] {
            let mut nav = PhoneNavigator::new(navigator_config()).unwrap();
            let t0 = Instant::now();
            for s in &sim.samples {
                nav.push_imu(&ImuSample {
                    t_s: s.t_s,
                    gyro_rads: s.gyro_radps,
                    accel_mps2: s.accel_mps2,
                    mag_ut: use_mag.then_some(s.mag_ut),
                })
                .unwrap();
            }
            let nav_ns = t0.elapsed().as_nanos() as f64 / n;
            println!("ahrs+output {ahrs_ns:.0} ns, detector {det_ns:.0} ns, navigator (mag {use_mag}) {nav_ns:.0} ns");
        }
    }
}
