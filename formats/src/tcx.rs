//! Garmin Training Center XML (TCX) reader.

use roxmltree::Node;

use crate::record::{Cleanup, Record};
use crate::xml;
use crate::FormatError;

const FORMAT: &str = "TCX";

/// Reads the trackpoints of a TCX document (activities and courses alike).
///
/// Trackpoints without a `<Time>` are skipped. Cadence comes from the `RunCadence`
/// extension, else the core `Cadence` element; both are strides per minute and are doubled
/// into `steps_per_min`.
pub fn read_tcx(text: &str) -> Result<Vec<Record>, FormatError> {
    read_tcx_counted(text).map(|(r, _)| r)
}

/// [`read_tcx`], also saying what the clean-up changed.
pub fn read_tcx_counted(text: &str) -> Result<(Vec<Record>, Cleanup), FormatError> {
    xml::read_track_points(
        text,
        FORMAT,
        "TrainingCenterDatabase",
        "Trackpoint",
        trackpoint,
    )
}

fn trackpoint(point: Node) -> Result<Option<Record>, FormatError> {
    let Some(time) = xml::child(point, "Time") else {
        return Ok(None);
    };
    let mut record = Record::at(xml::time(time, FORMAT)?);
    if let Some(position) = xml::child(point, "Position") {
        record.lat_deg = xml::child_number(position, "LatitudeDegrees", FORMAT)?;
        record.lon_deg = xml::child_number(position, "LongitudeDegrees", FORMAT)?;
    }
    record.alt_m = xml::child_number(point, "AltitudeMeters", FORMAT)?;
    record.device_distance_m = xml::child_number(point, "DistanceMeters", FORMAT)?;
    if let Some(hr) = xml::child(point, "HeartRateBpm") {
        record.heart_rate_bpm = xml::child_number(hr, "Value", FORMAT)?;
    }
    let mut strides_per_min = xml::child_number(point, "Cadence", FORMAT)?;
    if let Some(extensions) = xml::child(point, "Extensions") {
        // <TPX> (ActivityExtension v2), with or without a namespace prefix.
        for tpx in xml::elements(extensions, "TPX") {
            if let Some(speed) = xml::child_number(tpx, "Speed", FORMAT)? {
                record.device_speed_mps = Some(speed);
            }
            if let Some(cadence) = xml::child_number(tpx, "RunCadence", FORMAT)? {
                strides_per_min = Some(cadence);
            }
        }
    }
    record.steps_per_min = strides_per_min.map(|c| 2.0 * c);
    Ok(Some(record))
}

#[cfg(test)]
mod tests {
    use super::*;

    const TCX: &str = r#"  <?xml version="1.0" encoding="UTF-8"?>
<TrainingCenterDatabase xmlns="http://www.garmin.com/xmlschemas/TrainingCenterDatabase/v2"
    xmlns:ns3="http://www.garmin.com/xmlschemas/ActivityExtension/v2">
  <Activities><Activity Sport="Running"><Id>2021-01-10T08:54:22Z</Id>
    <Lap StartTime="2021-01-10T08:54:22Z"><Track>
      <Trackpoint>
        <Time>2021-01-10T08:54:32Z</Time>
        <Position><LatitudeDegrees>-8.045075</LatitudeDegrees><LongitudeDegrees>-34.893787</LongitudeDegrees></Position>
        <AltitudeMeters>9.35</AltitudeMeters>
        <DistanceMeters>5.04</DistanceMeters>
        <HeartRateBpm><Value>150</Value></HeartRateBpm>
        <Extensions><ns3:TPX><ns3:Speed>2.5</ns3:Speed><ns3:RunCadence>84</ns3:RunCadence></ns3:TPX></Extensions>
      </Trackpoint>
      <Trackpoint>
        <Time>2021-01-10T08:54:28Z</Time>
        <DistanceMeters>0.0</DistanceMeters>
        <Cadence>80</Cadence>
        <Extensions><TPX xmlns="http://www.garmin.com/xmlschemas/ActivityExtension/v2"><Speed>0.0</Speed></TPX></Extensions>
      </Trackpoint>
      <Trackpoint><DistanceMeters>1.0</DistanceMeters></Trackpoint>
    </Track></Lap></Activity></Activities>
</TrainingCenterDatabase>"#;

