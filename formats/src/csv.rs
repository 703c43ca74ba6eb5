//! CSV reader: the reference layout of the shared data set and a minimal layout for users.

use crate::record::{finish_counted, Cleanup, Record};
use crate::{FormatError, Unreadable};

const FORMAT: &str = "CSV";

/// Where each known column sits in a row.
#[derive(Default)]
struct Columns {
    time: usize,
    lat: usize,
    lon: usize,
    alt: Option<usize>,
    distance: Option<usize>,
    speed: Option<usize>,
    steps_per_min: Option<usize>,
    strides_per_min: Option<usize>,
    heart_rate: Option<usize>,
    accuracy: Option<usize>,
    steps: Option<usize>,
}

impl Columns {
    fn from_header(header: &[&str]) -> Result<Self, FormatError> {
        let find = |names: &[&str]| {
            names
                .iter()
                .find_map(|name| header.iter().position(|h| h.eq_ignore_ascii_case(name)))
        };
        Ok(Columns {
            time: find(&["t_unix_s", "t_s"])
                .ok_or(FormatError::MissingColumn("t_s or t_unix_s"))?,
            lat: find(&["lat_deg"]).ok_or(FormatError::MissingColumn("lat_deg"))?,
            lon: find(&["lon_deg"]).ok_or(FormatError::MissingColumn("lon_deg"))?,
            alt: find(&["alt_m"]),
            distance: find(&["device_distance_m"]),
            speed: find(&["device_speed_mps", "speed_mps"]),
            steps_per_min: find(&["steps_per_min"]),
            strides_per_min: find(&["cadence_strides_per_min"]),
            heart_rate: find(&["heart_rate_bpm"]),
            accuracy: find(&["horizontal_accuracy_m"]),
            steps: find(&["steps", "step_count"]),
        })
    }
}

/// Reads a CSV file with a header row. Columns are matched by name (case-insensitive), in
/// any order; unknown columns are ignored.
///
/// Required: `t_s` or `t_unix_s` (seconds, UNIX epoch), `lat_deg`, `lon_deg`. Optional:
/// `alt_m`, `device_distance_m`, `device_speed_mps` or `speed_mps`, `steps_per_min` (else
/// 2 × `cadence_strides_per_min`), `heart_rate_bpm`, `horizontal_accuracy_m`, `steps`
/// (cumulative step count). Empty cells and `nan` mean "no value". Fields are split on
/// commas without quoting rules (surrounding double quotes are stripped); blank lines and
/// lines starting with `#` are skipped.
pub fn read_csv(text: &str) -> Result<Vec<Record>, FormatError> {
    read_csv_counted(text).map(|(r, _)| r)
}

/// [`read_csv`], also saying what the clean-up changed.
pub fn read_csv_counted(text: &str) -> Result<(Vec<Record>, Cleanup), FormatError> {
    let mut lines = text
        .trim_start_matches('\u{feff}')
        .lines()
        .enumerate()
        .map(|(i, line)| (i + 1, line.trim()))
        .filter(|(_, line)| !line.is_empty() && !line.starts_with('#'));
    let Some((_, header)) = lines.next() else {
        return Err(FormatError::parse(FORMAT, "no header row"));
    };
    let header = split(header);
    let columns = Columns::from_header(&header)?;
    let mut records = Vec::new();
    let mut unreadable = Unreadable::default();
    let mut first_error = None;
    let mut last_read = true;
    for (line_no, line) in lines {
        let row = || -> Result<Record, FormatError> {
            let cells = split(line);
            if cells.len() != header.len() {
                return Err(FormatError::parse(
                    FORMAT,
                    format!(
                        "line {line_no}: {} fields, the header has {}",
                        cells.len(),
                        header.len()
                    ),
                ));
            }
            let cell = |index: Option<usize>| -> Result<Option<f64>, FormatError> {
                let Some(index) = index else {
                    return Ok(None);
                };
                let text = cells[index];
                if text.is_empty() {
                    return Ok(None);
                }
                text.parse::<f64>().map(Some).map_err(|_| {
                    FormatError::parse(
                        FORMAT,
                        format!(
                            "line {line_no}, column {:?}: {text:?} is not a number",
                            header[index]
                        ),
                    )
                })
            };
            let t_s = cell(Some(columns.time))?
                .ok_or_else(|| FormatError::parse(FORMAT, format!("line {line_no}: empty time")))?;
            let strides_per_min = cell(columns.strides_per_min)?;
            Ok(Record {
                t_s,
                lat_deg: cell(Some(columns.lat))?,
                lon_deg: cell(Some(columns.lon))?,
                alt_m: cell(columns.alt)?,
                device_distance_m: cell(columns.distance)?,
                device_speed_mps: cell(columns.speed)?,
                steps_per_min: match columns.steps_per_min {
                    Some(_) => cell(columns.steps_per_min)?,
                    None => strides_per_min.map(|c| 2.0 * c),
                },
                heart_rate_bpm: cell(columns.heart_rate)?,
                horizontal_accuracy_m: cell(columns.accuracy)?,
                step_count: cell(columns.steps)?,
            })
        };
        // A row that cannot be read (wrong field count, not a number, no time: a
        // truncated last line, a stray note) is skipped and counted, not fatal.
        last_read = match row() {
            Ok(r) => {
                records.push(r);
                true
            }
            Err(e) => {
                unreadable.add(line_no);
                first_error.get_or_insert(e);
                false
            }
        };
    }
    if let (true, Some(e)) = (records.is_empty(), first_error) {
        return Err(e);
    }
    let (records, mut cleanup) = finish_counted(records)?;
    cleanup.unreadable = unreadable;
    cleanup.truncated = crate::sniff::cut_mid_row(text, last_read);
    Ok((records, cleanup))
}

