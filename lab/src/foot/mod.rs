//! Foot-mounted navigation in the lab: the VICON-trial evaluation (`eval foot`), its
//! diagnosis and tuning, the leave-one-session-out split and the SVM zero-velocity
//! trainer (`train zupt`) that produced the shipped model.

pub mod alignment;
pub mod detector_gap;
pub mod device;
pub mod diagnose;
pub mod eval;
pub mod sessions;
pub mod train_zupt;
pub mod tune_shoe;

use stridekit_core::foot::FootError;

/// Samples a replay skipped, by the navigator's reason.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Skipped {
    /// Time equal to the previous accepted sample's.
    pub repeated_time: usize,
    /// Time before the previous accepted sample's.
    pub time_backwards: usize,
    pub non_finite: usize,
    pub out_of_range: usize,
    /// Rejected before alignment as accelerations in g.
    pub in_g: usize,
    /// Timestamps not in seconds (milliseconds, nanoseconds), and what the first such
    /// refusal said (the unit it names).
    pub time_unit: usize,
    pub time_unit_message: Option<String>,
    pub other: usize,
    /// Index of the first skipped sample and its error.
    pub first: Option<(usize, String)>,
}

impl Skipped {
    pub fn add(&mut self, index: usize, e: &FootError) {
        use stridekit_core::input::InputError as I;
        match e {
            FootError::Input(i) if i.is_duplicate_time() => self.repeated_time += 1,
            FootError::Input(I::TimeNotIncreasing { .. }) => self.time_backwards += 1,
            FootError::Input(I::NonFinite { .. }) => self.non_finite += 1,
            FootError::Input(I::OutOfRange { .. }) => self.out_of_range += 1,
            FootError::Input(I::AccelerationInG { .. }) => self.in_g += 1,
            FootError::Input(i @ I::TimeUnit { .. }) => {
                self.time_unit += 1;
                if self.time_unit_message.is_none() {
                    self.time_unit_message =
                        crate::rejected::unit_refusal(i, "IMU").map(|(_, m)| m);
                }
            }
            _ => self.other += 1,
        }
        self.first.get_or_insert_with(|| (index, e.to_string()));
    }

    pub fn total(&self) -> usize {
        self.repeated_time
            + self.time_backwards
            + self.non_finite
            + self.out_of_range
            + self.in_g
            + self.time_unit
            + self.other
    }

    /// "none", or the counts by reason.
    pub fn describe(&self) -> String {
        let parts: Vec<String> = [
            (self.repeated_time, "time equal to the previous sample's"),
            (self.time_backwards, "time before the previous sample's"),
            (self.non_finite, "NaN or infinite value"),
            (self.out_of_range, "value out of range"),
            (self.in_g, "accelerations in g, not m/s²"),
            (
                self.time_unit,
                self.time_unit_message
                    .as_deref()
                    .unwrap_or("timestamps not in seconds"),
            ),
            (self.other, "other"),
        ]
        .iter()
        .filter(|(n, _)| *n > 0)
        .map(|(n, why)| format!("{n} {why}"))
        .collect();
        if parts.is_empty() {
            "none".into()
        } else {
            parts.join(", ")
        }
    }
}
