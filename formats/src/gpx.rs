//! GPX 1.0/1.1 reader, including Garmin TrackPointExtension heart rate and cadence.

use roxmltree::Node;

use crate::record::{Cleanup, Record};
use crate::xml;
use crate::FormatError;

const FORMAT: &str = "GPX";

/// Reads the track points (`<trkpt>`) of a GPX document.
///
/// Points without `<time>` are skipped (a GPX route without times yields
/// [`FormatError::Empty`]). From `<extensions>` (any namespace) the reader takes `hr` /
/// `heartrate`, `cad` / `cadence` / `RunCadence` (strides per minute, doubled into
/// `steps_per_min`), `speed` and `distance`.
pub fn read_gpx(text: &str) -> Result<Vec<Record>, FormatError> {
    read_gpx_counted(text).map(|(r, _)| r)
}

/// [`read_gpx`], also saying what the clean-up changed.
pub fn read_gpx_counted(text: &str) -> Result<(Vec<Record>, Cleanup), FormatError> {
    xml::read_track_points(text, FORMAT, "gpx", "trkpt", track_point)
}

fn track_point(point: Node) -> Result<Option<Record>, FormatError> {
    let Some(time) = xml::child(point, "time") else {
        return Ok(None);
    };
    let mut record = Record::at(xml::time(time, FORMAT)?);
    record.lat_deg = Some(coordinate(point, "lat")?);
    record.lon_deg = Some(coordinate(point, "lon")?);
    record.alt_m = xml::child_number(point, "ele", FORMAT)?;
    if let Some(extensions) = xml::child(point, "extensions") {
        for node in extensions.descendants().filter(|n| n.is_element()) {
            let field = match node.tag_name().name().to_ascii_lowercase().as_str() {
                "hr" | "heartrate" => &mut record.heart_rate_bpm,
                "cad" | "cadence" | "runcadence" => &mut record.steps_per_min,
                "speed" => &mut record.device_speed_mps,
                "distance" => &mut record.device_distance_m,
                _ => continue,
            };
            if field.is_none() {
                *field = xml::number(node, FORMAT)?;
            }
        }
    }
    record.steps_per_min = record.steps_per_min.map(|strides| 2.0 * strides);
    Ok(Some(record))
}

fn coordinate(point: Node, name: &str) -> Result<f64, FormatError> {
    let value = point.attribute(name).map(str::trim);
    value.and_then(|v| v.parse().ok()).ok_or_else(|| {
        FormatError::parse(
            FORMAT,
            format!(
                "<trkpt> at {}: {name} attribute {value:?} is missing or not a number",
                xml::position(point)
            ),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const GPX: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<gpx version="1.1" creator="StravaGPX" xmlns="http://www.topografix.com/GPX/1/1"
     xmlns:gpxtpx="http://www.garmin.com/xmlschemas/TrackPointExtension/v1">
 <trk><name>Run</name><trkseg>
   <trkpt lat="-8.0450750" lon="-34.8937870">
    <ele>12.7</ele><time>2021-01-10T08:54:32Z</time>
    <extensions><gpxtpx:TrackPointExtension><gpxtpx:hr>174</gpxtpx:hr><gpxtpx:cad>84</gpxtpx:cad></gpxtpx:TrackPointExtension></extensions>
   </trkpt>
   <trkpt lat="-8.0451150" lon="-34.8938100"><time>2021-01-10T08:54:28Z</time></trkpt>
   <trkpt lat="1" lon="2"><ele>3</ele></trkpt>
 </trkseg></trk>
</gpx>"#;

    #[test]
    fn reads_track_points_with_extensions() {
        let records = read_gpx(GPX).unwrap();
        assert_eq!(records.len(), 2, "point without time skipped");
        assert_eq!(records[0].t_s, 1_610_268_868.0);
        assert_eq!(records[0].lat_deg, Some(-8.045115));
        assert_eq!(records[0].heart_rate_bpm, None);
        let r = records[1];
        assert_eq!((r.lat_deg, r.lon_deg), (Some(-8.045075), Some(-34.893787)));
        assert_eq!(r.alt_m, Some(12.7));
        assert_eq!(r.heart_rate_bpm, Some(174.0));
        assert_eq!(r.steps_per_min, Some(168.0), "gpxtpx:cad is strides/min");
        assert_eq!(r.device_distance_m, None);
    }

    #[test]
    fn a_file_cut_off_mid_write_is_read_up_to_its_last_complete_point() {
        let marker = "<trkpt lat=\"1\" lon=";
        let cut = &GPX[..GPX.find(marker).unwrap() + marker.len()];
        let (records, cleanup) = read_gpx_counted(cut).unwrap();
        assert_eq!(records.len(), 2);
        assert!(cleanup.truncated);
        // A '>' inside a quoted attribute value does not end the tag.
        let quoted = "<gpx creator=\"a>b\"><trk><trkseg><trkpt lat=\"1\" lon=\"2\">\
                      <time>2021-01-10T08:54:28Z</time></trkpt><trkpt lat=\"1\"";
        let (records, cleanup) = read_gpx_counted(quoted).unwrap();
        assert_eq!((records.len(), cleanup.truncated), (1, true));
    }

    #[test]
    fn malformed_inputs_are_typed_errors() {
        let parse_error = |text: &str| {
            matches!(
                read_gpx(text),
                Err(FormatError::Parse { format: "GPX", .. })
            )
        };
        assert!(parse_error(""));
        assert!(parse_error("<gpx><trk>"));
        assert!(parse_error("<TrainingCenterDatabase/>"));
        assert!(parse_error(
            r#"<gpx><trk><trkseg><trkpt lat="x" lon="2"><time>2021-01-10T08:54:28Z</time></trkpt></trkseg></trk></gpx>"#
        ));
        assert!(parse_error(
            r#"<gpx><trk><trkseg><trkpt lon="2"><time>2021-01-10T08:54:28Z</time></trkpt></trkseg></trk></gpx>"#
        ));
        assert!(parse_error(
            r#"<gpx><trk><trkseg><trkpt lat="1" lon="2"><time>2021-13-10T08:54:28Z</time></trkpt></trkseg></trk></gpx>"#
        ));
        assert!(matches!(read_gpx("<gpx/>"), Err(FormatError::Empty)));
    }
}
