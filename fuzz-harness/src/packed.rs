//! Every packed batch entry point of the bindings, called as the FFI would: no input
//! may panic (a caught panic surfaces as an `Internal` error, which fails the target),
//! every call returns a value or a typed error, and the object stays usable (its
//! snapshot restores).
//!
//! The first input byte picks the encoding: odd → the rest as raw bytes (any length);
//! even → records whose fields are decoded by [`crate::bytes`] (plausible values,
//! extremes, time faults), so the fuzzer reaches the engines behind the door.

use stridekit::foot::{FootNavigator, FootOutput};
use stridekit::phone::navigator::PhoneNavigator;
use stridekit::phone::odometry::PhoneOdometry;
use stridekit::phone::orientation::{OrientationFilter, OrientationOutput};
use stridekit::phone::placement::PlacementClassifier;
use stridekit::PaceTracker;

use crate::bytes::Bytes;

/// How to draw one f64 field of a record.
#[derive(Clone, Copy)]
enum Field {
    /// A time with this nominal interval.
    Time(f64),
    /// A value around `center` with this scale.
    Value(f64, f64),
    /// A cumulative step count (u64 LE).
    Count,
    /// An Android sensor type (i64 LE): mostly 1, 4, 2, sometimes any byte.
    Sensor,
}

use Field::{Count, Sensor, Time, Value as V};

const FIX: &[Field] = &[
    Time(1.0),
    V(47.0, 1e-4),
    V(8.0, 1e-4),
    V(400.0, 10.0),
    V(5.0, 2.0),
    V(3.0, 1.0),
    V(0.5, 0.2),
];
const STEP_COUNT: &[Field] = &[Time(1.0), Count];
const ACCEL: &[Field] = &[Time(0.01), V(0.0, 3.0), V(0.0, 3.0), V(9.81, 3.0)];
/// The 9-axis IMU record (`stridekit::packed`): `t_s`, accel xyz, gyro xyz, mag xyz.
const IMU: &[Field] = &[
    Time(0.01),
    V(0.0, 1.5),
    V(0.0, 1.5),
    V(9.81, 1.5),
    V(0.0, 0.5),
    V(0.0, 0.5),
    V(0.0, 0.5),
    V(20.0, 5.0),
    V(0.0, 5.0),
    V(-40.0, 5.0),
];
/// A separate sensor event (`stridekit::packed`): `t_s`, sensor type, x y z.
const EVENT: &[Field] = &[Time(0.004), Sensor, V(0.0, 3.0), V(0.0, 3.0), V(9.81, 3.0)];
/// The 6-axis IMU record (foot): `t_s`, accel xyz, gyro xyz.
const FOOT: &[Field] = &[
    Time(0.005),
    V(0.0, 5.0),
    V(0.0, 5.0),
    V(9.81, 5.0),
    V(0.0, 2.0),
    V(0.0, 2.0),
    V(0.0, 2.0),
];

/// Records of `layout` drawn from `data` (see the module docs).
fn encode(data: &[u8], layout: &[Field]) -> Vec<u8> {
    let Some((&mode, rest)) = data.split_first() else {
        return Vec::new();
    };
    if mode & 1 == 1 {
        return rest.to_vec();
    }
    let mut b = Bytes::new(rest);
    let mut out = Vec::new();
    let mut t = 0.0;
    let mut count = 0u64;
    let mut n = 0;
    while !b.is_empty() && n < 2_000 {
        for f in layout {
            let v = match *f {
                Time(dt) => b.time(&mut t, dt),
                V(c, s) => b.value(c, s),
                Sensor => {
                    let k = b.u8();
                    let code: i64 = match k % 8 {
                        0..=2 => 1,
                        3 | 4 => 4,
                        5 | 6 => 2,
                        _ => i64::from(k),
                    };
                    out.extend_from_slice(&code.to_le_bytes());
                    continue;
                }
                Count => {
                    count = match b.u8() {
                        255 => u64::from(b.u8()) << 40,
                        254 => 0,
                        k => count + u64::from(k % 6),
                    };
                    out.extend_from_slice(&count.to_le_bytes());
                    continue;
                }
            };
            out.extend_from_slice(&v.to_le_bytes());
        }
        n += 1;
    }
    out
}

/// A result (value or error) that does not report a caught panic.
fn typed<T: std::fmt::Debug>(what: &str, r: T) {
    let text = format!("{r:?}");
    assert!(
        !text.contains("Internal") && !text.contains("panicked"),
        "{what}: a panic crossed the door: {text}"
    );
}

pub fn pace_fixes(data: &[u8]) {
    let p = PaceTracker::with_defaults();
    typed("fixes", p.push_fixes_packed(encode(data, FIX)));
    assert!(PaceTracker::restore(p.snapshot()).is_ok());
}

pub fn pace_step_counts(data: &[u8]) {
    let p = PaceTracker::with_defaults();
    typed(
        "step counts",
        p.push_step_counts_packed(encode(data, STEP_COUNT)),
    );
    assert!(PaceTracker::restore(p.snapshot()).is_ok());
}

pub fn pace_accel(data: &[u8]) {
    let p = PaceTracker::with_defaults();
    typed("accel", p.push_accel_packed(encode(data, ACCEL)));
    assert!(PaceTracker::restore(p.snapshot()).is_ok());
}

pub fn navigator_imu(data: &[u8]) {
    let n = PhoneNavigator::with_defaults();
    typed("navigator imu", n.push_imu_packed(encode(data, IMU)));
    assert!(PhoneNavigator::restore(n.snapshot()).is_ok());
}

pub fn navigator_events(data: &[u8]) {
    let n = PhoneNavigator::with_defaults();
    typed(
        "navigator events",
        n.push_sensor_events_packed(encode(data, EVENT)),
    );
    assert!(PhoneNavigator::restore(n.snapshot()).is_ok());
    typed("navigator events flushed", n.flush_sensor_events());
    assert!(PhoneNavigator::restore(n.snapshot()).is_ok());
}

pub fn odometry_imu(data: &[u8]) {
    let o = PhoneOdometry::with_defaults();
    typed("odometry imu", o.push_imu_packed(encode(data, IMU)));
    assert!(PhoneOdometry::restore(o.snapshot()).is_ok());
}

pub fn orientation_imu(data: &[u8]) {
    let f = OrientationFilter::with_defaults();
    typed(
        "orientation imu",
        f.push_imu_packed(encode(data, IMU), OrientationOutput::LatestOnly),
    );
    assert!(OrientationFilter::restore(f.snapshot()).is_ok());
}

pub fn placement_accel(data: &[u8]) {
    let c = PlacementClassifier::with_defaults();
    typed("placement accel", c.push_accel_packed(encode(data, ACCEL)));
    assert!(PlacementClassifier::restore(c.snapshot()).is_ok());
}

pub fn foot(data: &[u8]) {
    let n = FootNavigator::with_defaults();
    typed(
        "foot",
        n.push_packed(encode(data, FOOT), FootOutput::LatestOnly),
    );
    assert!(FootNavigator::restore(n.snapshot()).is_ok());
}
