//! `stridekit train odometry`, `stridekit eval odometry` and `stridekit odometry FILE`:
//! the learned phone inertial odometry (core/src/odometry) on the simulator and on
//! recordings in the RIDI / RoNIN layouts (stridekit-formats).

use std::fmt::Write;
use std::path::Path;
use std::time::Instant;

use crate::odometry::evaluate::{run_methods, Scores, METHODS};
use crate::odometry::train::{
    fit_model, labelled_windows, samples_of, sim_scenario, simulated_windows, write_model,
    LabelledWindow, RecTruth, Truth, FEATURES_COMMENT, FIRST_EVAL_SEED,
};
use crate::table::Table;
use stridekit_core::odometry::{
    ImuSample, OdometryConfig, OdometryModel, PhoneOdometry, PipelineParams, PlacementSource,
    AUTO_MIN_CONFIDENCE,
};
use stridekit_core::placement::{Placement, CLASSES};
use stridekit_formats::{
    read_inertial, read_inertial_dir, InertialRecording as Recording, InertialSample,
};
use stridekit_sim::{simulate_phone, PhonePlacement};

use crate::report::{track_chart, Series};

/// Span over which recordings without an ENU heading are aligned, s.
const HEADING_FIT_S: f64 = 20.0;

/// Name of a simulator placement (`sim:SEED:NAME`, recordings from the simulator).
fn sim_name(p: PhonePlacement) -> &'static str {
    match p {
        PhonePlacement::InHand => "in_hand",
        PhonePlacement::FrontPocket => "front_pocket",
        PhonePlacement::BackPocket => "back_pocket",
        PhonePlacement::Bag => "bag",
        PhonePlacement::NeckPouch => "neck_pouch",
        PhonePlacement::Armband => "armband",
        PhonePlacement::SwingingArm => "swinging_arm",
    }
}

fn sim_from_name(s: &str) -> Option<PhonePlacement> {
    PhonePlacement::ALL.into_iter().find(|&p| sim_name(p) == s)
}

/// `SEED[:PLACEMENT]`, the part after `sim:` of a simulated walk's name (placement
/// `in_hand` when none is given).
pub fn parse_sim_spec(spec: &str) -> Result<(u64, PhonePlacement), String> {
    let (seed, place) = spec.split_once(':').unwrap_or((spec, "in_hand"));
    let seed: u64 = seed
        .parse()
        .map_err(|_| format!("bad seed {seed:?} in sim:{spec} (sim:SEED:PLACEMENT)"))?;
    let p = sim_from_name(place).ok_or_else(|| {
        let names: Vec<&str> = PhonePlacement::ALL.into_iter().map(sim_name).collect();
        format!("unknown placement {place} (one of {})", names.join(", "))
    })?;
    Ok((seed, p))
}

/// Placement class of a recording: a model-file name (`pocket`, …) or a simulator
/// placement name (`front_pocket`, as the RIDI reader guesses).
fn placement_of(rec: &Recording) -> Option<Placement> {
    let name = rec.placement.as_deref()?;
    stridekit_core::odometry::placement_from_name(name)
        .flatten()
        .or_else(|| sim_from_name(name).map(Placement::from))
}

/// The source of a recording's replay: its placement when known, else unknown.
fn source_of(rec: &Recording) -> PlacementSource {
    placement_of(rec).map_or(PlacementSource::Unknown, PlacementSource::Fixed)
}

/// The simulator's output as a recording.
fn from_sim(sim: &stridekit_sim::SimulatedPhone, p: PhonePlacement) -> Recording {
    Recording {
        name: format!("sim seed {}", sim.scenario.seed),
        placement: Some(sim_name(p).into()),
        samples: sim
            .samples
            .iter()
            .map(|s| InertialSample {
                t_s: s.t_s,
                accel_mps2: s.accel_mps2,
                gyro_rads: s.gyro_radps,
                mag_ut: Some(s.mag_ut),
            })
            .collect(),
        truth: sim
            .truth
            .iter()
            .map(|t| (t.t_s, t.east_m, t.north_m))
            .collect(),
        ..Default::default()
    }
}

