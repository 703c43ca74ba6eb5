//! `stridekit eval orientation`: the orientation filters against optical motion
//! capture on the BROAD trials, with the benchmark's own metric
//! ([`crate::orientation::metric`]): per trial and as means over trials, for the
//! default filter, Madgwick (defaults and plain with BROAD's best common gain) and
//! the variants of the decoupled filter kept for comparison; plus leave-half-out
//! figures (settings chosen on the odd-numbered trials, scored on the even ones,
//! and the reverse). Evaluation code: lives in the CLI, not in the shipped core.

use std::path::{Path, PathBuf};

use stridekit_core::ahrs::{Ahrs, AhrsSettings, DecoupledSettings};
use stridekit_formats::{list_broad_trials, read_broad, OrientationRecording};

use crate::orientation::metric::{ErrorSums, Rmse};
use crate::table::Table;

/// Options of `stridekit eval orientation`.
#[derive(Clone, Debug)]
pub struct EvalOrientationArgs {
    /// Folder with the BROAD trials (`*.csv.gz`).
    pub data: PathBuf,
    /// Without the magnetometer: only the inclination is meaningful.
    pub imu_only: bool,
    /// `NAME=VALUE` changes of the default filter's settings (sensitivity checks).
    pub set: Vec<(String, f64)>,
    /// Only the default filter (with `set` applied): no comparison, no grid.
    pub quick: bool,
}

/// Changes one setting of the decoupled filter by name (`--set NAME=VALUE`).
pub fn set_decoupled(s: &mut AhrsSettings, name: &str, v: f64) -> Result<(), String> {
    let d = &mut s.decoupled;
    let field = match name {
        "accel_time_constant_s" => &mut d.accel_time_constant_s,
        "mag_time_constant_s" => &mut d.mag_time_constant_s,
        "motion_bias_time_constant_s" => &mut d.motion_bias_time_constant_s,
        "heading_bias_time_constant_s" => &mut d.heading_bias_time_constant_s,
        "bias_random_walk" => &mut d.bias_random_walk,
        "motion_bias_accuracy_rads" => &mut d.motion_bias_accuracy_rads,
        "rest_gyro_rads" => &mut d.rest_gyro_rads,
        "rest_accel_mps2" => &mut d.rest_accel_mps2,
        "rest_time_s" => &mut d.rest_time_s,
        "rest_bias_time_constant_s" => &mut d.rest_bias_time_constant_s,
        "max_bias_rads" => &mut d.max_bias_rads,
        "mag_norm_threshold" => &mut d.mag_norm_threshold,
        "mag_dip_threshold_rad" => &mut d.mag_dip_threshold_rad,
        "mag_min_undisturbed_s" => &mut d.mag_min_undisturbed_s,
        "mag_max_rejection_s" => &mut d.mag_max_rejection_s,
        "mag_offset_max_ut" => &mut d.mag_offset_max_ut,
        _ => return Err(format!("unknown setting {name} (see DecoupledSettings)")),
    };
    *field = v;
    s.validate().map_err(|e| e.to_string())
}

/// BROAD's best common Madgwick gain (the authors' example code, all 39 trials).
pub const BROAD_MADGWICK_GAIN: f64 = 0.12;

/// One filter configuration under test.
pub struct Variant {
    pub name: &'static str,
    pub settings: AhrsSettings,
}

/// The filters of the comparison: the default, the Madgwick variants, and the
/// decoupled filter with one feature switched off at a time (ablations).
pub fn variants() -> Vec<Variant> {
    let d = AhrsSettings::default();
    let with = |f: &dyn Fn(&mut DecoupledSettings)| {
        let mut s = d;
        f(&mut s.decoupled);
        s
    };
    vec![
        Variant {
            name: "default (decoupled)",
            settings: d,
        },
        Variant {
            name: "Madgwick, stridekit defaults (`AhrsSettings::madgwick()`)",
            settings: AhrsSettings::madgwick(),
        },
        Variant {
            name: "Madgwick plain, β = 0.12 (`AhrsSettings::plain(0.12)`)",
            settings: AhrsSettings::plain(BROAD_MADGWICK_GAIN),
        },
        Variant {
            name: "decoupled, no bias estimation",
            settings: AhrsSettings {
                bias_estimation: false,
                ..d
            },
        },
        Variant {
            name: "decoupled + bias learned in motion (τ = 100 s)",
            settings: with(&|s| s.motion_bias_time_constant_s = 100.0),
        },
        Variant {
            name: "decoupled, no magnetic rejection",
            settings: with(&|s| {
                s.mag_norm_threshold = f64::INFINITY;
                s.mag_dip_threshold_rad = f64::INFINITY;
            }),
        },
    ]
}

