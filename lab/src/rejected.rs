//! Counting the samples a replay's engine rejects, by reason, for the summary a replay
//! prints (a real recording is replayed with its bad samples skipped, not aborted; see
//! docs/api.md, "Replaying recordings"). Refusals for a stream's units (timestamps not
//! in seconds, accelerations in g) count once per stream, naming the unit the first
//! refusal named: later intervals, measured from the last accepted sample, would name
//! others.

use std::collections::BTreeMap;

use stridekit_core::ahrs::AhrsError;
use stridekit_core::input::InputError;
use stridekit_core::odometry::OdometryError;
use stridekit_core::pdr::NavError;
use stridekit_core::stepdetect::StepDetectError;
use stridekit_core::PaceError;

/// Rejected samples by reason.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Rejected {
    by_reason: BTreeMap<String, u64>,
    /// Of them, samples refused for their stream's time unit
    /// ([`InputError::is_time_unit`]).
    time_unit: u64,
    /// Refusals for a stream's units, by stream name (`GNSS`, `step`, `accelerometer`,
    /// `IMU`).
    units: BTreeMap<String, UnitRefusal>,
}

/// The samples of one stream refused for their units.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnitRefusal {
    pub samples: u64,
    /// What the first refusal said, e.g. `GNSS timestamps are not seconds: they look
    /// like milliseconds (divide by 1000)`.
    pub message: String,
}

/// The stream a unit refusal is about and what it says; `None` for other errors.
/// `accel_stream` names the stream accelerations come in (`accelerometer`, `IMU`).
pub fn unit_refusal(e: &InputError, accel_stream: &str) -> Option<(String, String)> {
    match e {
        InputError::TimeUnit { stream, likely, .. } => Some((
            stream.to_string(),
            format!(
                "{stream} timestamps are not seconds: they look like {likely} (divide by {})",
                likely.per_second()
            ),
        )),
        InputError::TimeTooFine { stream, .. } => Some((
            stream.to_string(),
            format!(
                "{stream} timestamps are not seconds: they advance by less than a microsecond \
                 per sample, finer than any sensor samples (milliseconds divided by 10⁹ as if \
                 nanoseconds? multiply by 10⁶)"
            ),
        )),
        InputError::AccelerationInG { .. } => Some((
            accel_stream.to_string(),
            "accelerations look like g, not m/s² (multiply by 9.80665)".into(),
        )),
        _ => None,
    }
}

/// The reason a sample was refused at the door, without the sample's own values, so
/// that equal reasons count together. Equal timestamps (sensor batching, coarse clocks)
/// are told apart from timestamps going backwards.
pub fn input_reason(e: &InputError) -> String {
    match e {
        InputError::TimeNotIncreasing { stream, .. } if e.is_duplicate_time() => {
            format!("{stream} stream: duplicate timestamp (equal to the previous sample's)")
        }
        InputError::TimeNotIncreasing { stream, .. } => {
            format!("{stream} stream: timestamp before the previous sample's")
        }
        InputError::NonFinite { field } => format!("{field} not a finite number"),
        InputError::OutOfRange {
            field,
            min,
            max,
            unit,
            ..
        } => format!("{field} out of range ({min} to {max} {unit})"),
        InputError::TimeUnit { stream, likely, .. } => {
            format!("{stream} timestamps look like {likely}, not seconds")
        }
        InputError::TimeTooFine { stream, .. } => format!(
            "{stream} timestamps finer than any sensor samples: not seconds \
             (milliseconds divided by 10⁹ as if nanoseconds?)"
        ),
        InputError::TimeJump { stream, .. } => {
            format!("{stream} stream: clock jumped by more than a year")
        }
        InputError::AccelerationInG { .. } => {
            "acceleration looks like g, not m/s² (multiply by 9.80665)".into()
        }
    }
}

/// The reason the phone navigator refused a sample (see [`input_reason`]).
pub fn nav_reason(e: &NavError) -> String {
    match e {
        NavError::Input(i) => input_reason(i),
        other => other.to_string(),
    }
}

impl Rejected {
    pub fn total(&self) -> u64 {
        self.by_reason.values().sum::<u64>() + self.units.values().map(|u| u.samples).sum::<u64>()
    }

    /// A sample skipped for a reason of the replay's own (e.g. no rotation vector).
    pub fn add(&mut self, reason: String) {
        *self.by_reason.entry(reason).or_insert(0) += 1;
    }

    /// A sample refused at the door (see [`input_reason`]); accelerations come in the
    /// accelerometer stream.
    pub fn input(&mut self, e: &InputError) {
        self.input_in(e, "accelerometer");
    }

