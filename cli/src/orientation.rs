//! `stridekit orientation FILE [--out q.csv] [--imu-only]`: replays a recording with
//! IMU (and magnetometer) samples through the default orientation filter and writes
//! one CSV row per accepted sample: `t_s,qw,qx,qy,qz` (body → East-North-Up) and the
//! filter's flags (0/1). Samples the filter rejects are skipped and counted by
//! reason; one bad sample never aborts the replay. With optical truth in the file
//! (BROAD), the benchmark's errors are printed too.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

use stridekit_core::ahrs::{Ahrs, AhrsError, AhrsFlags, AhrsSettings};
use stridekit_formats::read_broad;

use stridekit_lab::orientation::metric::ErrorSums;

/// Options of `stridekit orientation`.
#[derive(Clone, Debug)]
pub struct OrientationArgs {
    pub file: PathBuf,
    pub out: PathBuf,
    /// Ignore the magnetometer (heading relative to the start).
    pub imu_only: bool,
}

/// A short name for why a sample was rejected (the replay's counters).
pub fn reason(e: &AhrsError) -> String {
    match e {
        AhrsError::Input(i) => crate::rejected::input_reason(i),
        other => other.to_string(),
    }
}

pub fn run(args: &OrientationArgs) -> Result<(), String> {
    let rec = read_broad(&args.file).map_err(|e| format!("{}: {e}", args.file.display()))?;
    let mut ahrs = Ahrs::new(AhrsSettings::default()).map_err(|e| e.to_string())?;
    let file =
        std::fs::File::create(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let mut w = std::io::BufWriter::new(file);
    let io = |e: std::io::Error| format!("{}: {e}", args.out.display());
    write!(w, "t_s,qw,qx,qy,qz").map_err(io)?;
    for name in AhrsFlags::NAMES {
        write!(w, ",{name}").map_err(io)?;
    }
    writeln!(w).map_err(io)?;
    let mut rejected: BTreeMap<String, usize> = BTreeMap::new();
    let mut sums = ErrorSums::default();
    let mut accepted = 0usize;
    for ((s, truth), &moving) in rec.samples.iter().zip(&rec.truth).zip(&rec.movement) {
        let mag = if args.imu_only { None } else { s.mag_ut };
        match ahrs.update(s.t_s, s.gyro_rads, s.accel_mps2, mag) {
            Ok(flags) => {
                accepted += 1;
                let q = ahrs.quaternion().unwrap_or([1.0, 0.0, 0.0, 0.0]);
                write!(
                    w,
                    "{:.6},{:.9},{:.9},{:.9},{:.9}",
                    s.t_s, q[0], q[1], q[2], q[3]
                )
                .map_err(io)?;
                for f in flags.to_array() {
                    write!(w, ",{}", f as u8).map_err(io)?;
                }
                writeln!(w).map_err(io)?;
                if let (true, Some(t)) = (moving, truth) {
                    sums.add(&q, t);
                }
            }
            Err(e) => *rejected.entry(reason(&e)).or_default() += 1,
        }
    }
    w.flush().map_err(io)?;
    println!(
        "{}: {} samples, {accepted} accepted, written to {}",
        display_name(&args.file),
        rec.len(),
        args.out.display()
    );
    for (why, n) in &rejected {
        println!("  skipped {n}: {why}");
    }
    if sums.n > 0 {
        let r = sums.rmse();
        if args.imu_only {
            println!(
                "against the optical truth (BROAD metric, {} scored samples): inclination RMSE {:.2}° \
                 (IMU only: the heading is relative to the start)",
                sums.n, r.inclination_deg
            );
        } else {
            println!(
                "against the optical truth (BROAD metric, {} scored samples): RMSE total {:.2}°, \
                 heading {:.2}°, inclination {:.2}°",
                sums.n, r.total_deg, r.heading_deg, r.inclination_deg
            );
        }
    }
    Ok(())
}

fn display_name(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}