/// Replays one trial; returns the error sums and the number of rejected samples.
pub fn score_trial(
    settings: AhrsSettings,
    rec: &OrientationRecording,
    imu_only: bool,
) -> Result<(ErrorSums, usize), String> {
    let mut ahrs = Ahrs::new(settings).map_err(|e| e.to_string())?;
    let mut sums = ErrorSums::default();
    let mut rejected = 0;
    for ((s, truth), &moving) in rec.samples.iter().zip(&rec.truth).zip(&rec.movement) {
        let mag = if imu_only { None } else { s.mag_ut };
        if ahrs.update(s.t_s, s.gyro_rads, s.accel_mps2, mag).is_err() {
            rejected += 1;
            continue;
        }
        if let (true, Some(t), Some(q)) = (moving, truth, ahrs.quaternion()) {
            sums.add(&q, t);
        }
    }
    Ok((sums, rejected))
}

/// RMSE per trial of one settings set.
fn score_all(
    settings: AhrsSettings,
    trials: &[OrientationRecording],
    imu_only: bool,
) -> Result<Vec<Rmse>, String> {
    trials
        .iter()
        .map(|t| score_trial(settings, t, imu_only).map(|(s, _)| s.rmse()))
        .collect()
}

fn number(t: &OrientationRecording) -> u32 {
    t.trial_number().unwrap_or(0)
}

/// Undisturbed trials (BROAD 1–23) and magnet trials (28–36).
fn is_undisturbed(t: &OrientationRecording) -> bool {
    (1..=23).contains(&number(t))
}
fn is_magnet(t: &OrientationRecording) -> bool {
    (28..=36).contains(&number(t))
}

fn mean_where(
    r: &[Rmse],
    trials: &[OrientationRecording],
    keep: impl Fn(&OrientationRecording) -> bool,
) -> Rmse {
    Rmse::mean(
        r.iter()
            .zip(trials)
            .filter(|(_, t)| keep(t))
            .map(|(r, _)| r),
    )
}

/// The candidate settings of the leave-half-out check: the accelerometer and
/// magnetometer time constants at ⅔×, 1× and 1.5× their defaults, and the motion bias
/// off / 200 s / 100 s.
fn grid() -> Vec<(String, AhrsSettings)> {
    let d = DecoupledSettings::default();
    let mut out = Vec::new();
    for fa in [2.0 / 3.0, 1.0, 1.5] {
        for fm in [2.0 / 3.0, 1.0, 1.5] {
            for tb in [f64::INFINITY, 200.0, 100.0] {
                let decoupled = DecoupledSettings {
                    accel_time_constant_s: d.accel_time_constant_s * fa,
                    mag_time_constant_s: d.mag_time_constant_s * fm,
                    motion_bias_time_constant_s: tb,
                    ..d
                };
                let bias = if tb.is_finite() {
                    format!("{tb:.0} s")
                } else {
                    "off".to_string()
                };
                out.push((
                    format!(
                        "{:.2} s, {:.1} s, {bias}",
                        decoupled.accel_time_constant_s, decoupled.mag_time_constant_s,
                    ),
                    AhrsSettings {
                        decoupled,
                        ..AhrsSettings::default()
                    },
                ));
            }
        }
    }
    out
}

