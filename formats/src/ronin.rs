//! Reader for RoNIN (Herath, Yan, Furukawa 2020) recordings as a CSV export.
//!
//! The original files are HDF5 (`data.hdf5`: `synced/time`, `synced/gyro`,
//! `synced/acce`, `synced/magnet`, `pose/tango_pos`, ...). An HDF5 reader needs the C
//! library (the `hdf5` crate) — too heavy for this crate — so this reads a CSV
//! export of the same fields, one row per synced sample:
//!
//! ```text
//! time_s,gyro_x,gyro_y,gyro_z,acce_x,acce_y,acce_z[,magnet_x,magnet_y,magnet_z],pos_x,pos_y,pos_z
//! ```
//!
//! (`time_s` seconds, rad/s, m/s² with gravity, µT, Tango position m). E.g. with
//! h5py: `np.column_stack([f['synced/time'], f['synced/gyro'], f['synced/acce'],
//! f['synced/magnet'], f['pose/tango_pos']])` written with that header. Optional
//! column `placement` is not read; the placement is unknown (`None`).

use crate::error::FormatError;
use crate::inertial::InertialRecording;

const FORMAT: &str = "RoNIN CSV export";

/// Parse the text of a RoNIN CSV export.
pub fn parse_ronin_csv(name: &str, text: &str) -> Result<InertialRecording, FormatError> {
    crate::ridi::parse_layout(FORMAT, name, None, text, "time_s", 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_small_export() {
        let text = "time_s,gyro_x,gyro_y,gyro_z,acce_x,acce_y,acce_z,magnet_x,magnet_y,magnet_z,pos_x,pos_y,pos_z\n\
                    0.0,0,0,0,0,0,9.8,10,20,-40,0,0,0\n\
                    0.005,0,0,0,0,0,9.8,10,20,-40,0.01,0,0\n";
        let r = parse_ronin_csv("a000_1", text).unwrap();
        assert_eq!(r.samples.len(), 2);
        assert_eq!(r.samples[0].mag_ut, Some([10.0, 20.0, -40.0]));
        assert_eq!(r.truth[1], (0.005, 0.01, 0.0));
        assert!(parse_ronin_csv("x", "time_s\n").is_err());
        // A truncated last row is skipped and counted; a file of only bad rows is an error.
        let cut = format!("{text}0.010,0,0,0,0,0,9.8,10,20");
        let r = parse_ronin_csv("a000_1", &cut).unwrap();
        assert_eq!(r.samples.len(), 2);
        assert_eq!(
            r.skipped,
            vec![("unreadable row (first at line 4)".to_string(), 1)]
        );
        let header = text.lines().next().unwrap();
        assert!(parse_ronin_csv("x", &format!("{header}\n0.0,0,0\n")).is_err());
    }
}
