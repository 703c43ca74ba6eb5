//! `stridekit foot FILE.csv`: replay a foot-mounted IMU recording through the foot
//! navigator and write the trajectory as CSV plus SVG plots next to it.
//!
//! Input: a pyshoe / UofT CSV or an x-io (NGIMU) CSV export (see
//! `stridekit_formats::foot`). The sensor axes come from `--axes` (see
//! [`FootConfig::axes_from_spec`]); without it, the layout's usual axes (pyshoe:
//! `frd`; x-io: `flu`, the body frame itself). The IMU profile (`--imu`) does not
//! follow the layout, which any IMU's export can have: trials of the UofT VICON set
//! (known by the set's label columns) were recorded with a factory-calibrated
//! MicroStrain (`calibrated`), anything else is taken as consumer MEMS (`consumer`,
//! the SDK default: gyro bias measured at the start rest). The gyroscope range
//! (`--gyro-range`) comes from the data when not given: the ceiling of a clipped
//! gyroscope ([`stridekit_core::foot::GyroCeilingDetector`]), else none. The replay
//! prints every device assumption it made ([`config_for`]).
//!
//! Samples the navigator rejects (repeated or reversed timestamps, NaN, values out
//! of range, accelerations in g) are skipped and counted by reason, and the counts
//! are printed (the navigator rejects a sample whose time equals the previous one:
//! common in logs of a fast sensor on a coarse clock).
//!
//! When the file has truth columns (`gt_x_m gt_y_m gt_z_m`, e.g. the pyshoe VICON
//! trials), the truth is mirrored as `eval foot` does (see `stridekit_lab::foot::eval::mirror_truth`)
//! and then carried into the estimate's ENU frame by the best rotation about the
//! vertical + translation, so that the `gt_*` columns and the plots compare directly.
//!
//! Outputs for `--out DIR/NAME.csv`: `DIR/NAME.csv` (one row per estimate),
//! `DIR/NAME.svg` (top view: estimate, truth, stride ends) and `DIR/NAME_height.svg`
//! (height over time); `--out -`: the CSV on stdout, no plots. The CSV is in the
//! navigator's frame, a local level East-North-Up frame from where the walk started
//! (east = where the foot's x axis pointed at the start, as no heading reference is
//! given): `t_s,east_m,north_m,up_m,v_east_mps,v_north_mps,v_up_mps,yaw_rad,stance,
//! strides,distance_m,gt_east_m,gt_north_m,gt_up_m`, positions to 0.1 mm.
//!
//! A replay with no stride, or whose samples were refused for their units (in g,
//! timestamps not in seconds), exits 1.

use std::io::Write;
use std::path::{Path, PathBuf};

use stridekit_core::foot::{FootConfig, FootEstimate};
use stridekit_formats::{read_foot_csv, Content, FootFormat};

use stridekit_lab::foot::device::{evidence, Evidence};
use stridekit_lab::foot::eval::{align, replay_counted, Method, Trial};
use stridekit_lab::report::{line_chart, track_chart, Chart, Series, Style};

use crate::commands::foot::{FootArgs, Imu};
use crate::outcome::{write_error, Failure};
use crate::output::{say, Sink};

/// What `stridekit foot` reads, for messages.
const EXPECTS: &str = "a foot IMU CSV (pyshoe / UofT or x-io NGIMU layout)";

/// `calibrate foot`: walks fitted alone that disagree by more than this, degrees,
/// get a warning (x-io's two NGIMU walks: 0.3°; the UofT MicroStrain's sessions: 1.1°).
const DISAGREE_DEG: f64 = 0.5;

/// Plots keep at most about this many points per series (the CSV keeps all).
const PLOT_POINTS: usize = 4000;

/// Below this distance walked, m, the loop closure is given without a percentage.
const MIN_WALKED_M: f64 = 0.01;

/// What `--imu` names: [`FootConfig::default`] for consumer MEMS (gyro bias from the
/// start rest), [`FootConfig::calibrated_imu`] for a factory-calibrated IMU (the UofT
/// MicroStrain).
impl Imu {
    fn name(self) -> &'static str {
        match self {
            Self::Consumer => "consumer",
            Self::Calibrated => "calibrated",
        }
    }
    fn config(self) -> FootConfig {
        match self {
            Self::Consumer => FootConfig::default(),
            Self::Calibrated => FootConfig::calibrated_imu(),
        }
    }
}