/// Source of training data.
pub enum TrainSource<'a> {
    Sim { seeds: u64 },
    Ridi(&'a Path),
    Ronin(&'a Path),
}

/// Train and write the model; returns a summary.
pub fn train(
    src: TrainSource,
    params: PipelineParams,
    out: &Path,
    command: &str,
) -> Result<String, String> {
    params.validate()?;
    let started = Instant::now();
    let (windows, what): (Vec<LabelledWindow>, String) = match src {
        TrainSource::Sim { seeds } => (
            simulated_windows(seeds, params),
            format!(
                "simulator: seeds 1..={seeds} for each of the 7 simulated placements (core::odometry::train::sim_scenario; front and back pocket both train `pocket`)"
            ),
        ),
        TrainSource::Ridi(dir) | TrainSource::Ronin(dir) => {
            let recs = read_inertial_dir(dir).map_err(|e| e.to_string())?;
            let mut w = Vec::new();
            for r in &recs {
                w.extend(labelled_windows(&samples_of(r), &RecTruth(r), placement_of(r), params));
            }
            (w, format!("{} recordings in {}", recs.len(), dir.display()))
        }
    };
    let comments = vec![
        format!("trained by: {command}"),
        format!("data: {what}; {} windows", windows.len()),
        FEATURES_COMMENT.into(),
    ];
    let model = fit_model(&windows, params, comments).ok_or("too few windows to fit")?;
    let written = write_model(&model, out)?;
    Ok(format!(
        "{} windows, {written}, {:.1} s; wrote {}",
        windows.len(),
        started.elapsed().as_secs_f64(),
        out.display()
    ))
}

fn load_model(path: Option<&Path>) -> Result<OdometryModel, String> {
    match path {
        None => Ok(OdometryModel::shipped()),
        Some(p) => {
            let text = std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()))?;
            OdometryModel::parse(&text).map_err(|e| format!("{}: {e}", p.display()))
        }
    }
}

/// A placement-source row: (ATE / RTE) per source, then Auto's placement counts.
fn source_row(name: &str, s: &[(f64, f64); 3], auto: &[usize; 4 + CLASSES]) -> Vec<String> {
    let mut row = vec![name.to_string()];
    row.extend(s.iter().map(|(a, r)| format!("{a:.1} / {r:.1}")));
    let pct = |k: usize| 100.0 * auto[k] as f64 / auto[0].max(1) as f64;
    let mut best = 0;
    for k in 0..CLASSES {
        if auto[4 + k] > auto[4 + best] {
            best = k;
        }
    }
    row.push(format!("{:.0} %", pct(1)));
    row.push(format!("{:.0} % / {:.0} %", pct(2), pct(3)));
    row.push(format!("{} ({:.0} %)", Placement::ALL[best], pct(4 + best)));
    row
}

/// A method row: (ATE / RTE) per method.
fn scores_row(name: &str, s: &Scores) -> Vec<String> {
    let mut row = vec![name.to_string()];
    row.extend(s.iter().map(|(a, r)| format!("{a:.1} / {r:.1}")));
    row
}

/// The simulator's attitude at `t`: normalised linear interpolation of the 10 Hz
/// truth quaternions (sign-aligned).
fn true_attitude(sim: &stridekit_sim::SimulatedPhone, t: f64) -> [f64; 4] {
    let tr = &sim.truth;
    let x = (t / 0.1).max(0.0);
    let i = (x.floor() as usize).min(tr.len() - 1);
    let j = (i + 1).min(tr.len() - 1);
    let f = (x - i as f64).clamp(0.0, 1.0);
    let (a, mut b) = (tr[i].attitude_wxyz, tr[j].attitude_wxyz);
    if a.iter().zip(&b).map(|(u, v)| u * v).sum::<f64>() < 0.0 {
        b = b.map(|v| -v);
    }
    let q: Vec<f64> = (0..4).map(|k| a[k] + f * (b[k] - a[k])).collect();
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
}