fn split(line: &str) -> Vec<&str> {
    line.split(',')
        .map(|cell| {
            let cell = cell.trim();
            cell.strip_prefix('"')
                .and_then(|c| c.strip_suffix('"'))
                .unwrap_or(cell)
                .trim()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_layout() {
        let text = "t_unix_s,lat_deg,lon_deg,alt_m,device_distance_m,device_speed_mps,\
cadence_strides_per_min,steps_per_min,step_length_mm,heart_rate_bpm,vertical_oscillation_mm,\
stance_time_ms,gps_cum_distance_m\n\
1497191572.0,38.2305,-122.6333,-0.6,1.6,1.409,53,106,641.0,71,41.0,,1.65\n\
1497191571.0,,,,0.0,,53.5,,651.0,,43.7,,0.0\n";
        let records = read_csv(text).unwrap();
        assert_eq!(records.len(), 2);
        let r = records[0];
        assert_eq!(r.t_s, 1_497_191_571.0);
        assert_eq!((r.lat_deg, r.lon_deg, r.alt_m), (None, None, None));
        assert_eq!(r.device_distance_m, Some(0.0));
        assert_eq!(
            r.steps_per_min, None,
            "steps_per_min column wins when present"
        );
        let r = records[1];
        assert_eq!((r.lat_deg, r.lon_deg), (Some(38.2305), Some(-122.6333)));
        assert_eq!(r.device_speed_mps, Some(1.409));
        assert_eq!(r.steps_per_min, Some(106.0));
        assert_eq!(r.heart_rate_bpm, Some(71.0));
    }

    #[test]
    fn strides_column_doubled_when_no_steps_column() {
        let text = "t_s,lat_deg,lon_deg,cadence_strides_per_min\n0,1,2,85.5\n";
        assert_eq!(read_csv(text).unwrap()[0].steps_per_min, Some(171.0));
    }

    #[test]
    fn minimal_layout() {
        let text = "\u{feff}# phone export\r\nT_S, lat_deg, lon_deg, speed_mps, horizontal_accuracy_m, steps, extra\r\n\
                    \r\n\
                    10.5, 48.1, 11.5, 3.2, 4.0, 1000, x\r\n\
                    11.5, 48.1001, 11.5, nan, 5.0, 1003, y\r\n";
        let records = read_csv(text).unwrap();
        assert_eq!(records.len(), 2);
        assert_eq!(records[0].t_s, 10.5);
        assert_eq!(records[0].device_speed_mps, Some(3.2));
        assert_eq!(records[0].horizontal_accuracy_m, Some(4.0));
        assert_eq!(records[0].step_count, Some(1000.0));
        assert_eq!(records[1].device_speed_mps, None, "NaN dropped");
        assert_eq!(records[1].step_count, Some(1003.0));
        assert_eq!(records[1].steps_per_min, None);
    }

    #[test]
    fn malformed_inputs_are_typed_errors() {
        assert!(matches!(
            read_csv(""),
            Err(FormatError::Parse { format: "CSV", .. })
        ));
        assert!(matches!(
            read_csv("lat_deg,lon_deg\n1,2\n"),
            Err(FormatError::MissingColumn("t_s or t_unix_s"))
        ));
        assert!(matches!(
            read_csv("t_s,lat_deg\n1,2\n"),
            Err(FormatError::MissingColumn("lon_deg"))
        ));
        let message = |text: &str| match read_csv(text) {
            Err(FormatError::Parse { message, .. }) => message,
            other => panic!("expected a parse error, got {other:?}"),
        };
        assert!(message("t_s,lat_deg,lon_deg\n1,2\n").contains("line 2"));
        assert!(message("t_s,lat_deg,lon_deg\nnorth,2,3\n").contains("line 2"));
        // With readable rows, the unreadable ones are skipped and counted.
        let (records, cleanup) =
            read_csv_counted("t_s,lat_deg,lon_deg\n1,2,3\n2,north,3\n3,2,3\n4,2\n").unwrap();
        assert_eq!(records.len(), 2);
        assert_eq!(
            (cleanup.unreadable.rows, cleanup.unreadable.first_line),
            (2, Some(3))
        );
        assert!(!cleanup.truncated, "the last row ends with a line end");
        // A file cut inside its last row.
        let (records, cleanup) = read_csv_counted("t_s,lat_deg,lon_deg\n1,2,3\n2,2").unwrap();
        assert_eq!((records.len(), cleanup.truncated), (1, true));
        assert!(
            !read_csv_counted("t_s,lat_deg,lon_deg\n1,2,3")
                .unwrap()
                .1
                .truncated
        );
        assert!(message("t_s,lat_deg,lon_deg\n,2,3\n").contains("empty time"));
        assert!(matches!(
            read_csv("t_s,lat_deg,lon_deg\n"),
            Err(FormatError::Empty)
        ));
    }
}