/// Reads every trial of `dir`.
pub fn load(dir: &Path) -> Result<Vec<OrientationRecording>, String> {
    let paths = list_broad_trials(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    if paths.is_empty() {
        return Err(format!("no BROAD trials (*.csv.gz) in {}", dir.display()));
    }
    paths
        .iter()
        .map(|p| read_broad(p).map_err(|e| format!("{}: {e}", p.display())))
        .collect()
}

/// The comparison's variants with `--set` applied to the default.
fn configured_variants(args: &EvalOrientationArgs) -> Result<Vec<Variant>, String> {
    let mut variants = variants();
    for (k, v) in &args.set {
        set_decoupled(&mut variants[0].settings, k, *v)?;
    }
    if !args.set.is_empty() {
        variants[0].name = "default with --set changes";
    }
    Ok(variants)
}

/// `eval orientation` as text: `--quick` (the default filter alone, per trial) or
/// [`eval`] rendered.
pub fn run(args: &EvalOrientationArgs) -> Result<String, String> {
    if args.quick {
        return quick(args);
    }
    Ok(eval(args)?.render())
}

/// The default filter (with `--set` applied) alone: its means and every trial.
fn quick(args: &EvalOrientationArgs) -> Result<String, String> {
    let trials = load(&args.data)?;
    let default = configured_variants(args)?.swap_remove(0);
    let r = score_all(default.settings, &trials, args.imu_only)?;
    let mut out = format!(
        "{}: all {} | undisturbed {} | magnet {}\n",
        default.name,
        Rmse::mean(&r).cell(),
        mean_where(&r, &trials, is_undisturbed).cell(),
        mean_where(&r, &trials, is_magnet).cell()
    );
    for (t, r) in trials.iter().zip(&r) {
        out.push_str(&format!("  {:<45} {}\n", t.name, r.cell()));
    }
    Ok(out)
}

/// `eval orientation`, computed ([`OrientationReport::render`] writes it).
pub struct OrientationReport {
    pub imu_only: bool,
    pub trials: Vec<OrientationRecording>,
    pub variants: Vec<Variant>,
    /// `results[variant][trial]`.
    pub results: Vec<Vec<Rmse>>,
    /// The leave-out grid ([`grid`]) and `per[setting][trial]`.
    pub grid: Vec<(String, AhrsSettings)>,
    pub per: Vec<Vec<Rmse>>,
}

/// Every variant and every grid setting on every trial.
pub fn eval(args: &EvalOrientationArgs) -> Result<OrientationReport, String> {
    let trials = load(&args.data)?;
    let imu = args.imu_only;
    let variants = configured_variants(args)?;
    let mut results = Vec::new();
    let pb = crate::progress::bar(variants.len(), "eval orientation: filters");
    for v in &variants {
        pb.inc(1);
        eprintln!("eval orientation: {}", v.name);
        results.push(score_all(v.settings, &trials, imu)?);
    }
    let grid = grid();
    eprintln!(
        "eval orientation: leave-half-out grid of {} settings",
        grid.len()
    );
    let mut per: Vec<Vec<Rmse>> = Vec::new();
    for (_, s) in &grid {
        per.push(score_all(*s, &trials, imu)?);
    }
    Ok(OrientationReport {
        imu_only: imu,
        trials,
        variants,
        results,
        grid,
        per,
    })
}

/// One half's choice in the leave-half-out check.
struct HalfChoice {
    name: &'static str,
    /// The setting was chosen on the odd trials (and is held out on the even ones).
    fit_odd: bool,
    /// Index into the grid.
    setting: usize,
    chosen_fit: Rmse,
    chosen_held: Rmse,
    default_held: Rmse,
}

impl OrientationReport {
    /// The report as markdown.
    pub fn render(&self) -> String {
        let mode = if self.imu_only {
            "IMU only (no magnetometer): inclination error"
        } else {
            "MARG (with magnetometer): total / heading / inclination error"
        };
        let mut out = format!(
            "BROAD, {} trials, {mode}, RMSE during movement in degrees, mean over trials; \
             one settings set per filter for all trials.\n\n",
            self.trials.len()
        );
        out.push_str(&self.filter_table().render());
        // Per trial: the default and the two Madgwick rows.
        out.push_str(&format!(
            "\nPer trial ({}):\n\n",
            if self.imu_only {
                "inclination"
            } else {
                "total / heading / inclination"
            }
        ));
        out.push_str(&self.trial_table().render());
        out.push_str(&self.leave_half_out());
        out.push_str(&self.leave_one_trial_out());
        out
    }

    fn cell(&self, r: &Rmse) -> String {
        if self.imu_only {
            format!("{:.2}", r.inclination_deg)
        } else {
            r.cell()
        }
    }

    /// What the grid minimises: inclination (IMU only) or total error.
    fn objective(&self, r: &Rmse) -> f64 {
        if self.imu_only {
            r.inclination_deg
        } else {
            r.total_deg
        }
    }

    /// Each filter's means over all trials, the groups and the two halves.
    fn filter_table(&self) -> Table {
        let trials = &self.trials;
        let mut t = Table::new([
            "filter",
            "all trials",
            "undisturbed (1–23)",
            "magnet (28–36)",
            "odd trials",
            "even trials",
        ]);
        for (v, r) in self.variants.iter().zip(&self.results) {
            t.row([
                v.name.to_string(),
                self.cell(&Rmse::mean(r)),
                self.cell(&mean_where(r, trials, is_undisturbed)),
                self.cell(&mean_where(r, trials, is_magnet)),
                self.cell(&mean_where(r, trials, |t| number(t) % 2 == 1)),
                self.cell(&mean_where(r, trials, |t| number(t) % 2 == 0)),
            ]);
        }
        t
    }

    /// The default and the two Madgwick rows, per trial.
    fn trial_table(&self) -> Table {
        let mut header = vec!["trial".to_string()];
        header.extend(self.variants[..3].iter().map(|v| v.name.to_string()));
        let mut t = Table::new(header);
        for (i, trial) in self.trials.iter().enumerate() {
            let mut row = vec![trial.name.clone()];
            row.extend(self.results[..3].iter().map(|r| self.cell(&r[i])));
            t.row(row);
        }
        t
    }

    /// For each half, the grid setting with the lowest mean objective on it, scored
    /// on the other half beside the fixed default.
    fn half_choices(&self) -> Vec<HalfChoice> {
        let (trials, per, default) = (&self.trials, &self.per, &self.results[0]);
        let mut out = Vec::new();
        for (fit_odd, name) in [(true, "odd trials → even"), (false, "even trials → odd")] {
            let fit = |t: &OrientationRecording| (number(t) % 2 == 1) == fit_odd;
            let best = (0..self.grid.len())
                .min_by(|&a, &b| {
                    self.objective(&mean_where(&per[a], trials, fit))
                        .total_cmp(&self.objective(&mean_where(&per[b], trials, fit)))
                })
                .unwrap_or(0);
            out.push(HalfChoice {
                name,
                fit_odd,
                setting: best,
                chosen_fit: mean_where(&per[best], trials, fit),
                chosen_held: mean_where(&per[best], trials, |t| !fit(t)),
                default_held: mean_where(default, trials, |t| !fit(t)),
            });
        }
        out
    }

    /// Leave half out: the paragraph and its table.
    fn leave_half_out(&self) -> String {
        let mut out = format!(
            "\nLeave half out: {} settings of the decoupled filter (accelerometer and magnetometer \
             time constants at ⅔×/1×/1.5× their defaults, motion bias off / 200 s / 100 s); \
             the one with the lowest mean {} on one half is scored on the other.\n\n",
            self.grid.len(),
            if self.imu_only {
                "inclination error"
            } else {
                "total error"
            }
        );
        let mut t = Table::new([
            "chosen on",
            "settings chosen (accel τ, mag τ, motion-bias τ)",
            "chosen half",
            "held-out half, chosen",
            "held-out half, fixed default",
        ]);
        let mut held = Vec::new();
        for c in self.half_choices() {
            held.extend(
                self.per[c.setting]
                    .iter()
                    .zip(&self.trials)
                    .filter(|(_, t)| (number(t) % 2 == 1) != c.fit_odd)
                    .map(|(r, _)| *r),
            );
            t.row([
                c.name.to_string(),
                self.grid[c.setting].0.clone(),
                self.cell(&c.chosen_fit),
                self.cell(&c.chosen_held),
                self.cell(&c.default_held),
            ]);
        }
        t.row([
            "**both halves held out**".to_string(),
            String::new(),
            String::new(),
            format!("**{}**", self.cell(&Rmse::mean(&held))),
            format!("**{}**", self.cell(&Rmse::mean(&self.results[0]))),
        ]);
        out.push_str(&t.render());
        out
    }

    /// Leave one trial out over the same grid: for each trial, the setting with the
    /// lowest mean objective on the other trials, scored on it; the per-trial table
    /// beside the fixed defaults, and the mean.
    fn leave_one_trial_out(&self) -> String {
        let (trials, per, default) = (&self.trials, &self.per, &self.results[0]);
        let out = format!(
            "\nLeave one trial out: for each trial, the setting of the same {} with the lowest \
             mean on the other {} trials, scored on it.\n\n",
            self.grid.len(),
            trials.len().saturating_sub(1)
        );
        let mut t = Table::new([
            "held-out trial",
            "settings chosen on the others",
            "held out, chosen",
            "fixed default",
        ]);
        let mut held = Vec::new();
        for (i, trial) in trials.iter().enumerate() {
            let others = |r: &[Rmse]| {
                let rest = r.iter().enumerate().filter(|&(j, _)| j != i);
                self.objective(&Rmse::mean(rest.map(|(_, r)| r)))
            };
            let best = (0..self.grid.len())
                .min_by(|&a, &b| others(&per[a]).total_cmp(&others(&per[b])))
                .unwrap_or(0);
            held.push(per[best][i]);
            t.row([
                trial.name.clone(),
                self.grid[best].0.clone(),
                self.cell(&per[best][i]),
                self.cell(&default[i]),
            ]);
        }
        t.row([
            "**mean**".to_string(),
            String::new(),
            format!("**{}**", self.cell(&Rmse::mean(&held))),
            format!("**{}**", self.cell(&Rmse::mean(default))),
        ]);
        out + &t.render()
    }
}