/// ATE / RTE of the learned pipeline fed the true attitude.
fn true_attitude_scores(
    sim: &stridekit_sim::SimulatedPhone,
    samples: &[ImuSample],
    model: &OdometryModel,
    placement: PlacementSource,
) -> (f64, f64) {
    use crate::odometry::metrics::{align_start, ate, rte};
    let mut eng = PhoneOdometry::new(
        OdometryConfig {
            placement,
            ..Default::default()
        },
        model.clone(),
    )
    .expect("valid model");
    let mut est = Vec::new();
    for s in samples {
        if let Ok(Some(e)) = eng.push_with_attitude(s, true_attitude(sim, s.t_s)) {
            est.push((e.t_s, e.position_m[0], e.position_m[1]));
        }
    }
    let truth: Vec<_> = est
        .iter()
        .map(|p| {
            let (e, n) = sim.position_at(p.0);
            (p.0, e, n)
        })
        .collect();
    align_start(&mut est, &truth);
    (ate(&est, &truth), rte(&est, &truth, 60.0))
}

/// The learned pipeline alone with `source`: (ATE, RTE), and over its estimates
/// the counts (estimates, detected placement = `truth`, own regressor of `truth`
/// used, general regressor used, then estimates per detected class).
fn learned_run(
    samples: &[ImuSample],
    truth: &dyn Truth,
    model: &OdometryModel,
    source: PlacementSource,
    class: Placement,
) -> ((f64, f64), [usize; 4 + CLASSES]) {
    use crate::odometry::metrics::{align_start, ate, rte};
    let cfg = OdometryConfig {
        placement: source,
        ..Default::default()
    };
    let mut eng = PhoneOdometry::new(cfg, model.clone()).expect("valid model");
    let mut est = Vec::new();
    let mut c = [0; 4 + CLASSES];
    for s in samples {
        if let Ok(Some(e)) = eng.push(s) {
            est.push((e.t_s, e.position_m[0], e.position_m[1]));
            c[0] += 1;
            c[1] += usize::from(e.detected_placement == Some(class));
            c[2] += usize::from(e.regressor_placement == Some(class));
            c[3] += usize::from(e.regressor_placement.is_none());
            if let Some(d) = e.detected_placement {
                c[4 + d.index()] += 1;
            }
        }
    }
    let truth: Vec<_> = est
        .iter()
        .map(|p| {
            let (e, n) = truth.position_at(p.0);
            (p.0, e, n)
        })
        .collect();
    align_start(&mut est, &truth);
    ((ate(&est, &truth), rte(&est, &truth, 60.0)), c)
}

/// One simulated placement over the held-out seeds (means over seeds).
#[derive(Clone, Debug)]
pub struct PlacementEval {
    pub name: &'static str,
    /// (ATE, RTE) of each method of [`METHODS`], m.
    pub methods: Scores,
    /// (ATE, RTE) of the learned pipeline per placement source: known, unknown, auto.
    pub by_source: [(f64, f64); 3],
    /// Auto's counts (see [`learned_run`]), summed over seeds.
    pub auto: [usize; 4 + CLASSES],
    /// (ATE, RTE) of the learned pipeline fed the true attitude, m.
    pub true_attitude: (f64, f64),
    /// Per window: the regressor's speed RMSE, m/s, and direction RMSE, °.
    pub speed_rmse_mps: f64,
    pub direction_rmse_deg: f64,
}

/// `eval odometry`, computed ([`OdometryReport::render`] writes it).
#[derive(Clone, Debug)]
pub struct OdometryReport {
    pub seeds: u64,
    pub placement_known: bool,
    pub placements: Vec<PlacementEval>,
    pub model_bytes: usize,
    pub model_regressors: usize,
}

/// Per placement (ATE / RTE) of each method on held-out simulator seeds.
pub fn eval(
    model: Option<&Path>,
    seeds: u64,
    placement_known: bool,
) -> Result<OdometryReport, String> {
    let model = load_model(model)?;
    let placements = PhonePlacement::ALL
        .into_iter()
        .map(|p| eval_placement(&model, p, seeds, placement_known))
        .collect();
    Ok(OdometryReport {
        seeds,
        placement_known,
        placements,
        model_bytes: model.size_bytes(),
        model_regressors: model.regressors.iter().flatten().count(),
    })
}

