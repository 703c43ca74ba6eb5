//! Real activity records → pace samples (clean, or with injected GNSS degradation).

use crate::pace::{degrade_track, TrackPoint};
use stridekit_core::geo::LocalFrame;
use stridekit_core::input;
use stridekit_core::{GnssFix, PaceSample, StepSample};
use stridekit_formats::{Activity, Record};
use stridekit_sim::Zone;

/// An activity prepared for replay: time relative to its first record.
pub struct Prepared {
    pub name: String,
    /// Seconds of the first record since the UNIX epoch.
    pub t0_unix_s: f64,
    pub samples: Vec<PaceSample>,
    /// The clean GNSS track in the local frame of the first fix.
    pub track: Vec<TrackPoint>,
    pub frame: Option<LocalFrame>,
    pub has_steps: bool,
}

fn fix_of(r: &Record, t: f64, lat: f64, lon: f64) -> GnssFix {
    GnssFix {
        t_s: t,
        lat_deg: lat,
        lon_deg: lon,
        alt_m: r.alt_m,
        horizontal_accuracy_m: r.horizontal_accuracy_m,
        // Device speeds in activity files are the watch's own fused output (often
        // from a foot pod): not fed, so the evaluation measures our fusion only.
        speed_mps: None,
        speed_accuracy_mps: None,
    }
}

fn step_of(r: &Record, t: f64) -> Option<StepSample> {
    if let Some(c) = r.step_count {
        return Some(StepSample::Count {
            t_s: t,
            steps: c.max(0.0) as u64,
        });
    }
    r.steps_per_min.map(|c| StepSample::Cadence {
        t_s: t,
        steps_per_min: c.clamp(0.0, 300.0),
    })
}

/// Samples of an activity: one step sample (count or cadence) and one fix per record
/// where present, steps first. Times are made relative to the first record, unless
/// they are not seconds at all (Unix time in milliseconds or nanoseconds, by the input
/// layer's magnitude rule): then they go to the engine as they are, and its input
/// checks refuse every sample from the first, naming the unit (the relative times of
/// such a file would hide it until the third interval).
pub fn prepare(activity: &Activity) -> Prepared {
    let t0 = activity
        .records
        .first()
        .map(|r| r.t_s)
        .filter(|&t| input::time_increasing(input::Stream::Gnss, t, None).is_ok())
        .unwrap_or(0.0);
    let mut samples = Vec::with_capacity(2 * activity.records.len());
    let mut track = Vec::new();
    let mut frame: Option<LocalFrame> = None;
    let mut has_steps = false;
    for r in &activity.records {
        let t = r.t_s - t0;
        if let Some(s) = step_of(r, t) {
            has_steps = true;
            samples.push(PaceSample::Steps(s));
        }
        if let (Some(lat), Some(lon)) = (r.lat_deg, r.lon_deg) {
            let f = *frame.get_or_insert_with(|| LocalFrame::new(lat, lon, 0.0));
            let p = f.to_enu(lat, lon, 0.0);
            track.push((t, p[0], p[1]));
            samples.push(PaceSample::Fix(fix_of(r, t, lat, lon)));
        }
    }
    Prepared {
        name: activity.name.clone(),
        t0_unix_s: t0,
        samples,
        track,
        frame,
        has_steps,
    }
}

/// The same samples with GNSS disturbances and outages injected on the track.
pub fn degraded(p: &Prepared, seed: u64) -> (Vec<PaceSample>, Vec<Zone>) {
    let Some(frame) = p.frame else {
        return (p.samples.clone(), Vec::new());
    };
    let (offsets, zones) = degrade_track(&p.track, seed);
    let mut out = Vec::with_capacity(p.samples.len());
    let mut k = 0;
    for s in &p.samples {
        match s {
            PaceSample::Fix(f) => {
                let (t, e, n) = p.track[k];
                if let Some((de, dn)) = offsets[k] {
                    let (lat, lon) = frame.to_geodetic(e + de, n + dn);
                    let mut g = *f;
                    g.t_s = t;
                    g.lat_deg = lat;
                    g.lon_deg = lon;
                    out.push(PaceSample::Fix(g));
                }
                k += 1;
            }
            other => out.push(*other),
        }
    }
    (out, zones)
}
