//! `stridekit eval pdr --data DIR`: pedestrian dead reckoning on real indoor walks
//! with surveyed waypoints (`phone-indoor/`: Android sensor logs), no GNSS. One
//! trajectory per walk from its first sample (the first waypoint), compared at the
//! waypoint times with the measures of `pdr_metrics` (median over walks), per floor
//! and overall, for:
//!
//! - the navigator's defaults, with and without the magnetometer;
//! - calibrated, leave one floor out: `calibrate pdr`'s learning on the other
//!   floors, scored on the held-out one (and, for reference, calibrated on all walks,
//!   i.e. fitted on the test data);
//! - Android's rotation vector as the orientation (a comparison, not a product path);
//! - the learned odometry (`eval_pdr_odometry`), trained leave one floor out.
//!
//! `--diagnose` prints where the error comes from instead (`pdr_diagnose`).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use stridekit_core::pdr::{NavigatorConfig, PdrCalibration};

use crate::pdr::calibrate::learn;
use crate::pdr::metrics::{evaluate, median, Metrics};
use crate::pdr::walks::{load_walks, replay, ReplayOptions, Walk};

/// Load the walks under `dir` with a progress bar.
pub fn load_walks_with_progress(dir: &Path) -> Result<Vec<Walk>, String> {
    let pb = crate::progress::bar(0, "reading walks");
    let walks = load_walks(dir, |i, n| {
        pb.set_length(n as u64);
        pb.set_position(i as u64);
    });
    pb.finish_and_clear();
    walks
}

/// Measures of one method on every walk, by floor.
pub struct MethodResult {
    pub name: String,
    pub by_walk: Vec<(String, Metrics)>,
}

impl MethodResult {
    /// walks | median ATE | start-pinned | end | distance (median |distance|).
    fn cells(ms: &[&Metrics]) -> Vec<String> {
        if ms.is_empty() {
            return ["0", "–", "–", "–", "–"].map(String::from).to_vec();
        }
        vec![
            ms.len().to_string(),
            format!("{:.2} m", median(ms.iter().map(|m| m.ate_m))),
            format!("{:.2} m", median(ms.iter().map(|m| m.start_pinned_m))),
            format!("{:.1} %", median(ms.iter().map(|m| m.end_pct))),
            format!(
                "{:+.1} % ({:.1} %)",
                median(ms.iter().map(|m| m.distance_pct)),
                median(ms.iter().map(|m| m.distance_pct.abs())),
            ),
        ]
    }

    /// The cells over every walk.
    pub fn overall_cells(&self) -> Vec<String> {
        let all: Vec<&Metrics> = self.by_walk.iter().map(|m| &m.1).collect();
        Self::cells(&all)
    }

    /// The cells over the walks of one floor.
    pub fn floor_cells(&self, floor: &str) -> Vec<String> {
        let f: Vec<&Metrics> = self
            .by_walk
            .iter()
            .filter(|m| m.0 == floor)
            .map(|m| &m.1)
            .collect();
        Self::cells(&f)
    }

    /// [`Self::overall_cells`] as one string, ` | ` between the cells.
    pub fn overall(&self) -> String {
        self.overall_cells().join(" | ")
    }

    /// [`Self::floor_cells`] as one string, ` | ` between the cells.
    pub fn floor(&self, floor: &str) -> String {
        self.floor_cells(floor).join(" | ")
    }
}

/// The columns of a method table.
const METHOD_COLUMNS: [&str; 6] = ["method", "walks", "ATE", "start-pinned", "end", "distance"];

/// A method table: one row per method, its cells from `cells`.
pub fn method_table(
    methods: &[MethodResult],
    cells: impl Fn(&MethodResult) -> Vec<String>,
) -> crate::table::Table {
    let mut t = crate::table::Table::new(METHOD_COLUMNS);
    for m in methods {
        let mut row = vec![m.name.clone()];
        row.extend(cells(m));
        t.row(row);
    }
    t
}

