//! The demo report's charts: pace, speed, GNSS weight, step length, the track and the
//! next session's treadmill, each an SVG in the report folder, with the run's zones as
//! bands on the time charts.

use std::path::Path;

use stridekit_sim::ZoneKind;

use super::treadmill::Treadmill;
use super::{Demo, NAMES, PACE_MIN_MPS};
use crate::report::{line_chart, track_chart, Band, Chart, ReportError, Series, Style, YFormat};

/// The GNSS weight's axis: the weight is a share, 0..1.
const GNSS_WEIGHT_RANGE: (f64, f64) = (0.0, 1.0);

/// One series of (t, v) points.
fn series(name: &str, t: &[f64], v: &[f64], color: (u8, u8, u8), style: Style) -> Series {
    Series {
        name: name.to_string(),
        points: t.iter().zip(v).map(|(&a, &b)| (a, b)).collect(),
        color: Some(color),
        style,
    }
}

impl Demo {
    /// The report's charts: pace, speed, GNSS weight, step length, track, treadmill.
    pub(super) fn write_charts(&self, out_dir: &Path) -> Result<(), String> {
        let bands = self.bands();
        let t: Vec<f64> = self.r.t_s.iter().map(|&v| minutes(v)).collect();
        self.pace_chart(out_dir, &t, &bands)?;
        self.speed_chart(out_dir, &t, &bands)?;
        self.weight_chart(out_dir, &t, &bands)?;
        self.step_length_chart(out_dir, &t, &bands)?;
        self.track_chart(out_dir)?;
        if let Some(tm) = &self.treadmill {
            treadmill_chart(out_dir, tm, self.top_speed_mps())?;
        }
        Ok(())
    }

    /// The zones of the run as bands on the time charts.
    fn bands(&self) -> Vec<Band> {
        self.run
            .zones
            .iter()
            .map(|z| Band {
                start: minutes(z.start_s),
                end: minutes(z.end_s),
                label: match z.kind {
                    ZoneKind::Disturbance => "GNSS disturbed (urban canyon, trees)",
                    ZoneKind::Outage => "no GNSS (tunnel)",
                    ZoneKind::Stop => "runner stopped",
                }
                .to_string(),
                color: match z.kind {
                    ZoneKind::Disturbance => (255, 190, 60),
                    ZoneKind::Outage => (120, 120, 120),
                    ZoneKind::Stop => (60, 150, 255),
                },
            })
            .collect()
    }

    /// The fastest true speed, m/s (the speed axes reach 1.6 times it).
    fn top_speed_mps(&self) -> f64 {
        let mut top = 0.0f64;
        for v in self.truth.iter().filter(|v| v.is_finite()) {
            top = top.max(*v);
        }
        top
    }

