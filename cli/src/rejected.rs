//! Counting the samples a replay's engine rejects, by reason, for the summary a replay
//! prints on stderr (a real recording is replayed with its bad samples skipped, not
//! aborted; see docs/api.md, "Replaying recordings").

use std::collections::BTreeMap;

use stridekit_core::stepdetect::StepDetectError;
use stridekit_core::PaceError;

/// Rejected samples by reason.
#[derive(Debug, Default)]
pub struct Rejected {
    by_reason: BTreeMap<String, u64>,
}

/// Reason for a time error: equal timestamps (sensor batching, coarse clocks) are
/// told apart from timestamps going backwards.
fn time_reason(stream: &str, t_s: f64, last_t_s: f64) -> String {
    if t_s == last_t_s {
        format!("{stream}duplicate timestamp (equal to the previous sample's)")
    } else {
        format!("{stream}timestamp before the previous sample's")
    }
}

impl Rejected {
    pub fn total(&self) -> u64 {
        self.by_reason.values().sum()
    }

    fn add(&mut self, reason: String) {
        *self.by_reason.entry(reason).or_insert(0) += 1;
    }

    pub fn pace(&mut self, e: &PaceError) {
        self.add(match e {
            PaceError::TimeNotIncreasing {
                stream,
                t_s,
                last_t_s,
            } => time_reason(&format!("{stream} stream: "), *t_s, *last_t_s),
            PaceError::NonFinite { field } => format!("{field} not a finite number"),
            PaceError::OutOfRange {
                field, expected, ..
            } => format!("{field} out of range ({expected})"),
            other => other.to_string(),
        });
    }

    pub fn steps(&mut self, e: &StepDetectError) {
        self.add(match e {
            StepDetectError::TimeNotIncreasing { t_s, last_t_s } => {
                time_reason("", *t_s, *last_t_s)
            }
            StepDetectError::NonFinite { field } => format!("{field} not a finite number"),
            StepDetectError::OutOfRange {
                field, expected, ..
            } => format!("{field} out of range ({expected})"),
            StepDetectError::LooksLikeG { .. } => {
                "acceleration looks like g, not m/s² (multiply by 9.80665)".into()
            }
            other => other.to_string(),
        });
    }

    /// One line per reason, e.g. `  skipped 205: duplicate timestamp (...)`.
    pub fn report(&self) -> String {
        self.by_reason
            .iter()
            .map(|(r, n)| format!("  skipped {n}: {r}\n"))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_and_reversed_timestamps_are_told_apart() {
        let mut r = Rejected::default();
        for (t, last) in [(1.0, 1.0), (1.0, 1.0), (0.5, 1.0)] {
            r.steps(&StepDetectError::TimeNotIncreasing {
                t_s: t,
                last_t_s: last,
            });
        }
        r.steps(&StepDetectError::NonFinite {
            field: "accel_x_mps2",
        });
        assert_eq!(r.total(), 4);
        let text = r.report();
        assert!(text.contains("skipped 2: duplicate timestamp"), "{text}");
        assert!(text.contains("skipped 1: timestamp before"), "{text}");
        assert!(
            text.contains("skipped 1: accel_x_mps2 not a finite number"),
            "{text}"
        );
    }
}
