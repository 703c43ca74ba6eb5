//! Reader for RIDI (Yan, Shan, Furukawa 2018) sequences: `<sequence>/processed/data.csv`
//! with a header naming the columns. Used: `time` (nanoseconds), `gyro_x gyro_y
//! gyro_z` (rad/s), `acce_x acce_y acce_z` (m/s², gravity included), optional
//! `magnet_x magnet_y magnet_z` (µT), `pos_x pos_y pos_z` (Tango position, m, z up).
//! The file also holds `linacce_*`, `grav_*`, `ori_w..z` (Tango orientation) and
//! `rv_*`/game rotation vectors, which are not needed (the pipeline runs its own AHRS).
//! Column names as read by RoNIN's `RIDIGlobSpeedSequence`; the magnetometer
//! column names are an assumption (the file is read without them when absent).
//! The placement is guessed from the sequence name (RIDI names sequences
//! `<person>_<placement><n>`: `body` → front_pocket, `bag` → bag, `hand` → in_hand,
//! `leg` → front_pocket).

use crate::error::FormatError;
use crate::inertial::{parse_rows, InertialRecording};

const FORMAT: &str = "RIDI CSV";

/// Placement name from a RIDI sequence name.
pub fn ridi_placement(name: &str) -> Option<String> {
    let n = name.to_ascii_lowercase();
    let p = if n.contains("bag") {
        "bag"
    } else if n.contains("hand") {
        "in_hand"
    } else if n.contains("leg") || n.contains("body") {
        "front_pocket"
    } else {
        return None;
    };
    Some(p.to_string())
}

/// Parse the text of a `processed/data.csv`.
pub fn parse_ridi_csv(name: &str, text: &str) -> Result<InertialRecording, FormatError> {
    parse_layout(FORMAT, name, ridi_placement(name), text, "time", 1e-9)
}

/// A recording named `name` in the RIDI column layout (RoNIN's export uses it too:
/// the two differ only in the time column, its unit in seconds, and what the name
/// tells of the placement).
pub(crate) fn parse_layout(
    format: &'static str,
    name: &str,
    placement: Option<String>,
    text: &str,
    time_column: &'static str,
    time_scale: f64,
) -> Result<InertialRecording, FormatError> {
    let (samples, truth, skipped) = parse_rows(format, text, time_column, time_scale)?;
    Ok(InertialRecording {
        name: name.to_string(),
        placement,
        samples,
        truth,
        skipped,
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_small_ridi_file() {
        let text = "time,gyro_x,gyro_y,gyro_z,acce_x,acce_y,acce_z,pos_x,pos_y,pos_z,ori_w\n\
                    1000000000,0.1,0.2,0.3,0,0,9.8,1,2,0,1\n\
                    1005000000,0.1,0.2,0.3,0,0,9.8,1.5,2,0,1\n";
        let r = parse_ridi_csv("dan_bag1", text).unwrap();
        assert_eq!(r.samples.len(), 2);
        assert!((r.samples[1].t_s - 1.005).abs() < 1e-12);
        assert_eq!(r.samples[0].accel_mps2, [0.0, 0.0, 9.8]);
        assert_eq!(r.placement.as_deref(), Some("bag"));
        let (x, y) = r.position_at(1.0025);
        assert!((x - 1.25).abs() < 1e-9 && y == 2.0);
        assert!(matches!(
            parse_ridi_csv("x", "time,gyro_x\n1,2\n"),
            Err(FormatError::MissingColumn(_))
        ));
    }
}