    /// pace.svg: raw GNSS, truth and the default tracker, min/km.
    fn pace_chart(&self, out_dir: &Path, t: &[f64], bands: &[Band]) -> Result<(), String> {
        let Self { r, truth, .. } = self;
        let truth_pace = pace_min_per_km(truth);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &p in truth_pace.iter().filter(|p| p.is_finite()) {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        let pace_range = if lo < hi {
            ((lo - 0.75).max(0.0), hi + 1.5)
        } else {
            (3.0, 9.0)
        };
        let pace_series = [
            series(
                NAMES[0],
                t,
                &pace_min_per_km(&r.speed[0]),
                (190, 190, 190),
                Style::Points,
            ),
            series("truth", t, &truth_pace, (0, 0, 0), Style::Line),
            series(
                NAMES[3],
                t,
                &pace_min_per_km(&r.speed[3]),
                (220, 30, 60),
                Style::Line,
            ),
        ];
        written(
            "pace.svg",
            line_chart(
                &out_dir.join("pace.svg"),
                &Chart {
                    title: "Pace: what the runner sees",
                    x_label: "time (min)",
                    y_label: "pace (min/km, lower is faster)",
                    series: &pace_series,
                    bands,
                    y_range: Some(pace_range),
                    y_format: YFormat::MinSec,
                },
            ),
        )?;
        Ok(())
    }

    /// speed.svg: every method against the truth (GNSS-only ones where GNSS is).
    fn speed_chart(&self, out_dir: &Path, t: &[f64], bands: &[Band]) -> Result<(), String> {
        let Self { r, truth, .. } = self;
        let top = self.top_speed_mps();
        // The GNSS-only methods have no value without GNSS (the replay holds their last
        // one): not drawn there.
        let gnss_only = |m: usize| -> Vec<f64> {
            r.speed[m]
                .iter()
                .zip(&r.has_gnss)
                .map(|(&v, &g)| if g { v } else { f64::NAN })
                .collect()
        };
        let speed = [
            series("truth", t, truth, (0, 0, 0), Style::Line),
            series(NAMES[1], t, &gnss_only(1), (230, 140, 40), Style::Line),
            series(NAMES[2], t, &r.speed[2], (60, 120, 220), Style::Line),
            series(NAMES[3], t, &r.speed[3], (220, 30, 60), Style::Line),
        ];
        written(
            "speed.svg",
            line_chart(
                &out_dir.join("speed.svg"),
                &Chart {
                    title: "Speed by method (spikes above the axis are clipped)",
                    x_label: "time (min)",
                    y_label: "speed (m/s)",
                    series: &speed,
                    bands,
                    y_range: Some((0.0, (1.6 * top).max(1.0))),
                    y_format: YFormat::Number,
                },
            ),
        )?;
        Ok(())
    }

    /// gnss_weight.svg: how much the speed follows GNSS.
    fn weight_chart(&self, out_dir: &Path, t: &[f64], bands: &[Band]) -> Result<(), String> {
        let r = &self.r;
        let weight = [
            series(NAMES[2], t, &r.weight[0], (60, 120, 220), Style::Line),
            series(NAMES[3], t, &r.weight[1], (220, 30, 60), Style::Line),
        ];
        written(
            "gnss_weight.svg",
            line_chart(
                &out_dir.join("gnss_weight.svg"),
                &Chart {
                    title: "How much the speed follows GNSS (1 = GNSS only, 0 = steps only)",
                    x_label: "time (min)",
                    y_label: "GNSS weight",
                    series: &weight,
                    bands,
                    y_range: Some(GNSS_WEIGHT_RANGE),
                    y_format: YFormat::Number,
                },
            ),
        )?;
        Ok(())
    }

    /// step_length.svg: the learned step length against the true one.
    fn step_length_chart(&self, out_dir: &Path, t: &[f64], bands: &[Band]) -> Result<(), String> {
        let Self { run, r, .. } = self;
        // The true step length where the runner steps (none while standing).
        let truth_len: Vec<f64> = r
            .t_s
            .iter()
            .map(|&t| {
                let p = run.truth_at(t);
                if p.cadence_spm > 0.0 {
                    p.step_length_m
                } else {
                    f64::NAN
                }
            })
            .collect();
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &v in truth_len
            .iter()
            .chain(&r.step_length)
            .filter(|v| v.is_finite())
        {
            lo = lo.min(v);
            hi = hi.max(v);
        }
        let len_range = if lo < hi {
            let pad = 0.1 * (hi - lo);
            ((lo - pad).max(0.0), hi + 4.0 * pad)
        } else {
            (0.4, 1.8)
        };
        let steps = [
            series("truth", t, &truth_len, (0, 0, 0), Style::Line),
            series(
                &format!("{}, learned from GNSS", NAMES[3]),
                t,
                &r.step_length,
                (220, 30, 60),
                Style::Line,
            ),
        ];
        written(
            "step_length.svg",
            line_chart(
                &out_dir.join("step_length.svg"),
                &Chart {
                    title: "Step length",
                    x_label: "time (min)",
                    y_label: "step length (m)",
                    series: &steps,
                    bands,
                    y_range: Some(len_range),
                    y_format: YFormat::Number,
                },
            ),
        )?;
        Ok(())
    }

    /// track.svg: the fixes, the truth and the tracker's positions.
    fn track_chart(&self, out_dir: &Path) -> Result<(), String> {
        let Self { run, r, origin, .. } = self;
        let origin = *origin;
        let fixes = self.fixes.clone();
        let fused: Vec<(f64, f64)> = r
            .position_enu_m
            .iter()
            .map(|&(e, n)| (origin.0 + e, origin.1 + n))
            .collect();
        let track = [
            Series {
                name: "GNSS fixes".into(),
                points: fixes,
                color: Some((230, 160, 60)),
                style: Style::Points,
            },
            Series {
                name: "truth".into(),
                points: run.truth.iter().map(|p| (p.east_m, p.north_m)).collect(),
                color: Some((0, 0, 0)),
                style: Style::Line,
            },
            Series {
                name: NAMES[3].into(),
                points: fused,
                color: Some((220, 30, 60)),
                style: Style::Line,
            },
        ];
        written(
            "track.svg",
            track_chart(
                &out_dir.join("track.svg"),
                "Track (metres east / north of the start)",
                &track,
            ),
        )?;
        Ok(())
    }
}

/// treadmill.svg: the next session's steps alone, calibrated or with the prior.
fn treadmill_chart(out_dir: &Path, tm: &Treadmill, top: f64) -> Result<(), String> {
    let g: Vec<f64> = tm.t_s.iter().map(|&v| minutes(v)).collect();
    let lines = [
        series("truth", &g, &tm.truth, (0, 0, 0), Style::Line),
        series(
            "steps only, population prior",
            &g,
            &tm.prior,
            (150, 150, 150),
            Style::Line,
        ),
        series(
            "steps only, this run's calibration",
            &g,
            &tm.calibrated,
            (220, 30, 60),
            Style::Line,
        ),
    ];
    written(
        "treadmill.svg",
        line_chart(
            &out_dir.join("treadmill.svg"),
            &Chart {
                title: "Next session without GNSS: the same steps, calibrated or not",
                x_label: "time (min)",
                y_label: "speed (m/s)",
                series: &lines,
                bands: &[],
                y_range: Some((0.0, (1.6 * top).max(1.0))),
                y_format: YFormat::Number,
            },
        ),
    )
}

/// Time in minutes, as a runner reads a run.
fn minutes(t_s: f64) -> f64 {
    t_s / 60.0
}

/// Pace in min/km; slower than [`PACE_MIN_MPS`] (standing, shuffling) is a gap.
fn pace_min_per_km(v: &[f64]) -> Vec<f64> {
    v.iter()
        .map(|&s| {
            if s >= PACE_MIN_MPS {
                1000.0 / s / 60.0
            } else {
                f64::NAN
            }
        })
        .collect()
}

/// A chart's writing error, naming the chart.
fn written(name: &str, res: Result<(), ReportError>) -> Result<(), String> {
    res.map_err(|e| format!("cannot write {name}: {e}"))
}