/// Replay every walk with options chosen per walk; a walk without options (its
/// floor has no leave-one-floor-out calibration) is not scored.
fn score(
    name: &str,
    walks: &[Walk],
    options: impl Fn(&Walk) -> Option<ReplayOptions>,
) -> Result<MethodResult, String> {
    score_track(name, walks, options, false)
}

/// `live`: score the live estimate (as an app sees it while walking) instead of the
/// trajectory of steps at their own times.
fn score_track(
    name: &str,
    walks: &[Walk],
    options: impl Fn(&Walk) -> Option<ReplayOptions>,
    live: bool,
) -> Result<MethodResult, String> {
    let mut by_walk = Vec::with_capacity(walks.len());
    let pb = crate::progress::bar(walks.len(), name);
    for w in walks {
        pb.inc(1);
        let Some(o) = options(w) else { continue };
        let r = replay(&w.rec, &o)?;
        let track = if live { &r.live } else { &r.track };
        if let Some(m) = evaluate(track, &w.rec.truth) {
            by_walk.push((w.floor.clone(), m));
        }
    }
    pb.finish_and_clear();
    Ok(MethodResult {
        name: name.to_string(),
        by_walk,
    })
}

/// Calibrations learned leave one floor out: floor → calibration from the others.
/// A floor whose other floors hold nothing to learn from (a folder with one floor)
/// gets none: the second map says why.
pub fn lofo_calibrations(
    walks: &[Walk],
    config: &NavigatorConfig,
) -> (BTreeMap<String, PdrCalibration>, BTreeMap<String, String>) {
    let (mut out, mut missing) = (BTreeMap::new(), BTreeMap::new());
    let fl = floors(walks);
    let pb = crate::progress::bar(fl.len(), "calibrating (leave one floor out)");
    for f in fl {
        let train: Vec<&Walk> = walks.iter().filter(|w| w.floor != f).collect();
        match learn(&train, config, config.step_length_model) {
            Ok(c) => {
                out.insert(f, c);
            }
            Err(e) => {
                missing.insert(f, e);
            }
        }
        pb.inc(1);
    }
    pb.finish_and_clear();
    (out, missing)
}

pub fn floors(walks: &[Walk]) -> Vec<String> {
    let mut f: Vec<String> = walks.iter().map(|w| w.floor.clone()).collect();
    f.sort();
    f.dedup();
    f
}

/// The walks with surveyed waypoints under `dir` (an error when there is none: the
/// evaluation scores tracks at the waypoints).
fn scored_walks(dir: &Path) -> Result<Vec<Walk>, String> {
    let walks = load_walks_with_progress(dir)?;
    if walks.is_empty() {
        return Err(format!(
            "no walk with surveyed waypoints (TYPE_WAYPOINT) under {}: the evaluation scores tracks at the waypoints; `stridekit pdr FILE` replays a walk without them",
            dir.display()
        ));
    }
    Ok(walks)
}

/// `eval pdr --data DIR [--diagnose]` as markdown: [`eval`] rendered, or the
/// diagnosis with and without the magnetometer.
pub fn run(dir: &Path, diagnose: bool) -> Result<String, String> {
    if diagnose {
        let walks = scored_walks(dir)?;
        let mut s = crate::pdr::diagnose::diagnose(&walks, true)?.render();
        s += &crate::pdr::diagnose::diagnose(&walks, false)?.render();
        return Ok(s);
    }
    Ok(eval(dir)?.render())
}

/// `eval pdr --data DIR`, computed ([`RealReport::render`] writes it).
pub struct RealReport {
    pub dir: std::path::PathBuf,
    pub walks: usize,
    pub floors: Vec<String>,
    pub methods: Vec<MethodResult>,
    /// Leave-one-floor-out calibrations: floor → learned on the others.
    pub lofo: BTreeMap<String, PdrCalibration>,
    /// Floors without one, and why.
    pub no_lofo: BTreeMap<String, String>,
}

/// Every method on the real walks under `dir`.
pub fn eval(dir: &Path) -> Result<RealReport, String> {
    let walks = scored_walks(dir)?;
    let config = NavigatorConfig::default();
    let (lofo, no_lofo) = lofo_calibrations(&walks, &config);
    let mut methods = pdr_methods(&walks, &config, &lofo)?;
    methods.extend(crate::pdr::odometry::methods(&walks)?);
    Ok(RealReport {
        dir: dir.to_path_buf(),
        walks: walks.len(),
        floors: floors(&walks),
        methods,
        lofo,
        no_lofo,
    })
}