    /// [`Rejected::input`], accelerations coming in `accel_stream`.
    pub fn input_in(&mut self, e: &InputError, accel_stream: &str) {
        if e.is_time_unit() {
            self.time_unit += 1;
        }
        match unit_refusal(e, accel_stream) {
            Some((stream, message)) => {
                self.units
                    .entry(stream)
                    .or_insert(UnitRefusal {
                        samples: 0,
                        message,
                    })
                    .samples += 1;
            }
            None => self.add(input_reason(e)),
        }
    }

    /// Samples refused because their stream's timestamps are not seconds: a replay
    /// with any has a stream in the wrong unit (its other samples of that stream were
    /// held or refused too) and should fail, naming the unit (the reasons say it).
    pub fn time_unit(&self) -> u64 {
        self.time_unit
    }

    pub fn pace(&mut self, e: &PaceError) {
        match e {
            PaceError::Input(i) => self.input(i),
            other => self.add(other.to_string()),
        }
    }

    pub fn steps(&mut self, e: &StepDetectError) {
        match e {
            StepDetectError::Input(i) => self.input(i),
            other => self.add(other.to_string()),
        }
    }

    pub fn ahrs(&mut self, e: &AhrsError) {
        match e {
            AhrsError::Input(i) => self.input_in(i, "IMU"),
            other => self.add(other.to_string()),
        }
    }

    pub fn odometry(&mut self, e: &OdometryError) {
        match e {
            OdometryError::Input(i) => self.input_in(i, "IMU"),
            other => self.add(other.to_string()),
        }
    }

    /// A sample the phone navigator refused.
    pub fn nav(&mut self, e: &NavError) {
        match e {
            NavError::Input(i) => self.input_in(i, "IMU"),
            other => self.add(other.to_string()),
        }
    }

    /// The counts by reason, unit refusals not included (see
    /// [`Rejected::unit_refusals`]).
    pub fn counts(&self) -> &BTreeMap<String, u64> {
        &self.by_reason
    }

    /// The refusals for a stream's units, by stream.
    pub fn unit_refusals(&self) -> &BTreeMap<String, UnitRefusal> {
        &self.units
    }

    /// One line per reason, e.g. `  skipped 205: duplicate timestamp (...)`; one per
    /// stream refused for its units, naming the unit.
    pub fn report(&self) -> String {
        let units = self
            .units
            .values()
            .map(|u| format!("  skipped {}: {}\n", u.samples, u.message));
        let others = self
            .by_reason
            .iter()
            .map(|(r, n)| format!("  skipped {n}: {r}\n"));
        units.chain(others).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stridekit_core::input::Stream;

    #[test]
    fn equal_and_reversed_timestamps_are_told_apart() {
        let mut r = Rejected::default();
        for (t, last) in [(1.0, 1.0), (1.0, 1.0), (0.5, 1.0)] {
            r.steps(&StepDetectError::Input(InputError::TimeNotIncreasing {
                stream: Stream::Accelerometer,
                t_s: t,
                last_t_s: last,
            }));
        }
        r.steps(&StepDetectError::Input(InputError::NonFinite {
            field: "accel_x_mps2",
        }));
        assert_eq!(r.total(), 4);
        assert_eq!(r.time_unit(), 0);
        let text = r.report();
        assert!(
            text.contains("skipped 2: accelerometer stream: duplicate timestamp"),
            "{text}"
        );
        assert!(
            text.contains("skipped 1: accelerometer stream: timestamp before"),
            "{text}"
        );
        assert!(
            text.contains("skipped 1: accel_x_mps2 not a finite number"),
            "{text}"
        );
    }

    #[test]
    fn unit_refusals_count_once_per_stream_naming_the_first_unit() {
        use stridekit_core::input::LikelyTimeUnit;
        let mut r = Rejected::default();
        for likely in [
            LikelyTimeUnit::Milliseconds,
            LikelyTimeUnit::Microseconds,
            LikelyTimeUnit::Microseconds,
        ] {
            r.pace(&PaceError::Input(InputError::TimeUnit {
                stream: Stream::Gnss,
                t_s: 3000.0,
                interval_s: 1000.0,
                likely,
            }));
        }
        r.ahrs(&AhrsError::Input(InputError::AccelerationInG {
            mean_magnitude: 1.0,
        }));
        assert_eq!(r.total(), 4);
        assert_eq!(
            r.report(),
            "  skipped 3: GNSS timestamps are not seconds: they look like milliseconds (divide by 1000)\n\
             \x20 skipped 1: accelerations look like g, not m/s² (multiply by 9.80665)\n"
        );
        assert_eq!(r.unit_refusals()["IMU"].samples, 1);
        assert!(r.counts().is_empty());
    }
}
