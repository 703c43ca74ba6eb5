//! `stridekit pace FILE`: replay a real activity file and print one CSV line per
//! GNSS epoch (and per pedometer-only update during outages). Samples the tracker
//! rejects (duplicate or reversed timestamps, NaN, out of range) are skipped and
//! counted by reason; the counts go to stderr with the summary, with what the file
//! reader cleaned up before (records merged, sorted, values dropped).

use std::io::Write as _;
use std::path::Path;

use stridekit_core::{PaceConfig, PaceSample, PaceTracker};

use stridekit_lab::activity::prepare;
use stridekit_lab::rejected::Rejected;

pub fn run(path: &Path, config: PaceConfig) -> Result<(), String> {
    let activity =
        stridekit_formats::read_activity(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let p = prepare(&activity);
    let mut tracker = PaceTracker::new(config).map_err(|e| e.to_string())?;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let w = |out: &mut dyn std::io::Write, s: String| {
        out.write_all(s.as_bytes()).map_err(|e| e.to_string())
    };
    w(&mut out, "t_s,t_unix_s,speed_mps,pace_s_per_km,pace_min_per_km,speed_std_mps,cadence_spm,step_length_m,gnss_weight,distance_m,source\n".into())?;
    let opt = |v: Option<f64>| v.map(|v| format!("{v:.3}")).unwrap_or_default();
    let mut rejected = Rejected::default();
    let mut last_t = f64::NEG_INFINITY;
    for s in &p.samples {
        if let Err(e) = tracker.push(s) {
            rejected.pace(&e);
            continue;
        }
        let Some(e) = tracker.estimate() else {
            continue;
        };
        let emit =
            matches!(s, PaceSample::Fix(_)) || (e.t_s > last_t + 0.5 && e.gnss_weight == 0.0);
        if emit && e.t_s > last_t {
            last_t = e.t_s;
            w(
                &mut out,
                format!(
                    "{:.3},{:.3},{:.3},{},{},{},{},{},{:.3},{:.2},{:?}\n",
                    e.t_s,
                    e.t_s + p.t0_unix_s,
                    e.speed_mps,
                    opt(e.pace_s_per_km),
                    e.pace_s_per_km.map(min_s).unwrap_or_default(),
                    opt(e.speed_std_mps),
                    opt(e.cadence_spm),
                    opt(e.step_length_m),
                    e.gnss_weight,
                    e.distance_m,
                    e.source
                ),
            )?;
        }
    }
    out.flush().map_err(|e| e.to_string())?;
    let distance_m = tracker.estimate().map_or(0.0, |e| e.distance_m);
    let moving_s = p.samples.last().map(|s| s.t_s()).unwrap_or(0.0)
        - p.samples.first().map(|s| s.t_s()).unwrap_or(0.0);
    let average = if distance_m > 0.0 {
        format!(
            ", average pace {} /km over the elapsed time",
            min_s(1000.0 * moving_s / distance_m)
        )
    } else {
        String::new()
    };
    eprintln!(
        "{}: {} samples, {} rejected, distance {:.0} m{average}, {} GNSS fixes, step data: {}",
        p.name,
        p.samples.len(),
        rejected.total(),
        distance_m,
        p.track.len(),
        if p.has_steps { "yes" } else { "no" }
    );
    eprint!("{}", rejected.report());
    for (why, n) in activity.cleanup.reasons() {
        eprintln!("  reader {n}: {why}");
    }
    Ok(())
}

/// Pace as a runner reads it: seconds per km as `m:ss` (330.7 → "5:31").
pub fn min_s(s_per_km: f64) -> String {
    if !s_per_km.is_finite() || s_per_km < 0.0 {
        return String::new();
    }
    let t = s_per_km.round() as u64;
    format!("{}:{:02}", t / 60, t % 60)
}

#[cfg(test)]
mod tests {
    #[test]
    fn pace_reads_as_minutes_and_seconds() {
        assert_eq!(super::min_s(330.676), "5:31");
        assert_eq!(super::min_s(59.6), "1:00");
        assert_eq!(super::min_s(f64::NAN), "");
    }
}