/// The navigator's rows: defaults, settings, calibrations, the rotation vector.
fn pdr_methods(
    walks: &[Walk],
    config: &NavigatorConfig,
    lofo: &BTreeMap<String, PdrCalibration>,
) -> Result<Vec<MethodResult>, String> {
    let config = *config;
    let all_refs: Vec<&Walk> = walks.iter().collect();
    let fitted = learn(&all_refs, &config, config.step_length_model).ok();
    let base = ReplayOptions::default();
    Ok(vec![
        score("defaults, magnetometer", walks, |_| Some(base.clone()))?,
        score_track(
            "defaults, magnetometer, live estimate",
            walks,
            |_| Some(base.clone()),
            true,
        )?,
        score("defaults, no magnetometer", walks, |_| {
            Some(ReplayOptions {
                mag: false,
                ..base.clone()
            })
        })?,
        // What an app gets that says its gyroscope is raw: the fast magnetic loop.
        score(
            "defaults, magnetometer, raw-gyroscope setting (fast magnetic loop)",
            walks,
            |_| {
                Some(ReplayOptions {
                    config: NavigatorConfig {
                        gyro_calibrated: false,
                        ..config
                    },
                    ..base.clone()
                })
            },
        )?,
        score("calibrated leave-one-floor-out, magnetometer", walks, |w| {
            lofo.get(&w.floor).map(|c| ReplayOptions {
                calibration: Some(*c),
                ..base.clone()
            })
        })?,
        score(
            "calibrated leave-one-floor-out, no magnetometer",
            walks,
            |w| {
                lofo.get(&w.floor).map(|c| ReplayOptions {
                    calibration: Some(*c),
                    mag: false,
                    ..base.clone()
                })
            },
        )?,
        score(
            "calibrated on all walks (fitted), magnetometer",
            walks,
            |_| {
                fitted.map(|c| ReplayOptions {
                    calibration: Some(c),
                    ..base.clone()
                })
            },
        )?,
        score("rotation vector as orientation (comparison)", walks, |_| {
            Some(ReplayOptions {
                rotation_vector: true,
                mag: false,
                ..base.clone()
            })
        })?,
    ])
}

impl RealReport {
    /// The report as markdown.
    pub fn render(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "Real indoor walks ({} walks with waypoints under {}; no GNSS): one trajectory per walk from its first sample, compared at the waypoint times. Cells: walks | median ATE (best rotation + translation) | median start-pinned mean error | median end error (% of the waypoint polyline) | median distance error (median |distance error|).\n",
            self.walks,
            self.dir.display()
        );
        out.push_str(&method_table(&self.methods, MethodResult::overall_cells).render());
        for f in &self.floors {
            let _ = writeln!(out, "\nFloor {f}:\n");
            out.push_str(&method_table(&self.methods, |m| m.floor_cells(f)).render());
        }
        out.push_str(&self.calibrations());
        out
    }

    /// The leave-one-floor-out calibrations, one line per floor.
    fn calibrations(&self) -> String {
        let mut out =
            String::from("\nCalibrations (leave one floor out, learned on the other floors):\n\n");
        for (f, why) in &self.no_lofo {
            let _ = writeln!(
                out,
                "- without {f}: none ({why}); the calibrated leave-one-floor-out rows leave its walks out"
            );
        }
        for (f, c) in &self.lofo {
            let _ = writeln!(
                out,
                "- without {f}: {:?} θ = [{:.4}, {:.5}, {:.4}], carrying {}",
                c.step_length_model,
                c.step_length_theta[0],
                c.step_length_theta[1],
                c.step_length_theta[2],
                c.carrying_body
                    .map_or("not fixed (estimates disagree)".into(), |v| format!(
                        "[{:.3}, {:.3}, {:.3}]",
                        v[0], v[1], v[2]
                    ))
            );
        }
        out
    }
}