/// The navigator configuration for a recording of `format` under `args`, given what
/// the data say about the device, and the device assumptions made, for the output.
///
/// Nothing about the device is taken from the file's layout alone, which any IMU's
/// export can have:
/// - axes: `--axes`, else the layout's usual axes (pyshoe: `frd`, x-io: `flu`);
/// - units: the ones the header names (the navigator refuses g and deg/s in SI columns);
/// - IMU profile: `--imu`, else `calibrated` only for a trial of the UofT VICON set (its
///   factory-calibrated MicroStrain, known by the set's label columns), `consumer` (the
///   SDK default, gyro bias measured at the start rest) for everything else;
/// - gyroscope range: `--gyro-range`, else the ceiling the data show (flat tops at a
///   constant rate, [`stridekit_core::foot::GyroCeilingDetector`]); without that
///   evidence, no range and nothing "repaired".
pub fn config_for(
    args: &FootArgs,
    format: FootFormat,
    device: &Evidence,
) -> Result<(FootConfig, String), String> {
    let default_axes = match format {
        FootFormat::Pyshoe => "frd",
        FootFormat::Xio => "flu",
    };
    let spec = args.axes.as_deref().unwrap_or(default_axes);
    let axis_remap = FootConfig::axes_from_spec(spec).map_err(|e| format!("--axes {spec}: {e}"))?;
    let (imu, imu_why) = match args.imu {
        Some(imu) => (imu, "given"),
        None if device.uoft_vicon_set => (
            Imu::Calibrated,
            "the UofT VICON set's factory-calibrated MicroStrain: the file has the set's label columns",
        ),
        None => (
            Imu::Consumer,
            "the SDK default for an IMU not known by name; --imu calibrated for a factory-calibrated one",
        ),
    };
    let units = match format {
        FootFormat::Pyshoe => "m/s² and rad/s, as the header names them",
        FootFormat::Xio => "g and deg/s in the file, converted to m/s² and rad/s",
    };
    let mut text = format!(
        "{}; device assumptions:\n  axes {spec} ({}); units {units}\n  IMU profile {} ({imu_why})",
        format.name(),
        if args.axes.is_some() {
            "given"
        } else {
            "default for this layout"
        },
        imu.name(),
    );
    let mut config = FootConfig {
        axis_remap,
        ..imu.config()
    };
    let (range, gyro_text) = gyro_range(args.gyro_range_rads, device);
    config.gyro_range_rads = range;
    text += &format!("\n  gyroscope: {gyro_text}");
    if args.no_level_floor {
        config.level_stride_max_grade = None;
        text += "\n  level-floor constraint off";
    }
    if let Some(path) = &args.calibration {
        let a = read_calibration(path)?;
        config.accel_alignment_rad = a;
        text += &format!(
            "\n  accelerometer alignment ({:.2}°, {:.2}°, {:.2}°) from {}",
            a[0].to_degrees(),
            a[1].to_degrees(),
            a[2].to_degrees(),
            path.display()
        );
    }
    Ok((config, text))
}

/// The gyroscope range to configure and what it rests on: the range given, else the
/// ceiling the data show, else none (nothing is repaired without evidence). A given
/// range the data contradict gets a warning in the text.
fn gyro_range(given: Option<f64>, device: &Evidence) -> (Option<f64>, String) {
    let seen = |c: &stridekit_core::foot::GyroCeiling| {
        format!(
            "{} flat tops at a constant ceiling of {:.2} rad/s on sensor {} (peak {:.2} rad/s)",
            c.flat_tops,
            c.ceiling_rads,
            stridekit_lab::foot::device::side_name(c),
            c.peak_rads
        )
    };
    match (given, device.ceiling) {
        (Some(r), found) => {
            let mut t = format!("range {r} rad/s (given; clipped swing peaks repaired)");
            if let Some(c) = found.filter(|c| c.range_rads() < 0.995 * r) {
                t += &format!(
                    "; warning: the data show {} — below 99 % of the given range: is --gyro-range right?",
                    seen(&c)
                );
            }
            if device.peak_rads > r {
                t += &format!(
                    "; warning: the data reach {:.2} rad/s, above the given range",
                    device.peak_rads
                );
            }
            (Some(r), t)
        }
        (None, Some(c)) => (
            Some(c.range_rads()),
            format!(
                "clipping detected: {}; clipped swing peaks repaired above {:.2} rad/s (--gyro-range RAD_S to set the device's range instead)",
                seen(&c),
                c.ceiling_rads
            ),
        ),
        (None, None) => (
            None,
            format!(
                "no clipping detected (peak {:.2} rad/s, no flat tops at a constant ceiling): nothing repaired (--gyro-range RAD_S if the device's range is known)",
                device.peak_rads
            ),
        ),
    }
}

