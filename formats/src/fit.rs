//! Garmin FIT reader (record messages), decoded with the `fitparser` crate.

use fitparser::de::{DecodeOption, FitObject, FitStreamProcessor};
use fitparser::profile::MesgNum;
use fitparser::{ErrorKind, FitDataRecord, Value};

use crate::record::{finish_counted, Cleanup, Record};
use crate::FormatError;

const FORMAT: &str = "FIT";
/// 1989-12-31T00:00:00Z, the FIT epoch, in UNIX seconds.
const FIT_EPOCH_UNIX_S: i64 = 631_065_600;
/// FIT `date_time` values below this are seconds since device power-on, not dates.
const FIT_MIN_DATE_TIME: i64 = 0x1000_0000;
const DEG_PER_SEMICIRCLE: f64 = 180.0 / 2_147_483_648.0;

/// Reads the `record` messages of a FIT file (chained FIT files included).
///
/// `cadence` (+ `fractional_cadence`) is strides per minute and is doubled into
/// `steps_per_min`; `enhanced_speed` / `enhanced_altitude` are preferred over `speed` /
/// `altitude`. A file cut short (a watch that lost power, a partial download: it ends
/// inside a message or before its closing CRC) keeps the records decoded before the
/// cut and says so in [`Cleanup::truncated`]; any other decoding error, CRC mismatches
/// included, fails the whole file.
///
/// No input panics: fitparser 0.11 adds without overflow checks in its accumulated
/// fields (`profile/mod.rs`, "attempt to add with overflow" on crafted files in builds
/// with overflow checks). The workspace builds fitparser without overflow checks in
/// every profile, as release builds are, where the same input returns an error; and a
/// panic inside the decoder is caught here and returned as a parse error.
pub fn read_fit(bytes: &[u8]) -> Result<Vec<Record>, FormatError> {
    read_fit_counted(bytes).map(|(r, _)| r)
}

/// [`read_fit`], also saying what the clean-up changed.
pub fn read_fit_counted(bytes: &[u8]) -> Result<(Vec<Record>, Cleanup), FormatError> {
    std::panic::catch_unwind(|| decode(bytes)).unwrap_or_else(|payload| {
        let what = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "panic".into());
        Err(FormatError::parse(
            FORMAT,
            format!("the FIT decoder failed on this file ({what})"),
        ))
    })
}

fn decode(bytes: &[u8]) -> Result<(Vec<Record>, Cleanup), FormatError> {
    let fit_error = |e: fitparser::Error| FormatError::parse(FORMAT, e.to_string());
    if bytes.is_empty() {
        return Err(FormatError::parse(FORMAT, "empty file"));
    }
    let mut processor = FitStreamProcessor::new();
    // Keep `compressed_speed_distance` so its distance can be accumulated here (see
    // `CompressedDistance`).
    processor.add_option(DecodeOption::KeepCompositeFields);
    let mut compressed_distance = CompressedDistance::default();
    let mut records = Vec::new();
    let mut rest = bytes;
    // The file ends where a FIT file ends: after its CRC.
    let mut closed = false;
    while !rest.is_empty() {
        let (next, object) = match processor.deserialize_next(rest) {
            Ok(next) => next,
            Err(e) if matches!(*e, ErrorKind::UnexpectedEof(_)) && !records.is_empty() => {
                closed = false;
                break;
            }
            Err(e) => return Err(fit_error(e)),
        };
        closed = matches!(object, FitObject::Crc(_));
        match object {
            // End of one FIT file; another may be chained after it.
            FitObject::Crc(_) => {
                processor.reset();
                compressed_distance = CompressedDistance::default();
            }
            // Every data message must be decoded, even unused ones: a compressed-timestamp
            // header updates the running time base.
            FitObject::DataMessage(message) => {
                let decoded = processor.decode_message(message).map_err(fit_error)?;
                if decoded.kind() == MesgNum::Record {
                    records.extend(record(&decoded, &mut compressed_distance));
                }
            }
            FitObject::Header(_) | FitObject::DefinitionMessage(_) => {}
        }
        rest = next;
    }
    let (records, mut cleanup) = finish_counted(records)?;
    cleanup.truncated = !closed;
    Ok((records, cleanup))
}

