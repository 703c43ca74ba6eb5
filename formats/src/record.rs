//! The common record type and the clean-up every reader applies before returning.

use crate::{FormatError, Unreadable};

/// One timed sample of an activity. Fields a file does not provide are `None`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Record {
    /// Seconds since the UNIX epoch (UTC). FIT times are converted from the FIT epoch
    /// (1989-12-31). Exception: FIT files from devices without a clock (e.g. a foot pod
    /// paired to a watch that never had a GPS fix) store "system time", seconds since
    /// power-on (raw values below 0x10000000); those are kept as-is, like python-fitparse
    /// does, so only differences between them are meaningful.
    pub t_s: f64,
    /// Latitude, degrees (WGS 84). Always `Some` together with `lon_deg`.
    pub lat_deg: Option<f64>,
    /// Longitude, degrees (WGS 84). Always `Some` together with `lat_deg`.
    pub lon_deg: Option<f64>,
    /// Altitude, metres.
    pub alt_m: Option<f64>,
    /// Cumulative distance as reported by the device (GNSS or foot pod), metres.
    pub device_distance_m: Option<f64>,
    /// Speed as reported by the device (GNSS or foot pod), m/s.
    pub device_speed_mps: Option<f64>,
    /// Cadence counting both feet (= 2 × strides/min).
    pub steps_per_min: Option<f64>,
    /// Heart rate, beats per minute.
    pub heart_rate_bpm: Option<f64>,
    /// Horizontal accuracy (1 σ or as the phone reports it), metres. CSV only.
    pub horizontal_accuracy_m: Option<f64>,
    /// Cumulative step count. CSV only.
    pub step_count: Option<f64>,
}

impl Record {
    /// A record at time `t_s` with every other field empty.
    pub fn at(t_s: f64) -> Self {
        Record {
            t_s,
            ..Record::default()
        }
    }

    /// The optional fields, for code that treats them alike.
    fn fields_mut(&mut self) -> [&mut Option<f64>; 9] {
        [
            &mut self.lat_deg,
            &mut self.lon_deg,
            &mut self.alt_m,
            &mut self.device_distance_m,
            &mut self.device_speed_mps,
            &mut self.steps_per_min,
            &mut self.heart_rate_bpm,
            &mut self.horizontal_accuracy_m,
            &mut self.step_count,
        ]
    }

    /// Drops non-finite values and incomplete or out-of-range positions. Returns how
    /// many non-position values were dropped and whether a position was.
    fn sanitize(&mut self) -> (u64, bool) {
        let had_position = self.lat_deg.is_some() || self.lon_deg.is_some();
        let mut dropped = 0;
        // Latitude and longitude are checked as a pair below (NaN fails the range).
        for field in self.fields_mut().into_iter().skip(2) {
            if field.is_some_and(|v| !v.is_finite()) {
                *field = None;
                dropped += 1;
            }
        }
        let position_ok = matches!(
            (self.lat_deg, self.lon_deg),
            (Some(lat), Some(lon)) if lat.abs() <= 90.0 && lon.abs() <= 180.0
        );
        if !position_ok {
            self.lat_deg = None;
            self.lon_deg = None;
        }
        (dropped, had_position && !position_ok)
    }

    /// Fills the fields this record lacks from `other` (a record with the same time).
    /// The position is taken as a pair so latitude and longitude never come from
    /// different samples.
    fn fill_from(&mut self, other: &Record) {
        if self.lat_deg.is_none() {
            self.lat_deg = other.lat_deg;
            self.lon_deg = other.lon_deg;
        }
        let mut other = *other;
        for (mine, theirs) in self
            .fields_mut()
            .into_iter()
            .zip(other.fields_mut())
            .skip(2)
        {
            if mine.is_none() {
                *mine = *theirs;
            }
        }
    }
}

/// An imported activity file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Activity {
    /// The file stem, e.g. `morning-run` for `morning-run.fit`.
    pub name: String,
    /// Records sorted by time, one per timestamp.
    pub records: Vec<Record>,
    /// What the reader's clean-up changed (dropped, sorted, merged), by kind.
    pub cleanup: Cleanup,
}

/// Records closer in time than this are the same sample (seconds).
const SAME_TIME_S: f64 = 1e-3;

/// What the clean-up every reader applies changed in a file, by kind (counts).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Cleanup {
    /// Records dropped because their time is missing or not a finite number.
    pub untimed_records: u64,
    /// Values (speed, cadence, …) dropped because they are NaN or infinite.
    pub non_finite_values: u64,
    /// Positions dropped: latitude or longitude missing, not finite or out of range.
    pub invalid_positions: u64,
    /// Records that came earlier in time than the record before them in the file
    /// (sorted into place).
    pub out_of_order_records: u64,
    /// Records merged into another with the same timestamp (within 1 ms).
    pub merged_records: u64,
    /// Rows a text reader could not read (CSV: wrong field count, not a number, no
    /// time), skipped.
    pub unreadable: Unreadable,
    /// The file was cut off (XML not closed, a FIT file without its closing CRC, a CSV
    /// ending inside a row) and was read up to its last complete record.
    pub truncated: bool,
}