/// The alignment of a foot calibration file (`stridekit calibrate foot`).
pub fn read_calibration(path: &Path) -> Result<[f64; 3], String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    stridekit_lab::foot::alignment::parse(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// `stridekit calibrate foot`: learn the accelerometer alignment from level walks,
/// write the calibration file, and return the report.
pub fn calibrate(
    files: &[PathBuf],
    out: &Path,
    axes: Option<String>,
    imu: Option<Imu>,
) -> Result<String, String> {
    let mut walks = Vec::new();
    let mut config: Option<FootConfig> = None;
    let mut report = String::new();
    let recs = files
        .iter()
        .map(|file| read_foot_csv(file).map_err(|e| format!("{}: {e}", file.display())))
        .collect::<Result<Vec<_>, _>>()?;
    // One device: its evidence from all the walks.
    let device = evidence(&recs.iter().collect::<Vec<_>>());
    for (file, rec) in files.iter().zip(recs) {
        let args = FootArgs {
            axes: axes.clone(),
            imu,
            ..Default::default()
        };
        let (c, described) = config_for(&args, rec.format, &device)?;
        if config.as_ref().is_some_and(|k| *k != c) {
            return Err(format!(
                "{}: another layout than the first file (give --axes and --imu)",
                file.display()
            ));
        }
        report += &format!("{}: {described}\n", file.display());
        let samples: Vec<_> = (0..rec.len())
            .map(|i| stridekit_lab::foot::eval::foot_sample(&rec, i))
            .collect();
        walks.push((rec.name.clone(), samples));
        config = Some(c);
    }
    let config = config.ok_or("no walk given")?;
    let fit = stridekit_lab::foot::alignment::learn(&config, &walks)?;
    let a = fit.alignment_rad;
    report += &format!(
        "accelerometer alignment (rotation vector, body axes x forward, y left, z up; \
         the angle about y fitted): ({:.3}°, {:.3}°, {:.3}°), {} iterations\n",
        a[0].to_degrees(),
        a[1].to_degrees(),
        a[2].to_degrees(),
        fit.iterations
    );
    report += "| walk | stance-to-stance steps | distance | RMS height change per step, before → after | height end − start | 3-D end − start |\n|---|---|---|---|---|---|\n";
    for w in &fit.walks {
        let pct = |x: f64| 100.0 * x / w.distance_m.max(1e-9);
        report += &format!(
            "| {} | {} | {:.2} m | {:.1} → {:.1} mm | {:+.3} → {:+.3} m | {:.2} → {:.2} % |\n",
            w.name,
            w.steps,
            w.distance_m,
            1e3 * w.rms_before_m,
            1e3 * w.rms_after_m,
            w.height_before_m,
            w.height_after_m,
            pct(w.closure_before_m),
            pct(w.closure_after_m),
        );
    }
    if walks.len() > 1 {
        // Each walk alone: a device constant agrees between walks; when the angles
        // scatter, the height error is not (only) this alignment.
        let mut alone = Vec::new();
        for w in &walks {
            let f = stridekit_lab::foot::alignment::learn(&config, std::slice::from_ref(w))?;
            report += &format!("  {} alone: {:.3}°\n", w.0, f.alignment_rad[1].to_degrees());
            alone.push(f.alignment_rad[1]);
        }
        let (lo, hi) = alone
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        if (hi - lo).to_degrees() > DISAGREE_DEG {
            report += &format!(
                "warning: the walks alone disagree by {:.2}° (over {DISAGREE_DEG}°): their \
                 height errors are not (only) a constant alignment of this IMU; check the \
                 calibration on another level walk before using it\n",
                (hi - lo).to_degrees()
            );
        }
    }
    let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    let text = stridekit_lab::foot::alignment::to_text(
        a,
        &format!(
            "accelerometer-to-gyroscope alignment learned by `stridekit calibrate foot` from the level walks:\n{}\naxes and IMU profile: as described when replaying with --calibration",
            names.join("\n")
        ),
    );
    std::fs::write(out, text).map_err(|e| format!("{}: {e}", out.display()))?;
    let svg = out.with_extension("svg");
    plot_stances(&svg, &fit)?;
    report += &format!("stance heights before and after: {}\n", svg.display());
    Ok(report)
}

/// Every stance's height over time, per walk, with the starting alignment (dots) and
/// the fitted one (line): a level walk's stances should lie on zero.
fn plot_stances(path: &Path, fit: &stridekit_lab::foot::alignment::LevelFit) -> Result<(), String> {
    let mut series = Vec::new();
    for (i, w) in fit.walks.iter().enumerate() {
        let c = stridekit_lab::report::PALETTE[i % stridekit_lab::report::PALETTE.len()];
        series.push(Series {
            name: format!("{} before", w.name),
            points: w.stances_before.clone(),
            color: Some(c),
            style: Style::Points,
        });
        series.push(Series {
            name: format!("{} calibrated", w.name),
            points: w.stances_after.clone(),
            color: Some(c),
            style: Style::Line,
        });
    }
    line_chart(
        path,
        &Chart {
            title: "stance heights above the first stance (a level walk: 0)",
            x_label: "time since the walk's start (s)",
            y_label: "height (m)",
            series: &series,
            bands: &[],
            y_range: None,
            y_format: stridekit_lab::report::YFormat::Number,
        },
    )
    .map_err(|e| format!("{}: {e}", path.display()))
}

pub fn run(args: &FootArgs, sink: &Sink) -> Result<(), Failure> {
    let file = &args.file;
    let what = |e| crate::input::read_error(file, e, EXPECTS);
    match stridekit_formats::sniff(file).map_err(what)?.content {
        Content::Foot(_) | Content::Broad | Content::Unknown => {}
        other => return Err(crate::input::other_content(file, other, EXPECTS).into()),
    }
    let mut rec = read_foot_csv(file).map_err(what)?;
    if rec.truncated {
        crate::input::warn_truncated(file);
    }
    // (--axes is checked by clap: what can fail here is the calibration file.)
    let (config, described) =
        config_for(args, rec.format, &evidence(&[&rec])).map_err(|e| match args.calibration {
            Some(_) => crate::outcome::usage("--calibration", e),
            None => Failure::Failed(e),
        })?;
    if let Some(t) = rec.truth_m.as_mut() {
        stridekit_lab::foot::eval::mirror_truth(t);
    }
    if let Some(l) = args
        .label_column()
        .filter(|l| !["best", "runner-up"].contains(l))
    {
        if rec.label(l).is_none() {
            let have: Vec<String> = rec.labels.iter().map(|(n, _)| format!("zv_{n}")).collect();
            return Err(crate::outcome::usage(
                "--labels",
                format!(
                    "{}: no label column zv_{l} (the file has: {})",
                    file.display(),
                    if have.is_empty() {
                        "none".to_string()
                    } else {
                        have.join(", ")
                    }
                ),
            ));
        }
    }
    let unreadable = (rec.unreadable_rows, rec.first_unreadable_line);
    let trial = Trial {
        best: "shoe_opt".into(),
        runner_up: None,
        pyshoe_best_m: None,
        run: false,
        path_m: 0.0,
        rec,
    };
    let m = Method {
        name: "replay".into(),
        config,
        labels: args.label_column().map(str::to_string),
    };
    let replayed = replay_counted(&trial, &m)?;
    let est = &replayed.estimates;
    // With the level floor on, the filter's own height too (for the report and the
    // height plot): the same replay with it off.
    let unlevelled = match m.config.level_stride_max_grade {
        Some(_) => Some(
            replay_counted(
                &trial,
                &Method {
                    config: FootConfig {
                        level_stride_max_grade: None,
                        ..m.config.clone()
                    },
                    ..m.clone()
                },
            )?
            .estimates,
        ),
        None => None,
    };
    say!("{}: {}", trial.rec.name, described);
    say!(
        "  {} rows, {} samples skipped: {}",
        trial.rec.len() + unreadable.0,
        replayed.skipped.total() + unreadable.0,
        {
            let mut d = replayed.skipped.describe();
            if unreadable.0 > 0 {
                let u = format!(
                    "{} unreadable rows (first at line {})",
                    unreadable.0,
                    unreadable.1.unwrap_or(0)
                );
                d = if d == "none" { u } else { format!("{d}, {u}") };
            }
            d
        }
    );
    if let Some((i, e)) = &replayed.skipped.first {
        say!("  first skipped: row {} ({e})", i + 2);
    }
    if est.is_empty() {
        return Err(format!(
            "{}: no estimate: the navigator never aligned (it needs {} s of rest at the start, in m/s² and rad/s)",
            trial.rec.name, m.config.alignment_s
        )
        .into());
    }
    // Truth per estimate, in the estimate's frame.
    let truth: Option<Vec<[f64; 3]>> = trial.rec.truth_m.as_ref().map(|t| {
        let g: Vec<[f64; 3]> = est.iter().map(|(k, _)| t[*k]).collect();
        let e: Vec<[f64; 3]> = est.iter().map(|(_, e)| e.position_m).collect();
        let (th, tr) = align(&e, &g);
        g.iter().map(|p| into_estimate_frame(th, tr, *p)).collect()
    });

    write_csv(sink, est, truth.as_deref())?;
    let plots = sink.path().map(svg_paths);
    if let Some((top, height)) = &plots {
        plot(
            top,
            height,
            &trial.rec.name,
            est,
            unlevelled.as_deref(),
            truth.as_deref(),
        )?;
    }

    let first = est[0].1;
    let last = est[est.len() - 1].1;
    say!(
        "  {} estimates at {:.1} Hz (detector window {} samples), {} strides, {:.2} m walked, {:.1} s",
        est.len(),
        replayed.rate_hz,
        replayed.window,
        last.strides,
        last.distance_m,
        last.t_s - first.t_s,
    );
    if let Some(raw) = &unlevelled {
        let strides: Vec<_> = est.iter().filter_map(|(_, e)| e.stride).collect();
        let levelled: Vec<f64> = strides
            .iter()
            .filter(|s| s.levelled_m != 0.0)
            .map(|s| s.levelled_m)
            .collect();
        let own_end = match (raw.first(), raw.last()) {
            (Some(a), Some(b)) => b.1.position_m[2] - a.1.position_m[2],
            _ => 0.0,
        };
        say!(
            "  level floor: {} of {} strides taken as level, their height change set to zero ({:+.3} m in all, median {:+.3} m per levelled stride); the other strides climbed {:+.3} m; the filter's own height ends at {:+.3} m (--no-level-floor)",
            levelled.len(),
            strides.len(),
            levelled.iter().sum::<f64>(),
            if levelled.is_empty() {
                0.0
            } else {
                stridekit_lab::stats::median(levelled.iter().copied())
            },
            strides.iter().map(|s| s.climb_m).sum::<f64>(),
            own_end,
        );
    }
    let d: Vec<f64> = (0..3)
        .map(|i| last.position_m[i] - first.position_m[i])
        .collect();
    let d3 = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let dh = d[0].hypot(d[1]);
    // A share of the distance walked; none when the foot did not walk.
    let pct = |x: f64| {
        if last.distance_m > MIN_WALKED_M {
            format!("{:.2} %", 100.0 * x / last.distance_m)
        } else {
            "— % (nothing walked)".into()
        }
    };
    say!(
        "  end − start: ({:.3}, {:.3}, {:.3}) m ENU; 3-D {:.3} m = {} of the distance walked, horizontal {:.3} m = {}, height {:+.3} m (loop closure, for a walk that ends where it starts)",
        d[0], d[1], d[2], d3, pct(d3), dh, pct(dh), d[2]
    );
    if replayed.resets > 0 {
        say!("  divergence-guard resets: {}", replayed.resets);
    }
    if let Some(g) = &truth {
        let se: f64 = est
            .iter()
            .zip(g)
            .map(|((_, e), g)| {
                (0..3)
                    .map(|i| (e.position_m[i] - g[i]).powi(2))
                    .sum::<f64>()
            })
            .sum();
        let sh: f64 = est
            .iter()
            .zip(g)
            .map(|((_, e), g)| {
                (0..2)
                    .map(|i| (e.position_m[i] - g[i]).powi(2))
                    .sum::<f64>()
            })
            .sum();
        say!(
            "  position RMSE against the aligned truth: {:.3} m (horizontal {:.3} m)",
            (se / est.len() as f64).sqrt(),
            (sh / est.len() as f64).sqrt()
        );
    }
    say!(
        "  rests on: the IMU alone (zero-velocity updates at each stance; no GNSS, no step-length model); accelerometer alignment: {}",
        match &args.calibration {
            Some(f) => format!("the device calibration {}", f.display()),
            None => "none given (`stridekit calibrate foot` learns it from level walks; without it the height may climb by a centimetre a stride, see docs/foot.md)".into(),
        }
    );
    match &plots {
        Some((top, height)) => say!(
            "  trajectory in {}, plots in {} and {}",
            sink.name(),
            top.display(),
            height.display()
        ),
        None => say!("  trajectory on stdout (no plots)"),
    }
    usable(&replayed.skipped, trial.rec.len(), last.strides)
}

/// Fails when the replay produced nothing usable: no stride, or the samples refused
/// for their units (in g, timestamps not in seconds) outnumber the accepted ones.
fn usable(
    skipped: &stridekit_lab::foot::Skipped,
    samples: usize,
    strides: u64,
) -> Result<(), Failure> {
    let mut causes = Vec::new();
    if strides == 0 {
        causes.push(if skipped.total() >= samples {
            "no stride: every sample was refused".to_string()
        } else {
            "no stride detected: no trajectory (the foot never left a stance the detector saw)"
                .to_string()
        });
    }
    let units = [
        (
            skipped.in_g,
            "accelerations look like g, not m/s² (multiply by 9.80665)",
        ),
        (
            skipped.time_unit,
            skipped
                .time_unit_message
                .as_deref()
                .unwrap_or("timestamps not in seconds"),
        ),
    ];
    for (n, why) in units {
        if 2 * n > samples {
            causes.push(format!(
                "the IMU stream was refused for its units ({n} of its samples): {why}"
            ));
        }
    }
    if causes.is_empty() {
        Ok(())
    } else {
        Err(Failure::Failed(causes.join("; ")))
    }
}

/// `v` with `decimals` decimals, without a sign on a value that rounds to zero.
fn fixed(v: f64, decimals: usize) -> String {
    let text = format!("{v:.decimals$}");
    match text.strip_prefix('-') {
        Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_string(),
        _ => text,
    }
}

/// `DIR/NAME.csv` → (`DIR/NAME.svg`, `DIR/NAME_height.svg`).
fn svg_paths(out: &Path) -> (PathBuf, PathBuf) {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "foot_trajectory".into());
    (
        out.with_file_name(format!("{stem}.svg")),
        out.with_file_name(format!("{stem}_height.svg")),
    )
}

