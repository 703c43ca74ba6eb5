//! Real indoor walks with waypoints (Android sensor logs, `phone-indoor/`): loading,
//! and replaying one through `PhoneNavigator` into a track. Shared by `stridekit pdr`,
//! `stridekit calibrate pdr` and `stridekit eval pdr`.

use std::path::Path;

use stridekit_core::ahrs::ImuSample;
use stridekit_core::pdr::{NavigatorConfig, PdrCalibration, PhoneNavigator};
use stridekit_formats::{list_android_logs, read_inertial, InertialRecording};

use crate::pdr::metrics::TrackPoint;

/// One walk: its recording and the group it belongs to for cross-validation (the
/// floor: the header's `FloorName`, else the parent folder's name).
pub struct Walk {
    pub floor: String,
    pub rec: InertialRecording,
}

/// The floor of a recording at `path`.
fn floor_of(path: &Path, rec: &InertialRecording) -> String {
    rec.meta_value("FloorName")
        .map(str::to_string)
        .or_else(|| {
            path.parent()
                .and_then(|p| p.file_name())
                .map(|s| s.to_string_lossy().into_owned())
        })
        .unwrap_or_else(|| "?".into())
}

/// Every Android sensor log with at least two waypoints under `dir`, sorted by path;
/// `progress` is told (done, total) as files are read.
pub fn load_walks(dir: &Path, mut progress: impl FnMut(usize, usize)) -> Result<Vec<Walk>, String> {
    let paths = list_android_logs(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    if paths.is_empty() {
        return Err(format!(
            "no Android sensor logs (*.txt, *.txt.gz) under {}",
            dir.display()
        ));
    }
    let mut out = Vec::with_capacity(paths.len());
    for (i, path) in paths.iter().enumerate() {
        let rec = read_inertial(path).map_err(|e| format!("{}: {e}", path.display()))?;
        progress(i + 1, paths.len());
        if rec.truth.len() < 2 {
            continue;
        }
        out.push(Walk {
            floor: floor_of(path, &rec),
            rec,
        });
    }
    Ok(out)
}

/// Read one walk.
pub fn load_walk(path: &Path) -> Result<Walk, String> {
    let rec = read_inertial(path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(Walk {
        floor: floor_of(path, &rec),
        rec,
    })
}

/// One placed step (a row of `stridekit pdr`'s CSV).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepRow {
    pub t_s: f64,
    pub east_m: f64,
    pub north_m: f64,
    pub length_m: f64,
    pub azimuth_rad: f64,
    /// Σ step lengths so far, m.
    pub distance_m: f64,
}

/// How a replay went.
pub struct Replay {
    /// The trajectory: where each step ended at the step's own time, from the origin
    /// at the first sample, held (not interpolated) through pauses between steps.
    pub track: Vec<TrackPoint>,
    /// The live estimate after every accepted sample (lags the steps by the
    /// detector's latency).
    pub live: Vec<TrackPoint>,
    pub steps: Vec<StepRow>,
    /// Rejected samples by reason.
    pub rejected: crate::rejected::Rejected,
}

/// How a walk is replayed.
#[derive(Clone, Debug)]
pub struct ReplayOptions {
    pub config: NavigatorConfig,
    pub calibration: Option<PdrCalibration>,
    /// Push the magnetometer.
    pub mag: bool,
    /// Android's rotation vector as the orientation instead of the internal AHRS (a
    /// comparison; samples without a rotation vector within 0.1 s are skipped).
    pub rotation_vector: bool,
}

impl Default for ReplayOptions {
    fn default() -> Self {
        Self {
            config: NavigatorConfig::default(),
            calibration: None,
            mag: true,
            rotation_vector: false,
        }
    }
}

/// A step longer than this since the previous one holds the track still until
/// shortly before it (a pause), s.
const HOLD_AFTER_S: f64 = 1.2;
const STEP_SPAN_S: f64 = 0.55;

/// Replay the IMU samples of `rec` through a navigator; rejected samples are
/// skipped and counted by reason.
pub fn replay(rec: &InertialRecording, o: &ReplayOptions) -> Result<Replay, String> {
    let mut nav = PhoneNavigator::new(o.config).map_err(|e| e.to_string())?;
    if let Some(c) = &o.calibration {
        nav.set_calibration(c).map_err(|e| e.to_string())?;
    }
    let mut ri = 0;
    let mut live = Vec::with_capacity(rec.samples.len());
    let mut track = Vec::new();
    let mut steps: Vec<StepRow> = Vec::new();
    if let Some(s) = rec.samples.first() {
        track.push(TrackPoint {
            t_s: s.t_s,
            ..Default::default()
        });
    }
    let mut placed = 0u64;
    let mut rejected = crate::rejected::Rejected::default();
    for s in &rec.samples {
        let imu = ImuSample {
            t_s: s.t_s,
            gyro_rads: s.gyro_rads,
            accel_mps2: s.accel_mps2,
            mag_ut: if o.mag { s.mag_ut } else { None },
        };
        let pushed = if o.rotation_vector {
            let rv = &rec.orientation;
            while ri + 1 < rv.len() && rv[ri + 1].0 <= s.t_s {
                ri += 1;
            }
            match rv.get(ri) {
                Some((t, q)) if (s.t_s - t).abs() <= 0.1 => nav.push_imu_with_attitude(&imu, *q),
                _ => {
                    rejected.add("no rotation vector".to_string());
                    continue;
                }
            }
        } else {
            nav.push_imu(&imu)
        };
        if let Err(e) = pushed {
            rejected.nav(&e);
            continue;
        }
        let Some(e) = nav.estimate() else { continue };
        live.push(TrackPoint {
            t_s: s.t_s,
            x_m: e.east_m,
            y_m: e.north_m,
            distance_m: e.distance_m,
        });
        for st in nav.steps_since(placed) {
            let last = track[track.len() - 1];
            if st.t_s - last.t_s > HOLD_AFTER_S {
                track.push(TrackPoint {
                    t_s: st.t_s - STEP_SPAN_S,
                    ..last
                });
            }
            let d = last.distance_m + st.length_m;
            track.push(TrackPoint {
                t_s: st.t_s,
                x_m: st.east_m,
                y_m: st.north_m,
                distance_m: d,
            });
            steps.push(StepRow {
                t_s: st.t_s,
                east_m: st.east_m,
                north_m: st.north_m,
                length_m: st.length_m,
                azimuth_rad: st.azimuth_rad,
                distance_m: d,
            });
        }
        placed = nav.recent_steps().1;
    }
    Ok(Replay {
        track,
        live,
        steps,
        rejected,
    })
}