/// Every method, source and diagnosis on the held-out seeds of one placement.
fn eval_placement(
    model: &OdometryModel,
    p: PhonePlacement,
    seeds: u64,
    placement_known: bool,
) -> PlacementEval {
    let class = Placement::from(p);
    let sources = [
        PlacementSource::Fixed(class),
        PlacementSource::Unknown,
        PlacementSource::Auto,
    ];
    let mut by_source = [(0.0, 0.0); 3];
    let mut auto = [0usize; 4 + CLASSES];
    let source = if placement_known {
        PlacementSource::Fixed(class)
    } else {
        PlacementSource::Unknown
    };
    let mut diag = (0.0, 0.0, 0.0, 0.0);
    let mut oracle = (0.0, 0.0);
    let mut mean = [(0.0, 0.0); 4];
    let reg = *model.regressor(placement_known.then_some(class));
    for seed in FIRST_EVAL_SEED..FIRST_EVAL_SEED + seeds {
        let sim = simulate_phone(&sim_scenario(seed, p));
        let samples: Vec<ImuSample> = sim.samples.iter().map(Into::into).collect();
        let (a, r) = true_attitude_scores(&sim, &samples, model, source);
        oracle.0 += a;
        oracle.1 += r;
        window_errors(&mut diag, &reg, &samples, &sim, class, model.params);
        let tracks = run_methods(&samples, &sim, model, source);
        for (k, &src) in sources.iter().enumerate() {
            let ((a, r), c) = learned_run(&samples, &sim, model, src, class);
            by_source[k].0 += a / seeds as f64;
            by_source[k].1 += r / seeds as f64;
            if src == PlacementSource::Auto {
                for i in 0..c.len() {
                    auto[i] += c[i];
                }
            }
        }
        for (k, s) in tracks.scores().iter().enumerate() {
            mean[k].0 += s.0 / seeds as f64;
            mean[k].1 += s.1 / seeds as f64;
        }
    }
    PlacementEval {
        name: sim_name(p),
        methods: mean,
        by_source,
        auto,
        true_attitude: (oracle.0 / seeds as f64, oracle.1 / seeds as f64),
        speed_rmse_mps: (diag.0 / diag.1).sqrt(),
        direction_rmse_deg: (diag.2 / diag.3).sqrt().to_degrees(),
    }
}

/// Adds the regressor's per-window errors to `diag`: (Σ speed error², windows,
/// Σ direction error² over windows faster than 0.3 m/s, those windows).
fn window_errors(
    diag: &mut (f64, f64, f64, f64),
    reg: &stridekit_core::odometry::Regressor,
    samples: &[ImuSample],
    sim: &stridekit_sim::SimulatedPhone,
    class: Placement,
    params: PipelineParams,
) {
    for w in labelled_windows(samples, sim, Some(class), params) {
        let v = w.velocity_s_mps;
        let s = (v[0] * v[0] + v[1] * v[1]).sqrt();
        let est = reg.predict(&w.features);
        diag.0 += (reg.speed(&w.features) - s).powi(2);
        diag.1 += 1.0;
        if s > 0.3 {
            let d = (est[1].atan2(est[0]) - v[1].atan2(v[0]) + std::f64::consts::PI)
                .rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            diag.2 += d * d;
            diag.3 += 1.0;
        }
    }
}