impl Cleanup {
    /// `(reason, count)` for every non-zero count, in a fixed order.
    pub fn reasons(&self) -> Vec<(String, u64)> {
        [
            (
                "file cut off mid-write, read up to its last complete record".into(),
                u64::from(self.truncated),
            ),
            (
                self.unreadable
                    .reason()
                    .map_or_else(String::new, |(why, _)| format!("{why}, skipped")),
                self.unreadable.rows,
            ),
            (
                "record without a valid time, dropped".into(),
                self.untimed_records,
            ),
            (
                "NaN or infinite value, dropped".into(),
                self.non_finite_values,
            ),
            (
                "position missing half, not finite or out of range, dropped".into(),
                self.invalid_positions,
            ),
            (
                "record out of time order, sorted".into(),
                self.out_of_order_records,
            ),
            (
                "record with the same timestamp as another, merged".into(),
                self.merged_records,
            ),
        ]
        .into_iter()
        .filter(|(_, n)| *n > 0)
        .collect()
    }
}

/// Sorts by time, merges records sharing a timestamp, drops non-finite values, and
/// says what it changed. Fails with [`FormatError::Empty`] when nothing timed is left.
pub(crate) fn finish_counted(
    mut records: Vec<Record>,
) -> Result<(Vec<Record>, Cleanup), FormatError> {
    let mut cleanup = Cleanup::default();
    let before = records.len();
    records.retain(|r| r.t_s.is_finite());
    cleanup.untimed_records = (before - records.len()) as u64;
    for r in records.iter_mut() {
        let (values, position) = r.sanitize();
        cleanup.non_finite_values += values;
        cleanup.invalid_positions += u64::from(position);
    }
    cleanup.out_of_order_records =
        records.windows(2).filter(|w| w[1].t_s < w[0].t_s).count() as u64;
    // Stable sort: among equal times the first record in the file stays first.
    records.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    let mut merged: Vec<Record> = Vec::with_capacity(records.len());
    for record in records {
        match merged.last_mut() {
            Some(last) if record.t_s - last.t_s < SAME_TIME_S => {
                last.fill_from(&record);
                cleanup.merged_records += 1;
            }
            _ => merged.push(record),
        }
    }
    if merged.is_empty() {
        return Err(FormatError::Empty);
    }
    Ok((merged, cleanup))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sorts_merges_and_sanitizes() {
        let mut a = Record::at(2.0);
        a.heart_rate_bpm = Some(120.0);
        let mut b = Record::at(1.0);
        b.lat_deg = Some(10.0);
        b.lon_deg = Some(f64::NAN);
        b.alt_m = Some(f64::INFINITY);
        let mut c = Record::at(2.0);
        c.heart_rate_bpm = Some(99.0);
        c.steps_per_min = Some(170.0);
        c.lat_deg = Some(1.0);
        c.lon_deg = Some(2.0);
        let nan_time = Record::at(f64::NAN);
        let out = finish_counted(vec![a, b, c, nan_time]).unwrap().0;
        assert_eq!(out.len(), 2);
        assert_eq!(out[0].t_s, 1.0);
        assert_eq!(
            (out[0].lat_deg, out[0].lon_deg, out[0].alt_m),
            (None, None, None)
        );
        assert_eq!(out[1].heart_rate_bpm, Some(120.0), "first record wins");
        assert_eq!(
            out[1].steps_per_min,
            Some(170.0),
            "gaps filled from duplicates"
        );
        assert_eq!((out[1].lat_deg, out[1].lon_deg), (Some(1.0), Some(2.0)));
    }

    #[test]
    fn the_clean_up_is_counted() {
        let mut bad_pos = Record::at(3.0);
        bad_pos.lat_deg = Some(f64::NAN);
        bad_pos.lon_deg = Some(1.0);
        let mut half = Record::at(4.0);
        half.lat_deg = Some(1.0);
        let mut nan_speed = Record::at(1.0);
        nan_speed.device_speed_mps = Some(f64::NAN);
        let records = vec![
            Record::at(2.0),
            nan_speed,
            bad_pos,
            half,
            Record::at(4.0005),
            Record::at(f64::NAN),
        ];
        let (out, c) = finish_counted(records).unwrap();
        assert_eq!(out.len(), 4);
        assert_eq!(
            c,
            Cleanup {
                untimed_records: 1,
                non_finite_values: 1,
                invalid_positions: 2,
                out_of_order_records: 1,
                merged_records: 1,
                ..Default::default()
            }
        );
        assert_eq!(c.reasons().len(), 5);
        let (_, clean) = finish_counted(vec![Record::at(1.0), Record::at(2.0)]).unwrap();
        assert!(clean.reasons().is_empty());
    }

    #[test]
    fn out_of_range_position_dropped() {
        let mut r = Record::at(0.0);
        r.lat_deg = Some(91.0);
        r.lon_deg = Some(0.0);
        let out = finish_counted(vec![r]).unwrap().0;
        assert_eq!((out[0].lat_deg, out[0].lon_deg), (None, None));
    }

    #[test]
    fn nothing_left_is_empty() {
        assert!(matches!(finish_counted(vec![]), Err(FormatError::Empty)));
        assert!(matches!(
            finish_counted(vec![Record::at(f64::NAN)]),
            Err(FormatError::Empty)
        ));
    }
}