fn write_csv(
    sink: &Sink,
    est: &[(usize, FootEstimate)],
    truth: Option<&[[f64; 3]]>,
) -> Result<(), Failure> {
    let name = sink.name();
    let io = write_error(&name);
    let mut w = sink.open()?;
    writeln!(w, "t_s,east_m,north_m,up_m,v_east_mps,v_north_mps,v_up_mps,yaw_rad,stance,strides,distance_m,gt_east_m,gt_north_m,gt_up_m").map_err(&io)?;
    // Positions and distances to 0.1 mm, velocities to 0.1 mm/s, yaw to 1e-5 rad,
    // time to 1 µs: finer than the navigator resolves (and than VICON's truth).
    let mm = |v: f64| fixed(v, 4);
    for (j, (_, e)) in est.iter().enumerate() {
        let gs = truth.map_or(",,".to_string(), |g| {
            format!("{},{},{}", mm(g[j][0]), mm(g[j][1]), mm(g[j][2]))
        });
        let [x, y, z] = e.position_m.map(mm);
        let [vx, vy, vz] = e.velocity_mps.map(mm);
        writeln!(
            w,
            "{:.6},{x},{y},{z},{vx},{vy},{vz},{},{},{},{},{gs}",
            e.t_s,
            fixed(e.yaw_rad, 5),
            e.stance as u8,
            e.strides,
            mm(e.distance_m),
        )
        .map_err(&io)?;
    }
    w.flush().map_err(&io)
}

