//! One sensor event as a phone delivers it: which sensor, its time, three values.
//! The sensor codes are Android's `Sensor.TYPE_*` constants, so an app passes
//! `event.sensor.type` straight through.

use crate::input::{self, InputError, Stream};

/// Which sensor an event comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SensorKind {
    /// Specific force, m/s², gravity included (Android `TYPE_ACCELEROMETER` = 1).
    Accelerometer,
    /// Angular rate, rad/s (Android `TYPE_GYROSCOPE` = 4).
    Gyroscope,
    /// Magnetic field, µT (Android `TYPE_MAGNETIC_FIELD` = 2).
    Magnetometer,
}

impl SensorKind {
    /// Android's `Sensor.TYPE_ACCELEROMETER`.
    pub const ANDROID_ACCELEROMETER: i64 = 1;
    /// Android's `Sensor.TYPE_MAGNETIC_FIELD`.
    pub const ANDROID_MAGNETIC_FIELD: i64 = 2;
    /// Android's `Sensor.TYPE_GYROSCOPE`.
    pub const ANDROID_GYROSCOPE: i64 = 4;

    /// The kind of an Android `Sensor.TYPE_*` code (None for other sensors).
    pub fn from_android(code: i64) -> Option<Self> {
        match code {
            Self::ANDROID_ACCELEROMETER => Some(Self::Accelerometer),
            Self::ANDROID_GYROSCOPE => Some(Self::Gyroscope),
            Self::ANDROID_MAGNETIC_FIELD => Some(Self::Magnetometer),
            _ => None,
        }
    }

    /// Android's `Sensor.TYPE_*` code of this kind.
    pub fn android_code(self) -> i64 {
        match self {
            Self::Accelerometer => Self::ANDROID_ACCELEROMETER,
            Self::Gyroscope => Self::ANDROID_GYROSCOPE,
            Self::Magnetometer => Self::ANDROID_MAGNETIC_FIELD,
        }
    }

    /// The input stream whose time rules the events follow.
    pub fn stream(self) -> Stream {
        match self {
            Self::Accelerometer => Stream::Accelerometer,
            Self::Gyroscope => Stream::Gyroscope,
            Self::Magnetometer => Stream::Magnetometer,
        }
    }
}

/// One event of one sensor, device axes as the platform reports them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuEvent {
    /// Seconds on the app's monotonic clock (the same clock for every sensor).
    pub t_s: f64,
    pub kind: SensorKind,
    /// x, y, z in the kind's unit (m/s², rad/s, µT).
    pub values: [f64; 3],
}

impl ImuEvent {
    /// The value checks of the input layer for this kind (time is checked by the
    /// merger, per stream).
    pub fn check_values(&self) -> Result<(), InputError> {
        match self.kind {
            SensorKind::Accelerometer => input::accel(&self.values),
            SensorKind::Gyroscope => input::gyro(&self.values),
            SensorKind::Magnetometer => input::mag(&self.values),
        }
    }
}