impl OdometryReport {
    /// The report as markdown.
    pub fn render(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "Held-out simulator walks (seeds {FIRST_EVAL_SEED}..{}, 250 s each, \
             core::odometry::train::sim_scenario), mean over seeds of ATE / RTE (1 min), metres; \
             regressor: {}.\n",
            FIRST_EVAL_SEED + self.seeds,
            if self.placement_known {
                "the placement's own"
            } else {
                "general (placement unknown)"
            }
        );
        out.push_str(&self.method_table().render());
        let _ = writeln!(
            out,
            "\nPlacement source (`OdometryConfig::placement`), learned pipeline, same walks, \
             ATE / RTE, metres. Known = `Fixed(class)`, unknown = general regressor, auto = the \
             embedded placement classifier (shipped model, trained on real Oxford traces), its \
             class's regressor at confidence ≥ {AUTO_MIN_CONFIDENCE}. Auto's placement accuracy: \
             share of estimates whose detected placement is the true class; own / general: share \
             of estimates that used the true class's regressor / the general one; most detected: \
             the class the classifier output most often (share of estimates).\n\n{}",
            self.source_table().render()
        );
        let mut oracle = Table::new(["placement", "learned, true attitude"]);
        for p in &self.placements {
            let (a, r) = p.true_attitude;
            oracle.row([p.name.to_string(), format!("{a:.1} / {r:.1}")]);
        }
        let _ = writeln!(
            out,
            "\nDiagnosis: the learned pipeline (same model) fed the simulator's true attitude \
             instead of the AHRS (`PhoneOdometry::push_with_attitude`), ATE / RTE, metres.\n\n{}",
            oracle.render()
        );
        let _ = writeln!(
            out,
            "\nModel: {} bytes of weights ({} regressors); engine state (size_of PhoneOdometry, \
             heap model included in the weights figure): {} bytes.",
            self.model_bytes,
            self.model_regressors,
            std::mem::size_of::<stridekit_core::odometry::PhoneOdometry>()
        );
        let mut windows = Table::new(["placement", "speed RMSE m/s", "direction RMSE °"]);
        for p in &self.placements {
            windows.row([
                p.name.to_string(),
                format!("{:.3}", p.speed_rmse_mps),
                format!("{:.1}", p.direction_rmse_deg),
            ]);
        }
        let _ = writeln!(
            out,
            "\nPer window (same walks): speed RMSE and direction RMSE of the regressor \
             (windows faster than 0.3 m/s).\n\n{}",
            windows.render()
        );
        out
    }

    /// Methods per placement, then their mean over placements.
    fn method_table(&self) -> Table {
        let mut header = vec!["placement".to_string()];
        header.extend(METHODS.iter().map(|m| m.to_string()));
        let mut t = Table::new(header);
        let mut total = [(0.0, 0.0); 4];
        for p in &self.placements {
            t.row(scores_row(p.name, &p.methods));
            for (t, m) in total.iter_mut().zip(&p.methods) {
                t.0 += m.0;
                t.1 += m.1;
            }
        }
        let n = self.placements.len() as f64;
        t.row(scores_row("**all**", &total.map(|(a, r)| (a / n, r / n))));
        t
    }

    /// Placement sources per placement, then their mean (Auto's counts summed).
    fn source_table(&self) -> Table {
        let mut t = Table::new([
            "placement",
            "known",
            "unknown",
            "auto",
            "auto: placement accuracy",
            "auto: own / general regressor",
            "auto: most detected",
        ]);
        let mut total = [(0.0, 0.0); 3];
        let mut auto_total = [0usize; 4 + CLASSES];
        for p in &self.placements {
            t.row(source_row(p.name, &p.by_source, &p.auto));
            for (t, s) in total.iter_mut().zip(&p.by_source) {
                t.0 += s.0;
                t.1 += s.1;
            }
            for (t, a) in auto_total.iter_mut().zip(&p.auto) {
                *t += a;
            }
        }
        let n = self.placements.len() as f64;
        let total = total.map(|(a, r)| (a / n, r / n));
        t.row(source_row("**all**", &total, &auto_total));
        t
    }
}

