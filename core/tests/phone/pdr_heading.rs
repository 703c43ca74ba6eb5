//! Behaviour of the walking-direction estimator of PDR (`pdr::heading`): the direction
//! of travel from the gait, turns, magnetometer drift cancelling and the GNSS sign flip.

use std::f64::consts::PI;

use nalgebra::{UnitQuaternion, Vector3};
use stridekit_core::pdr::{wrap, WalkingDirection};
use stridekit_sim::Rng;

const GRAVITY_MPS2: f64 = 9.80665;

/// The phone upright in a pocket: body y up, body x pointing 1 rad anticlockwise of
/// forward (phone body → walking frame x forward, y left, z up).
fn pocket() -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 1.0)
        * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.5 * PI)
}

/// A walker heading `az(t)` with the phone at `body_to_walk` (e.g. [`pocket`]),
/// inverted-pendulum acceleration (its forward part's gait phase multiplied by
/// `gait_sign`: −1, the gait cue says backwards) plus sway and noise, an ideal AHRS
/// whose yaw drifts by `drift` rad/s, and a magnetometer if `mag`, its field turned
/// about the vertical by `field_turn(t)` rad (steel nearby: the same strength and dip,
/// another azimuth).
#[allow(clippy::too_many_arguments)]
fn walk(
    wd: &mut WalkingDirection,
    rng: &mut Rng,
    t0: f64,
    seconds: f64,
    az_of_t: impl Fn(f64) -> f64,
    step_hz: f64,
    drift: f64,
    mag: bool,
    body_to_walk: UnitQuaternion<f64>,
    gait_sign: f64,
    field_turn: impl Fn(f64) -> f64,
) -> f64 {
    let fs = 100.0;
    let mut next_step = t0 + 1.0 / step_hz;
    let n = (seconds * fs) as usize;
    let mut t = t0;
    let field = Vector3::new(0.0, 20.0, -44.0);
    for i in 0..n {
        t = t0 + i as f64 / fs;
        let ph = 2.0 * PI * step_hz * (t - t0);
        let vz = 0.15 * ph.cos();
        let a_up = -0.15 * 2.0 * PI * step_hz * ph.sin();
        let a_fwd = -gait_sign * 2.0 * vz / 0.15 * 0.6 + 0.2 * rng.normal();
        let a_side = 0.4 * (0.5 * ph).sin() + 0.2 * rng.normal();
        let az = az_of_t(t);
        // True attitude: walking frame (x fwd, y left, z up) → ENU, then the phone.
        let walk_to_enu = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.5 * PI - az);
        let q_true = walk_to_enu * body_to_walk;
        let q_ahrs = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), -drift * t) * q_true;
        let a_true = walk_to_enu * Vector3::new(a_fwd, a_side, a_up + GRAVITY_MPS2);
        let a_ahrs = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), -drift * t) * a_true;
        let turned = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), field_turn(t)) * field;
        let m = mag.then(|| (q_true.inverse() * turned).into());
        wd.push_sample(t, &q_ahrs, a_ahrs.into(), m, None);
        if t >= next_step {
            wd.push_step(step_hz);
            next_step += 1.0 / step_hz;
        }
    }
    t
}

/// The walking azimuth after `seconds` of walking towards `az` from t = 0 (noise seed
/// `seed`) with the phone at `pose` and the gait cue's sign `gait_sign`
/// (magnetometer, no yaw drift).
fn azimuth_after(
    seconds: f64,
    seed: u64,
    az: f64,
    pose: UnitQuaternion<f64>,
    gait_sign: f64,
) -> f64 {
    let mut wd = WalkingDirection::new();
    let mut rng = Rng::new(seed);
    let az_of_t = |_| az;
    walk(
        &mut wd,
        &mut rng,
        0.0,
        seconds,
        az_of_t,
        1.8,
        0.0,
        true,
        pose,
        gait_sign,
        |_| 0.0,
    );
    wd.azimuth_rad().unwrap()
}

#[test]
fn finds_the_walking_direction_from_the_gait() {
    for az in [0.3, 2.0, -2.5] {
        let est = azimuth_after(30.0, 1, az, pocket(), 1.0);
        assert!(wrap(est - az).abs() < 0.1, "{az}: {est}");
    }
}