/// Distance carried in the 3-byte `compressed_speed_distance` field of foot pods: the
/// high 12 bits are distance in 1/16 m, modulo 4096, to be accumulated with roll-over
/// (FIT SDK / python-fitparse rule). fitparser 0.11 instead adds each raw value to the
/// previous total (14.25 m then 14.25 + 18.875 m instead of 18.875 m), so the
/// distance is recomputed here from the raw bytes.
#[derive(Default)]
struct CompressedDistance {
    /// Running total, 1/16 m.
    total: u64,
}

impl CompressedDistance {
    const BITS: u32 = 12;

    fn update(&mut self, raw_field: &Value) -> Option<f64> {
        let Value::Array(bytes) = raw_field else {
            return None;
        };
        let [b0, b1, b2] = bytes.as_slice() else {
            return None;
        };
        let packed = [b0, b1, b2]
            .iter()
            .enumerate()
            .try_fold(0u64, |acc, (i, b)| {
                Some(acc | (number(b)? as u64) << (8 * i))
            })?;
        let mask = (1u64 << Self::BITS) - 1;
        let raw = packed >> Self::BITS;
        self.total += raw.wrapping_sub(self.total) & mask;
        Some(self.total as f64 / 16.0)
    }
}

/// Converts one `record` message; `None` when it has no timestamp.
fn record(message: &FitDataRecord, compressed_distance: &mut CompressedDistance) -> Option<Record> {
    let mut t_s = None;
    let mut record = Record::default();
    let (mut lat, mut lon) = (None, None);
    let (mut altitude, mut enhanced_altitude) = (None, None);
    let (mut speed, mut enhanced_speed) = (None, None);
    let (mut cadence, mut fractional_cadence) = (None, None);
    let mut accumulated_distance = None;
    for field in message.fields() {
        let value = field.value();
        match field.name() {
            "timestamp" => t_s = timestamp(value),
            "position_lat" => lat = degrees(value, field.units()),
            "position_long" => lon = degrees(value, field.units()),
            "altitude" => altitude = number(value),
            "enhanced_altitude" => enhanced_altitude = number(value),
            "speed" => speed = number(value),
            "enhanced_speed" => enhanced_speed = number(value),
            "distance" => record.device_distance_m = number(value),
            "compressed_speed_distance" => accumulated_distance = compressed_distance.update(value),
            "heart_rate" => record.heart_rate_bpm = number(value),
            "cadence" => cadence = number(value),
            "fractional_cadence" => fractional_cadence = number(value),
            _ => {}
        }
    }
    record.t_s = t_s?;
    record.lat_deg = lat;
    record.lon_deg = lon;
    record.alt_m = enhanced_altitude.or(altitude);
    record.device_distance_m = accumulated_distance.or(record.device_distance_m);
    record.device_speed_mps = enhanced_speed.or(speed);
    record.steps_per_min = cadence.map(|c| 2.0 * (c + fractional_cadence.unwrap_or(0.0)));
    Some(record)
}

/// UNIX seconds for a FIT timestamp; device "system time" (before any clock sync) is
/// returned as raw seconds since power-on, as python-fitparse does.
fn timestamp(value: &Value) -> Option<f64> {
    let Value::Timestamp(time) = value else {
        return None;
    };
    let unix_s = time.timestamp();
    let fit_s = unix_s - FIT_EPOCH_UNIX_S;
    let seconds = if (0..FIT_MIN_DATE_TIME).contains(&fit_s) {
        fit_s
    } else {
        unix_s
    };
    Some(seconds as f64 + f64::from(time.timestamp_subsec_nanos()) * 1e-9)
}

fn degrees(value: &Value, units: &str) -> Option<f64> {
    let v = number(value)?;
    Some(if units == "semicircles" {
        v * DEG_PER_SEMICIRCLE
    } else {
        v
    })
}