fn plot(
    top: &Path,
    height: &Path,
    name: &str,
    est: &[(usize, FootEstimate)],
    unlevelled: Option<&[(usize, FootEstimate)]>,
    truth: Option<&[[f64; 3]]>,
) -> Result<(), String> {
    let step = (est.len() / PLOT_POINTS).max(1);
    let thin = |f: &dyn Fn(usize) -> (f64, f64)| -> Vec<(f64, f64)> {
        (0..est.len()).step_by(step).map(f).collect()
    };
    let mut track = Vec::new();
    let mut heights = Vec::new();
    if let Some(g) = truth {
        track.push(Series {
            name: "truth (aligned)".into(),
            points: thin(&|j| (g[j][0], g[j][1])),
            color: Some((0, 0, 0)),
            style: Style::Line,
        });
        heights.push(Series {
            name: "truth (aligned)".into(),
            points: thin(&|j| (est[j].1.t_s, g[j][2])),
            color: Some((0, 0, 0)),
            style: Style::Line,
        });
    }
    track.push(Series {
        name: "estimate".into(),
        points: thin(&|j| (est[j].1.position_m[0], est[j].1.position_m[1])),
        color: Some((31, 119, 180)),
        style: Style::Line,
    });
    track.push(Series {
        name: "stride ends".into(),
        points: est
            .iter()
            .filter(|(_, e)| e.stride.is_some())
            .map(|(_, e)| (e.position_m[0], e.position_m[1]))
            .collect(),
        color: Some((214, 39, 40)),
        style: Style::Points,
    });
    if let Some(raw) = unlevelled {
        heights.push(Series {
            name: "the filter's own height (level floor off)".into(),
            points: raw
                .iter()
                .step_by(step)
                .map(|(_, e)| (e.t_s, e.position_m[2]))
                .collect(),
            color: Some((150, 150, 150)),
            style: Style::Line,
        });
    }
    heights.push(Series {
        name: "estimate".into(),
        points: thin(&|j| (est[j].1.t_s, est[j].1.position_m[2])),
        color: Some((31, 119, 180)),
        style: Style::Line,
    });
    let title = format!("{name}: foot trajectory, top view (local ENU)");
    track_chart(top, &title, &track).map_err(|e| format!("{}: {e}", top.display()))?;
    let title = format!("{name}: foot height");
    line_chart(
        height,
        &Chart {
            title: &title,
            x_label: "time (s)",
            y_label: "up (m)",
            series: &heights,
            bands: &[],
            y_range: None,
            y_format: stridekit_lab::report::YFormat::Number,
        },
    )
    .map_err(|e| format!("{}: {e}", height.display()))
}