#[test]
fn a_phone_held_to_be_read_walks_towards_its_top_edge() {
    // Screen up, tilted 40° towards the walker, top edge 0.1 rad left of forward
    // (phone body x right, y top edge, z out of the screen).
    let read = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), -0.5 * PI + 0.1)
        * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 40f64.to_radians());
    for (az, gait_sign) in [(0.3, 1.0), (2.0, -1.0), (-2.5, -1.0)] {
        // From the first strides, even where the gait cue says backwards: the top
        // edge's azimuth (0.1 rad anticlockwise of the walking direction).
        let est = azimuth_after(3.0, 4, az, read, gait_sign);
        assert!(wrap(est - (az - 0.1)).abs() < 0.05, "{az}: {est}");
    }
    // Upside down (top edge towards the walker, lower than the bottom edge): not the
    // reading pose, the gait cue decides (forward here).
    let upside_down = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.5 * PI)
        * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), -40f64.to_radians());
    assert!(wrap(azimuth_after(3.0, 4, 2.0, upside_down, 1.0) - 2.0).abs() < 0.5 * PI);
    // The same gait in a pocket follows the gait cue: backwards when it says so.
    assert!(wrap(azimuth_after(3.0, 4, 2.0, pocket(), -1.0) - 2.0).abs() > 0.5 * PI);
}

#[test]
fn follows_turns_and_the_magnetometer_cancels_yaw_drift() {
    // A raw gyroscope: the fast magnetic loop follows its drift.
    let mut wd = WalkingDirection::with_gyro_calibrated(false);
    let mut rng = Rng::new(2);
    // Straight north, then a 90° right turn over 3 s, then east; the AHRS yaw
    // drifts 0.01 rad/s.
    let az = |t: f64| {
        if t < 20.0 {
            0.0
        } else if t < 23.0 {
            0.5 * PI * (t - 20.0) / 3.0
        } else {
            0.5 * PI
        }
    };
    walk(
        &mut wd,
        &mut rng,
        0.0,
        200.0,
        az,
        1.8,
        0.01,
        true,
        pocket(),
        1.0,
        |_| 0.0,
    );
    assert!(wrap(wd.azimuth_rad().unwrap() - 0.5 * PI).abs() < 0.1);
}

#[test]
fn steel_passed_bends_the_heading_of_a_calibrated_gyroscope_less() {
    // Walking north; from 30 s to 35 s the field turns by 30° (steel passed), with its
    // strength and dip unchanged, so no gate rejects it. The walking azimuth's
    // largest departure over the walk: the slow loop of a calibrated gyroscope keeps
    // most of the disturbance out, the raw gyroscope's fast loop follows it.
    let largest_departure = |gyro_calibrated: bool| {
        let mut wd = WalkingDirection::with_gyro_calibrated(gyro_calibrated);
        let mut rng = Rng::new(5);
        let steel = |t: f64| {
            if (30.0..35.0).contains(&t) {
                PI / 6.0
            } else {
                0.0
            }
        };
        // North in a pocket, one second at a time, in the field of the moment.
        let go = |wd: &mut WalkingDirection, rng: &mut Rng, t0: f64, seconds: f64| {
            walk(
                wd,
                rng,
                t0,
                seconds,
                |_| 0.0,
                1.8,
                0.0,
                true,
                pocket(),
                1.0,
                steel,
            );
        };
        go(&mut wd, &mut rng, 0.0, 30.0);
        let before = wd.azimuth_rad().unwrap();
        let mut worst: f64 = 0.0;
        for k in 0..30 {
            let t0 = 30.0 + k as f64;
            let mut r = Rng::new(100 + k);
            go(&mut wd, &mut r, t0, 1.0);
            worst = worst.max(wrap(wd.azimuth_rad().unwrap() - before).abs());
        }
        worst
    };
    let (calibrated, raw) = (largest_departure(true), largest_departure(false));
    // (Measured: 2.1° against 11.8°; the gait's own stride-to-stride noise is in both.)
    assert!(
        calibrated < 4f64.to_radians(),
        "{}",
        calibrated.to_degrees()
    );
    assert!(
        raw > 3.0 * calibrated,
        "{} {}",
        raw.to_degrees(),
        calibrated.to_degrees()
    );
}

#[test]
fn gnss_flips_a_wrong_sign_once_and_calibrates() {
    let mut wd = WalkingDirection::new();
    let mut rng = Rng::new(3);
    // North-east-ish in a pocket, no magnetometer.
    let walk_ne = |wd: &mut WalkingDirection, rng: &mut Rng, t0: f64, seconds: f64| {
        walk(
            wd,
            rng,
            t0,
            seconds,
            |_| 1.0,
            1.8,
            0.0,
            false,
            pocket(),
            1.0,
            |_| 0.0,
        );
    };
    walk_ne(&mut wd, &mut rng, 0.0, 10.0);
    let before = wd.azimuth_rad().unwrap();
    wd.observe_rotation(PI - 0.1, 10.0, 0.5);
    assert!(wd.sign_resolved());
    walk_ne(&mut wd, &mut rng, 10.0, 2.0);
    let after = wd.azimuth_rad().unwrap();
    assert!(
        (wrap(after - before).abs() - (PI - 0.05)).abs() < 0.05,
        "{before} {after}"
    );
}

#[test]
fn wrap_is_in_range() {
    for a in [-10.0, -PI, 0.0, PI, 7.0] {
        let w = wrap(a);
        assert!(w > -PI && w <= PI, "{a} -> {w}");
    }
}