    #[test]
    fn reads_trackpoints_sorted() {
        let records = read_tcx(TCX).unwrap();
        assert_eq!(records.len(), 2, "trackpoint without time skipped");
        let first = records[0];
        assert_eq!(first.t_s, 1_610_268_868.0);
        assert_eq!((first.lat_deg, first.lon_deg), (None, None));
        assert_eq!(first.device_distance_m, Some(0.0));
        assert_eq!(first.device_speed_mps, Some(0.0));
        assert_eq!(
            first.steps_per_min,
            Some(160.0),
            "core <Cadence> is strides/min"
        );
        let second = records[1];
        assert_eq!(second.t_s, 1_610_268_872.0);
        assert_eq!(second.lat_deg, Some(-8.045075));
        assert_eq!(second.lon_deg, Some(-34.893787));
        assert_eq!(second.alt_m, Some(9.35));
        assert_eq!(second.device_distance_m, Some(5.04));
        assert_eq!(second.device_speed_mps, Some(2.5));
        assert_eq!(second.steps_per_min, Some(168.0));
        assert_eq!(second.heart_rate_bpm, Some(150.0));
        assert_eq!(second.horizontal_accuracy_m, None);
        assert_eq!(second.step_count, None);
    }

    #[test]
    fn a_file_cut_off_mid_write_is_read_up_to_its_last_complete_trackpoint() {
        // Cut inside the second trackpoint's extension, and inside a tag.
        for marker in ["<Speed>0.0", "<Cadence"] {
            let cut = &TCX[..TCX.find(marker).unwrap() + marker.len() - 2];
            let (records, cleanup) = read_tcx_counted(cut).unwrap();
            assert_eq!(records.len(), 1);
            assert_eq!(records[0].t_s, 1_610_268_872.0);
            assert_eq!(records[0].device_speed_mps, Some(2.5));
            assert!(cleanup.truncated);
            assert!(cleanup.reasons()[0].0.contains("cut off"));
        }
        let (_, whole) = read_tcx_counted(TCX).unwrap();
        assert!(!whole.truncated);
        // Tags that do not nest are not repaired.
        assert!(read_tcx("<TrainingCenterDatabase><Trackpoint><Time>2021-01-10T08:54:28Z</Time></Trackpoint></Lap><Trackpoint>").is_err());
    }

    #[test]
    fn malformed_inputs_are_typed_errors() {
        let parse_error = |text: &str| {
            matches!(
                read_tcx(text),
                Err(FormatError::Parse { format: "TCX", .. })
            )
        };
        assert!(parse_error(""));
        assert!(parse_error("not xml at all"));
        assert!(parse_error("<TrainingCenterDatabase><Trackpoint>"));
        assert!(parse_error("<gpx/>"));
        assert!(parse_error(
            "<TrainingCenterDatabase><Trackpoint><Time>noon</Time></Trackpoint></TrainingCenterDatabase>"
        ));
        let bad_number = read_tcx(
            "<TrainingCenterDatabase><Trackpoint><Time>2021-01-10T08:54:28Z</Time>\
             <DistanceMeters>far</DistanceMeters></Trackpoint></TrainingCenterDatabase>",
        );
        match bad_number {
            Err(FormatError::Parse { message, .. }) => {
                assert!(
                    message.contains("DistanceMeters") && message.contains("line 1"),
                    "{message}"
                )
            }
            other => panic!("expected a parse error, got {other:?}"),
        }
        assert!(matches!(
            read_tcx("<TrainingCenterDatabase/>"),
            Err(FormatError::Empty)
        ));
    }
}