/// A truth point in the estimate's frame: `R(−θ)·(g − t)`.
fn into_estimate_frame(th: f64, t: [f64; 3], g: [f64; 3]) -> [f64; 3] {
    let (s, c) = th.sin_cos();
    let (x, y) = (g[0] - t[0], g[1] - t[1]);
    [c * x + s * y, -s * x + c * y, g[2] - t[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alignment_recovers_a_rotation_and_translation() {
        let est: Vec<[f64; 3]> = (0..50)
            .map(|i| {
                let a = i as f64 * 0.2;
                [3.0 * a.cos(), 2.0 * a.sin(), 0.1 * a]
            })
            .collect();
        let (th0, t0) = (0.7_f64, [1.5, -2.0, 0.3]);
        let (s, c) = th0.sin_cos();
        let truth: Vec<[f64; 3]> = est
            .iter()
            .map(|e| {
                [
                    c * e[0] - s * e[1] + t0[0],
                    s * e[0] + c * e[1] + t0[1],
                    e[2] + t0[2],
                ]
            })
            .collect();
        let (th, t) = align(&est, &truth);
        assert!((th - th0).abs() < 1e-12);
        for i in 0..3 {
            assert!((t[i] - t0[i]).abs() < 1e-12);
        }
        for (e, g) in est.iter().zip(&truth) {
            let back = into_estimate_frame(th, t, *g);
            for i in 0..3 {
                assert!((back[i] - e[i]).abs() < 1e-12);
            }
        }
    }

    /// A simulated 400 Hz walk with the sensor z up and tilted on the shoe, written
    /// as an x-io CSV export (deg/s, g) with repeated rows as from a coarse clock,
    /// a reversed timestamp, a NaN and a truncated line: the replay skips and counts
    /// them and the loop closes.
    #[test]
    fn replays_an_xio_export_with_repeated_rows() {
        use stridekit_sim::{simulate_foot, FootScenario};
        let sim = simulate_foot(&FootScenario {
            sample_rate_hz: 400.0,
            mount_rpy_rad: [0.3, -0.5, 0.4],
            loop_m: [10.0, 5.0],
            ..FootScenario::walk(7, 1)
        });
        let dir = std::env::temp_dir().join(format!("stridekit-xio-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("walk.csv");
        let mut text = String::from("Time (s),Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s),Accelerometer X (g),Accelerometer Y (g),Accelerometer Z (g)\n");
        let row = |t: f64, s: &stridekit_core::foot::FootSample| {
            let w = s.gyro_rads.map(f64::to_degrees);
            let a = s.accel_mps2.map(|v| v / 9.80665);
            format!(
                "{t:.9},{},{},{},{},{},{}\n",
                w[0], w[1], w[2], a[0], a[1], a[2]
            )
        };
        let (mut repeated, mut backwards, mut nan) = (0, 0, 0);
        for (i, s) in sim.samples.iter().enumerate() {
            text.push_str(&row(s.t_s, s));
            if i > 400 && i % 97 == 0 {
                text.push_str(&row(s.t_s, s));
                repeated += 1;
            }
            if i == 5000 {
                text.push_str(&row(s.t_s - 0.1, s));
                backwards += 1;
            }
            if i == 6000 {
                text.push_str(&format!("{},NaN,0,0,0,0,1\n", s.t_s + 1e-4));
                nan += 1;
            }
        }
        text.push_str("12.3,4.5\n");
        std::fs::write(&file, text).unwrap();

        let rec = read_foot_csv(&file).unwrap();
        assert_eq!(rec.format, FootFormat::Xio);
        assert_eq!(rec.unreadable_rows, 1);
        let args = FootArgs {
            file: file.clone(),
            out: dir.join("walk_out.csv"),
            axes: Some("flu".into()),
            ..Default::default()
        };
        let (config, _) = config_for(&args, rec.format, &evidence(&[&rec])).unwrap();
        assert!(
            config.gyro_bias_from_alignment,
            "x-io: consumer profile by default"
        );
        let trial = Trial {
            best: String::new(),
            runner_up: None,
            pyshoe_best_m: None,
            run: false,
            path_m: 0.0,
            rec,
        };
        let m = Method {
            name: "t".into(),
            config,
            labels: None,
        };
        let r = replay_counted(&trial, &m).unwrap();
        assert_eq!(r.skipped.repeated_time, repeated);
        assert_eq!(r.skipped.time_backwards, backwards);
        assert_eq!(r.skipped.non_finite, nan);
        assert_eq!(r.skipped.total(), repeated + backwards + nan);
        assert!((r.rate_hz - 400.0).abs() < 1.0, "{}", r.rate_hz);
        let first = r.estimates[0].1;
        let last = r.estimates.last().unwrap().1;
        let d: f64 = (0..3)
            .map(|i| (last.position_m[i] - first.position_m[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        let closure = d / last.distance_m;
        assert!(last.distance_m > 25.0, "{}", last.distance_m);
        assert!(
            closure < 0.01,
            "closure {:.2} % of {:.1} m",
            closure * 100.0,
            last.distance_m
        );
        // The command itself runs end to end.
        run(&args, &Sink::from_arg(&args.out, "csv").unwrap()).unwrap();
        assert!(dir.join("walk_out.svg").exists());
        std::fs::remove_dir_all(&dir).ok();
    }

    /// A level simulated walk whose accelerometer is turned 1.2° about the lateral
    /// axis against the gyroscope, as an x-io export: `calibrate` learns the angle,
    /// writes the file, and the replay with `--calibration` uses it.
    #[test]
    fn calibrate_learns_the_alignment_and_the_replay_loads_it() {
        use stridekit_sim::{simulate_foot, FootScenario};
        let truth = 0.021_f64;
        let sim = simulate_foot(&FootScenario::walk(3, 1));
        // Turned by −truth about y: x' = c·x − s·z, z' = s·x + c·z.
        let (sn, c) = truth.sin_cos();
        let dir = std::env::temp_dir().join(format!("stridekit-footcal-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("level.csv");
        let mut text = String::from("Time (s),Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s),Accelerometer X (g),Accelerometer Y (g),Accelerometer Z (g)\n");
        for s in &sim.samples {
            let w = s.gyro_rads.map(f64::to_degrees);
            let f = s.accel_mps2;
            let a = [c * f[0] - sn * f[2], f[1], sn * f[0] + c * f[2]].map(|v| v / 9.80665);
            text += &format!(
                "{:.9},{},{},{},{},{},{}\n",
                s.t_s, w[0], w[1], w[2], a[0], a[1], a[2]
            );
        }
        std::fs::write(&file, text).unwrap();
        let cal = dir.join("imu.cal");
        let report = calibrate(std::slice::from_ref(&file), &cal, None, None).unwrap();
        assert!(report.contains("| level |"), "{report}");
        assert!(dir.join("imu.svg").exists());
        let a = read_calibration(&cal).unwrap();
        assert!((a[1] - truth).abs() < 0.003, "{a:?}");
        let args = FootArgs {
            file: file.clone(),
            out: dir.join("out.csv"),
            calibration: Some(cal.clone()),
            ..Default::default()
        };
        let (config, described) = config_for(&args, FootFormat::Xio, &Evidence::default()).unwrap();
        assert_eq!(config.accel_alignment_rad, a);
        assert!(described.contains("accelerometer alignment"), "{described}");
        run(&args, &Sink::from_arg(&args.out, "csv").unwrap()).unwrap();
        std::fs::write(&cal, "not a calibration\n").unwrap();
        let e = config_for(&args, FootFormat::Xio, &Evidence::default()).unwrap_err();
        assert!(e.contains("imu.cal"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn bad_axes_are_refused() {
        let args = FootArgs {
            axes: Some("x,y,-z".into()),
            ..Default::default()
        };
        let e = config_for(&args, FootFormat::Xio, &Evidence::default()).unwrap_err();
        assert!(e.contains("mirror"), "{e}");
    }

    /// A trial of the UofT VICON set in `../shared/data`, or `None` (the test skips,
    /// saying why).
    fn uoft_trial(name: &str) -> Option<stridekit_formats::FootRecording> {
        let Some(path) = stridekit_formats::data_dir()
            .map(|d| d.join("foot/pyshoe-vicon").join(format!("{name}.csv")))
            .filter(|p| p.exists())
        else {
            eprintln!("skipping: ../shared/data/foot/pyshoe-vicon/{name}.csv not found (set STRIDEKIT_DATA)");
            return None;
        };
        Some(read_foot_csv(&path).unwrap())
    }

    /// Issue 36 item 6, real data: the MicroStrain's pitch rate on 2017-11-22-11-44-47
    /// stops at about 9.13 rad/s in 15 swings. The data say so, and the ceiling found is
    /// the clip's; the same motion with every rate ×1.5, as an IMU of 1.5× the range
    /// clipped at 1.5× the rate would record it, is clipped at ×1.5, not at 9.2 rad/s.
    #[test]
    fn a_real_clipped_gyroscope_is_detected_at_its_own_ceiling() {
        let Some(rec) = uoft_trial("2017-11-22-11-44-47") else {
            return;
        };
        let (config, text) =
            config_for(&FootArgs::default(), rec.format, &evidence(&[&rec])).unwrap();
        let r = config.gyro_range_rads.expect("clipping detected");
        assert!((9.0..9.15).contains(&(0.99 * r)), "{r}: {text}");
        assert!(text.contains("clipping detected"), "{text}");
        assert!(text.contains("on sensor y−"), "{text}");
        assert!(!config.gyro_bias_from_alignment, "UofT: calibrated: {text}");

        let mut wide = rec.clone();
        wide.gyro_rads.iter_mut().flatten().for_each(|w| *w *= 1.5);
        let c = evidence(&[&wide]).ceiling.expect("still clipped");
        assert!((1.5 * 9.0..1.5 * 9.15).contains(&c.ceiling_rads), "{c:?}");
    }

    /// Issue 36 item 6, real data: a trial that never clips (2017-11-22-11-26-05,
    /// peak 8.99 rad/s) with every rate ×1.3, its swing peaks at 11.7 rad/s as from a
    /// wider-range IMU on a faster foot, written as a plain `t_s,acc_*,gyr_*` CSV of an
    /// unknown device. Before: the layout meant the UofT MicroStrain, so the calibrated
    /// profile and a 9.2 rad/s range whose "repair" added rotation to every peak above
    /// 9.1 rad/s. Now: no flat tops, no range, nothing repaired, the consumer profile,
    /// and the replay says so.
    #[test]
    fn a_wider_range_imu_is_not_repaired_at_the_microstrain_ceiling() {
        let Some(rec) = uoft_trial("2017-11-22-11-26-05") else {
            return;
        };
        let dir = std::env::temp_dir().join(format!("stridekit-widegyro-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("wide.csv");
        let mut text =
            String::from("t_s,acc_x_mps2,acc_y_mps2,acc_z_mps2,gyr_x_rads,gyr_y_rads,gyr_z_rads\n");
        for i in 0..rec.len() {
            let (a, w) = (rec.accel_mps2[i], rec.gyro_rads[i].map(|w| 1.3 * w));
            text += &format!(
                "{},{},{},{},{},{},{}\n",
                rec.t_s[i], a[0], a[1], a[2], w[0], w[1], w[2]
            );
        }
        std::fs::write(&file, text).unwrap();
        let wide = read_foot_csv(&file).unwrap();
        let device = evidence(&[&wide]);
        assert!(device.peak_rads > 11.0, "{}", device.peak_rads);
        assert_eq!(device.ceiling, None);
        let args = FootArgs {
            file: file.clone(),
            out: dir.join("out.csv"),
            ..Default::default()
        };
        let (config, described) = config_for(&args, wide.format, &device).unwrap();
        assert_eq!(config.gyro_range_rads, None, "{described}");
        assert!(config.gyro_bias_from_alignment, "consumer: {described}");
        assert!(described.contains("no clipping detected"), "{described}");
        assert!(described.contains("IMU profile consumer"), "{described}");
        // A range the user gives is used, and one the data contradict is questioned.
        let (config, described) = config_for(
            &FootArgs {
                gyro_range_rads: Some(9.2),
                ..args.clone()
            },
            wide.format,
            &device,
        )
        .unwrap();
        assert_eq!(config.gyro_range_rads, Some(9.2));
        assert!(described.contains("above the given range"), "{described}");
        run(&args, &Sink::from_arg(&args.out, "csv").unwrap()).unwrap();
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn numbers_are_written_to_their_precision() {
        assert_eq!(fixed(-0.00000014, 4), "0.0000");
        assert_eq!(fixed(-0.00012, 4), "-0.0001");
        assert_eq!(fixed(0.028743696105534, 4), "0.0287");
    }

    #[test]
    fn svgs_go_next_to_the_csv() {
        let (a, b) = svg_paths(Path::new("out/walk.csv"));
        assert_eq!(a, Path::new("out/walk.svg"));
        assert_eq!(b, Path::new("out/walk_height.svg"));
    }
}