/// Replay a recording (RIDI / RoNIN CSV or a simulator seed `sim:SEED:PLACEMENT`),
/// write an SVG of the trajectories and print the errors.
pub fn replay(file: &str, model: Option<&Path>, svg: &Path) -> Result<String, String> {
    let model = load_model(model)?;
    let rec = if let Some(spec) = file.strip_prefix("sim:") {
        let (seed, p) = parse_sim_spec(spec)?;
        from_sim(&simulate_phone(&sim_scenario(seed, p)), p)
    } else {
        read_inertial(Path::new(file)).map_err(|e| format!("{file}: {e}"))?
    };
    let samples = samples_of(&rec);
    let mut tracks = run_methods(&samples, &RecTruth(&rec), &model, source_of(&rec));
    if tracks.truth.is_empty() {
        let mut why = format!(
            "{file}: no estimate from {} samples (the odometry needs a few seconds of IMU samples in m/s² and rad/s)",
            samples.len()
        );
        if tracks.rejected.total() > 0 {
            why += &format!("; rejected:\n{}", tracks.rejected.report().trim_end());
        }
        return Err(why);
    }
    let has_mag = samples.iter().all(|s| s.mag_ut.is_some());
    let mut note = String::new();
    if !has_mag || !file.starts_with("sim:") {
        // Truth frame not ENU (Tango) or heading relative to the start: align it.
        tracks.align_heading(HEADING_FIT_S);
        note = format!(
            "tracks rotated about their start to the truth's heading over the first {HEADING_FIT_S} s\n"
        );
    }
    let xy = |v: &[(f64, f64, f64)]| v.iter().map(|p| (p.1, p.2)).collect::<Vec<_>>();
    let mut series = vec![Series {
        name: "truth".into(),
        points: xy(&tracks.truth),
        color: Some((0, 0, 0)),
        style: Default::default(),
    }];
    // The naive baselines drift thousands of metres: draw them only until they leave
    // a frame of twice the truth's extent, so the truth and the learned track stay
    // readable.
    let (mut lo, mut hi) = ((f64::MAX, f64::MAX), (f64::MIN, f64::MIN));
    for p in &tracks.truth {
        lo = (lo.0.min(p.1), lo.1.min(p.2));
        hi = (hi.0.max(p.1), hi.1.max(p.2));
    }
    let centre = (0.5 * (lo.0 + hi.0), 0.5 * (lo.1 + hi.1));
    let reach = (hi.0 - lo.0).max(hi.1 - lo.1).max(10.0);
    let inside = |p: &(f64, f64)| (p.0 - centre.0).abs() < reach && (p.1 - centre.1).abs() < reach;
    for (k, m) in tracks.methods.iter().enumerate() {
        let mut points = xy(m);
        let mut name = METHODS[k].to_string();
        if let Some(cut) = points.iter().position(|p| !inside(p)) {
            points.truncate(cut);
            name.push_str(" (until off the frame)");
        }
        series.push(Series {
            name,
            points,
            color: None,
            style: Default::default(),
        });
    }
    track_chart(svg, &format!("odometry: {file}"), &series).map_err(|e| e.to_string())?;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{} samples, {} estimates",
        samples.len(),
        tracks.truth.len()
    );
    let _ = writeln!(
        out,
        "model: {}; the learned odometry is experimental: on real walks the PDR (`stridekit pdr FILE`) is more accurate (docs/odometry.md)",
        model
            .comments
            .iter()
            .find_map(|c| c.strip_prefix("trained by: "))
            .unwrap_or("no training command in its comments")
    );
    out.push_str(&note);
    if tracks.rejected.total() == 0 {
        out.push_str("rejected samples: none\n");
    } else {
        let _ = writeln!(out, "rejected samples: {}", tracks.rejected.total());
        out.push_str(&tracks.rejected.report());
    }
    for (why, n) in &rec.skipped {
        let _ = writeln!(out, "  skipped by the reader {n}: {why}");
    }
    if rec.truncated {
        let _ = writeln!(
            out,
            "warning: {file} was cut off mid-write: read up to its last complete record"
        );
    }
    for (k, (a, r)) in tracks.scores().iter().enumerate() {
        let _ = writeln!(out, "{:<30} ATE {a:8.2} m  RTE {r:8.2} m", METHODS[k]);
    }
    let _ = writeln!(out, "wrote {}", svg.display());
    Ok(out)
}
