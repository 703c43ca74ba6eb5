//! The common record type and the clean-up every reader applies before returning.

use crate::FormatError;

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

    /// Drops non-finite values and incomplete or out-of-range positions.
    fn sanitize(&mut self) {
        for field in self.fields_mut() {
            if field.is_some_and(|v| !v.is_finite()) {
                *field = None;
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
}

/// Records closer in time than this are the same sample (seconds).
const SAME_TIME_S: f64 = 1e-3;

/// Sorts by time, merges records sharing a timestamp, drops non-finite values.
/// Fails with [`FormatError::Empty`] when nothing timed is left.
pub(crate) fn finish(mut records: Vec<Record>) -> Result<Vec<Record>, FormatError> {
    records.retain(|r| r.t_s.is_finite());
    records.iter_mut().for_each(Record::sanitize);
    // Stable sort: among equal times the first record in the file stays first.
    records.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    let mut merged: Vec<Record> = Vec::with_capacity(records.len());
    for record in records {
        match merged.last_mut() {
            Some(last) if record.t_s - last.t_s < SAME_TIME_S => last.fill_from(&record),
            _ => merged.push(record),
        }
    }
    if merged.is_empty() {
        return Err(FormatError::Empty);
    }
    Ok(merged)
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
        let out = finish(vec![a, b, c, nan_time]).unwrap();
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
    fn out_of_range_position_dropped() {
        let mut r = Record::at(0.0);
        r.lat_deg = Some(91.0);
        r.lon_deg = Some(0.0);
        let out = finish(vec![r]).unwrap();
        assert_eq!((out[0].lat_deg, out[0].lon_deg), (None, None));
    }

    #[test]
    fn nothing_left_is_empty() {
        assert!(matches!(finish(vec![]), Err(FormatError::Empty)));
        assert!(matches!(
            finish(vec![Record::at(f64::NAN)]),
            Err(FormatError::Empty)
        ));
    }
}