fn number(value: &Value) -> Option<f64> {
    match *value {
        Value::SInt8(v) => Some(v.into()),
        Value::UInt8(v) | Value::UInt8z(v) | Value::Byte(v) => Some(v.into()),
        Value::SInt16(v) => Some(v.into()),
        Value::UInt16(v) | Value::UInt16z(v) => Some(v.into()),
        Value::SInt32(v) => Some(v.into()),
        Value::UInt32(v) | Value::UInt32z(v) => Some(v.into()),
        Value::SInt64(v) => Some(v as f64),
        Value::UInt64(v) | Value::UInt64z(v) => Some(v as f64),
        Value::Float32(v) => Some(v.into()),
        Value::Float64(v) => Some(v),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hex(s: &str) -> Vec<u8> {
        (0..s.len())
            .step_by(2)
            .map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap())
            .collect()
    }

    #[test]
    fn a_crafted_file_that_overflowed_the_decoder_is_an_error_not_a_panic() {
        // 29 bytes found by fuzzing: fitparser's accumulated-field addition
        // overflowed ("attempt to add with overflow") in builds with overflow checks.
        let bytes = hex("0e102d080d0000002e464954554c40000014000112010200c800c8b534");
        assert_eq!(bytes.len(), 29);
        assert!(read_fit(&bytes).is_err());
    }

    const CRC_TABLE: [u16; 16] = [
        0x0000, 0xCC01, 0xD801, 0x1400, 0xF001, 0x3C00, 0x2800, 0xE401, 0xA001, 0x6C00, 0x7800,
        0xB401, 0x5000, 0x9C01, 0x8801, 0x4400,
    ];

    fn crc(bytes: &[u8]) -> u16 {
        bytes.iter().fold(0u16, |mut crc, &byte| {
            for nibble in [byte & 0xF, byte >> 4] {
                let tmp = CRC_TABLE[usize::from(crc & 0xF)];
                crc = ((crc >> 4) & 0x0FFF) ^ tmp ^ CRC_TABLE[usize::from(nibble)];
            }
            crc
        })
    }

    /// Wraps data messages into a FIT file: 14-byte header, data, CRC.
    fn fit_file(data: &[u8]) -> Vec<u8> {
        let mut file = vec![14u8, 0x10];
        file.extend(2093u16.to_le_bytes());
        file.extend((data.len() as u32).to_le_bytes());
        file.extend(b".FIT");
        file.extend(crc(&file).to_le_bytes());
        file.extend(data);
        file.extend(crc(&file).to_le_bytes());
        file
    }

    fn definition(local: u8, fields: &[(u8, u8, u8)]) -> Vec<u8> {
        let mut message = vec![0x40 | local, 0, 0];
        message.extend(20u16.to_le_bytes()); // global message 20 = record
        message.push(fields.len() as u8);
        for &(number, size, base_type) in fields {
            message.extend([number, size, base_type]);
        }
        message
    }

    const FIT_T0: u32 = 1_000_000_000; // 2021-09-08T01:46:40Z

    /// Local 0: full record with timestamp. Local 1: position + heart rate, sent with
    /// compressed-timestamp headers.
    fn sample_data() -> Vec<u8> {
        let mut data = definition(
            0,
            &[
                (253, 4, 0x86), // timestamp, uint32
                (0, 4, 0x85),   // position_lat, sint32 semicircles
                (1, 4, 0x85),   // position_long
                (5, 4, 0x86),   // distance, 1/100 m
                (3, 1, 0x02),   // heart_rate
                (4, 1, 0x02),   // cadence, strides/min
                (53, 1, 0x02),  // fractional_cadence, 1/128
                (6, 2, 0x84),   // speed, mm/s
            ],
        );
        let full = |t: u32, lat: i32, distance_cm: u32| {
            let mut m = vec![0x00];
            m.extend(t.to_le_bytes());
            m.extend(lat.to_le_bytes());
            m.extend((-(1i32 << 29)).to_le_bytes()); // -45°
            m.extend(distance_cm.to_le_bytes());
            m.extend([150, 85, 64]); // 150 bpm, 85.5 strides/min
            m.extend(3250u16.to_le_bytes());
            m
        };
        data.extend(full(FIT_T0, 1 << 29, 0)); // 45°
        data.extend(definition(1, &[(0, 4, 0x85), (1, 4, 0x85), (3, 1, 0x02)]));
        // Compressed timestamp: offset 2 s from the last full timestamp (FIT_T0 % 32 == 0).
        data.push(0x80 | (1 << 5) | 2);
        data.extend(0x7FFF_FFFFi32.to_le_bytes()); // invalid latitude
        data.extend(0x7FFF_FFFFi32.to_le_bytes());
        data.push(151);
        data.extend(full(FIT_T0 + 1, 1 << 28, 350)); // out of order in the file
        data.extend(full(FIT_T0 + 1, 0, 999)); // duplicate time
        data
    }

    #[test]
    fn decodes_records() {
        let records = read_fit(&fit_file(&sample_data())).unwrap();
        assert_eq!(records.len(), 3);
        let t0 = f64::from(FIT_T0) + FIT_EPOCH_UNIX_S as f64;
        assert_eq!(records[0].t_s, t0);
        assert_eq!(records[0].lat_deg, Some(45.0));
        assert_eq!(records[0].lon_deg, Some(-45.0));
        assert_eq!(records[0].device_distance_m, Some(0.0));
        assert_eq!(records[0].heart_rate_bpm, Some(150.0));
        assert_eq!(records[0].steps_per_min, Some(171.0), "2 × (85 + 64/128)");
        assert_eq!(records[0].device_speed_mps, Some(3.25));
        assert_eq!(records[0].horizontal_accuracy_m, None);
        assert_eq!(records[1].t_s, t0 + 1.0);
        assert_eq!(records[1].lat_deg, Some(22.5));
        assert_eq!(
            records[1].device_distance_m,
            Some(3.5),
            "first duplicate wins"
        );
        assert_eq!(records[2].t_s, t0 + 2.0, "compressed timestamp");
        assert_eq!((records[2].lat_deg, records[2].lon_deg), (None, None));
        assert_eq!(records[2].heart_rate_bpm, Some(151.0));
        assert_eq!(records[2].steps_per_min, None);
    }

    #[test]
    fn system_time_kept_relative() {
        let mut data = definition(0, &[(253, 4, 0x86), (3, 1, 0x02)]);
        data.extend([0x00]);
        data.extend(17_217_864u32.to_le_bytes());
        data.push(93);
        let records = read_fit(&fit_file(&data)).unwrap();
        assert_eq!(records[0].t_s, 17_217_864.0);
    }

    #[test]
    fn compressed_distance_accumulates_with_rollover() {
        let mut data = definition(0, &[(253, 4, 0x86), (8, 3, 0x0D)]);
        // (distance in 1/16 m, speed in 1/100 m/s), packed as 12 + 12 bits.
        for (i, (distance, speed)) in [(0u32, 354u32), (228, 355), (4000, 300), (100, 310)]
            .into_iter()
            .enumerate()
        {
            data.push(0x00);
            data.extend((FIT_T0 + 5 * i as u32).to_le_bytes());
            data.extend(&((distance << 12) | speed).to_le_bytes()[..3]);
        }
        let records = read_fit(&fit_file(&data)).unwrap();
        let distances: Vec<_> = records.iter().map(|r| r.device_distance_m).collect();
        assert_eq!(
            distances,
            [Some(0.0), Some(14.25), Some(250.0), Some(262.25)],
            "4000 then 100 rolls over to 4196"
        );
        assert_eq!(records[1].device_speed_mps, Some(3.55));
    }

    #[test]
    fn truncated_file_keeps_complete_records() {
        let file = fit_file(&sample_data());
        // Cut inside the last message (and drop the CRC): said in the clean-up.
        let (records, cleanup) = read_fit_counted(&file[..file.len() - 6]).unwrap();
        assert_eq!(records.len(), 3);
        assert_eq!(records[1].device_distance_m, Some(3.5));
        assert!(cleanup.truncated);
        // Cut after the last message, before the CRC: cut all the same.
        assert!(
            read_fit_counted(&file[..file.len() - 2])
                .unwrap()
                .1
                .truncated
        );
        assert!(!read_fit_counted(&file).unwrap().1.truncated);
    }

    #[test]
    fn malformed_inputs_are_typed_errors() {
        let is_parse_error = |bytes: &[u8]| {
            matches!(
                read_fit(bytes),
                Err(FormatError::Parse { format: "FIT", .. })
            )
        };
        assert!(is_parse_error(b""));
        assert!(is_parse_error(b"hello"));
        assert!(is_parse_error(
            b"<gpx></gpx> plus enough bytes for a header"
        ));
        let mut bad_crc = fit_file(&sample_data());
        let last = bad_crc.len() - 1;
        bad_crc[last] ^= 0xFF;
        assert!(is_parse_error(&bad_crc));
        // A data message for a local type that was never defined.
        assert!(is_parse_error(&fit_file(&[0x00, 1, 2, 3, 4])));
        // A header and nothing else: no records.
        assert!(matches!(read_fit(&fit_file(&[])), Err(FormatError::Empty)));
    }
}
