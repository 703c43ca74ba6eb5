//! `stridekit train placement` and `stridekit eval placement`: the phone-placement
//! classifier (core::placement) on the Oxford Step Counter traces (phones carried 7
//! ways by 3 users; the placement is in each folder name).
//!
//! Evaluation is leave-one-user-out: for each user, a model is trained on the other
//! users' traces and tested on all of this user's traces. Scores: per window (one
//! window = 5.12 s, every 1.28 s), per window after the classifier's 8-window
//! smoothing, and per trace by majority vote of the windows. The simulator part
//! applies the model trained on all real traces to simulated walks (information
//! only: the simulator's placements were not designed to match the real ones).

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use crate::placement::{predict, train, TrainParams};
use crate::table::Table;
use stridekit_core::placement::BinAverager;
use stridekit_core::placement::{
    trace_features, AccelSample, Features, Placement, PlacementClassifier, PlacementModel, CLASSES,
    FEATURES, FEATURE_NAMES, WINDOW,
};
use stridekit_core::placement::{window_features, FeatureTables};
use stridekit_formats::{list_oxford_traces, read_oxford_trace};
use stridekit_sim::{simulate_phone, PhonePlacement, PhoneScenario};

/// Smoothing of the streaming classifier, windows.
const SMOOTHING: usize = stridekit_core::placement::DEFAULT_SMOOTHING;

/// One trace's windows.
pub struct TraceWindows {
    pub name: String,
    pub user: String,
    pub label: Placement,
    pub samples: usize,
    pub features: Vec<Features>,
}

/// Features of every Oxford trace under `dir`, and the extraction time.
pub fn load(dir: &Path, drop: &[usize]) -> Result<(Vec<TraceWindows>, f64), String> {
    let mut out = Vec::new();
    let mut secs = 0.0;
    for path in list_oxford_traces(dir).map_err(|e| e.to_string())? {
        let t = read_oxford_trace(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let label = Placement::from_oxford_position(t.position.name())
            .ok_or_else(|| {
                format!(
                    "{}: no placement in the folder name (the placement evaluation needs it as the label: <Phone>_<User>_<Surface>_<Position>_<n>, Position one of {})",
                    t.name,
                    stridekit_formats::OxfordPosition::ALL.map(|p| p.name()).join(", ")
                )
            })?;
        let start = Instant::now();
        let mut features = trace_features(t.accel.iter().map(|a| (a.t_s, a.accel_mps2)));
        secs += start.elapsed().as_secs_f64();
        for f in &mut features {
            for &i in drop {
                f[i] = 0.0;
            }
        }
        out.push(TraceWindows {
            name: t.name,
            user: t.user,
            label,
            samples: t.accel.len(),
            features,
        });
    }
    if out.is_empty() {
        return Err(format!("no Oxford traces under {}", dir.display()));
    }
    Ok((out, secs))
}

fn labelled<'a>(traces: impl Iterator<Item = &'a TraceWindows>) -> Vec<(Features, Placement)> {
    traces
        .flat_map(|t| t.features.iter().map(move |f| (*f, t.label)))
        .collect()
}

/// Per-window predictions of a trace: raw and after the classifier's smoothing.
fn predictions(model: &PlacementModel, feats: &[Features]) -> (Vec<Placement>, Vec<Placement>) {
    let mut raw = Vec::new();
    let mut smooth = Vec::new();
    let mut logs: Vec<[f64; CLASSES]> = Vec::new();
    for f in feats {
        raw.push(predict(model, f));
        let p = model.probabilities(f);
        logs.push(p.map(|v| v.max(1e-6).ln()));
        let from = logs.len().saturating_sub(SMOOTHING);
        let mut s = [0.0; CLASSES];
        for l in &logs[from..] {
            for c in 0..CLASSES {
                s[c] += l[c];
            }
        }
        let best = (0..CLASSES)
            .max_by(|&a, &b| s[a].total_cmp(&s[b]))
            .unwrap_or(0);
        smooth.push(Placement::ALL[best]);
    }
    (raw, smooth)
}

fn vote(pred: &[Placement]) -> Option<Placement> {
    let mut n = [0usize; CLASSES];
    for p in pred {
        n[p.index()] += 1;
    }
    (!pred.is_empty()).then(|| Placement::ALL[(0..CLASSES).max_by_key(|&c| n[c]).unwrap_or(0)])
}

fn pct(a: usize, b: usize) -> String {
    if b == 0 {
        "–".into()
    } else {
        format!("{:.1} %", 100.0 * a as f64 / b as f64)
    }
}

fn provenance(line: &str, traces: &[TraceWindows], params: &TrainParams) -> Vec<String> {
    let windows: usize = traces.iter().map(|t| t.features.len()).sum();
    vec![
        "Phone placement classifier: multinomial logistic regression, class-balanced, L2.".into(),
        format!("Trained by: {line}"),
        format!(
            "Data: Oxford Step Counter (Salvi et al. 2018, CC BY 4.0), {} traces, {windows} windows of 5.12 s every 1.28 s.",
            traces.len()
        ),
        format!(
            "Params: l2 {} iterations {} step {} momentum {}",
            params.l2, params.iterations, params.step, params.momentum
        ),
    ]
}

/// `stridekit train placement`: train on every trace, write the model file.
pub fn train_cmd(dir: &Path, out: &Path, line: &str) -> Result<String, String> {
    let (traces, _) = load(dir, &[])?;
    let params = TrainParams::default();
    let data = labelled(traces.iter());
    let model =
        train(&data, &params, provenance(line, &traces, &params)).map_err(|e| e.to_string())?;
    let text = model.to_text();
    std::fs::write(out, &text).map_err(|e| format!("{}: {e}", out.display()))?;
    let acc = crate::placement::accuracy(&model, &data);
    Ok(format!(
        "wrote {} ({} bytes): {} traces, {} windows, training accuracy {:.1} % (not a test score; see `stridekit eval placement`)",
        out.display(),
        text.len(),
        traces.len(),
        data.len(),
        100.0 * acc
    ))
}

/// ns per window (features + model) on a real window, and ns per sample of the
/// whole classifier on a trace.
fn timing(dir: &Path, model: &PlacementModel) -> Result<(f64, f64, f64), String> {
    let path = list_oxford_traces(dir)
        .map_err(|e| e.to_string())?
        .into_iter()
        .next()
        .ok_or("no trace")?;
    let t = read_oxford_trace(&path).map_err(|e| e.to_string())?;
    let mut bins = BinAverager::new();
    let mut w = [[0.0; 3]; WINDOW];
    let mut n = 0;
    for a in &t.accel {
        let b = bins.push(a.t_s, a.accel_mps2);
        for m in &b.means[..b.len] {
            if n < WINDOW {
                w[n] = *m;
                n += 1;
            }
        }
        if n == WINDOW {
            break;
        }
    }
    let tables = FeatureTables::default();
    let reps = 2000;
    let start = Instant::now();
    let mut sink = 0.0;
    for _ in 0..reps {
        let f = window_features(&tables, std::hint::black_box(&w));
        sink += model.probabilities(&f)[0];
    }
    let ns_window = start.elapsed().as_secs_f64() * 1e9 / reps as f64;
    std::hint::black_box(sink);
    let mut c = PlacementClassifier::new(model.clone(), SMOOTHING);
    let start = Instant::now();
    for a in &t.accel {
        let s = AccelSample {
            t_s: a.t_s,
            accel_mps2: a.accel_mps2,
        };
        let _ = std::hint::black_box(c.push(&s));
    }
    let ns_sample = start.elapsed().as_secs_f64() * 1e9 / t.accel.len() as f64;
    Ok((ns_window, ns_sample, t.rate_hz()))
}

/// The features `--drop` names, as indices (for ablation: set to 0 in training and test).
fn dropped_features(drop: Option<&str>) -> Result<Vec<usize>, String> {
    let Some(list) = drop else {
        return Ok(Vec::new());
    };
    list.split(',')
        .map(|n| {
            FEATURE_NAMES
                .iter()
                .position(|f| *f == n.trim())
                .ok_or_else(|| {
                    format!(
                        "unknown feature {n:?}; features: {}",
                        FEATURE_NAMES.join(" ")
                    )
                })
        })
        .collect()
}

/// Hits out of a count.
#[derive(Clone, Copy, Debug, Default)]
struct Score {
    ok: usize,
    n: usize,
}

impl Score {
    fn add(&mut self, other: Score) {
        self.ok += other.ok;
        self.n += other.n;
    }
    fn pct(self) -> String {
        pct(self.ok, self.n)
    }
}

/// One held-out user's scores (the logistic regression trained on the others).
#[derive(Clone, Debug, Default)]
struct UserScores {
    user: String,
    traces: usize,
    /// Windows, raw.
    windows: Score,
    /// Windows after the classifier's smoothing (of the same windows).
    smoothed: Score,
    /// Traces by majority vote.
    votes: Score,
    /// Classes of this user's traces the training users never recorded.
    missing: Vec<&'static str>,
}

/// One held-out trace's result.
struct TraceResult {
    name: String,
    truth: Placement,
    vote: Option<Placement>,
    windows: Score,
    smoothed: Score,
}

/// One held-out user's MLP scores.
struct MlpScores {
    user: String,
    windows: Score,
    votes: Score,
}

/// One simulated placement under the model trained on every real trace.
struct SimResult {
    placement: PhonePlacement,
    class: Placement,
    windows: Score,
    most_often: Option<Placement>,
}

/// The model trained on every trace: its size and its cost on this machine.
struct ModelCost {
    parameter_bytes: usize,
    file_bytes: usize,
    ns_window: f64,
    ns_sample: f64,
    rate_hz: f64,
    samples: usize,
    extract_s: f64,
}

/// What `stridekit eval placement` measured, computed by [`evaluate`] and rendered by
/// [`PlacementReport::render`].
struct PlacementReport {
    traces: usize,
    users: usize,
    windows: usize,
    by_user: Vec<UserScores>,
    /// The MLP of `--mlp`, its L2, per held-out user.
    mlp: Option<(f64, Vec<MlpScores>)>,
    /// Windows and traces whose class the training users recorded.
    seen_windows: Score,
    seen_votes: Score,
    confusion: [[usize; CLASSES]; CLASSES],
    trace_confusion: [[usize; CLASSES]; CLASSES],
    by_trace: Vec<TraceResult>,
    cost: ModelCost,
    sim: Vec<SimResult>,
}

/// `stridekit eval placement`.
/// `drop`: feature names to neutralise (set to 0 in training and test), for ablation.
pub fn eval_cmd(
    dir: &Path,
    drop: Option<&str>,
    l2: Option<f64>,
    mlp: bool,
) -> Result<String, String> {
    let drop = dropped_features(drop)?;
    let mut params = TrainParams::default();
    if let Some(l2) = l2 {
        params.l2 = l2;
    }
    Ok(evaluate(dir, &drop, &params, mlp)?.render())
}

/// Leave one user out over the traces under `dir`, the MLP beside it when `mlp`, the
/// model on every trace (its cost) and on the simulator.
fn evaluate(
    dir: &Path,
    drop: &[usize],
    params: &TrainParams,
    mlp: bool,
) -> Result<PlacementReport, String> {
    let (traces, extract_s) = load(dir, drop)?;
    let mut users: Vec<String> = traces.iter().map(|t| t.user.clone()).collect();
    users.sort();
    users.dedup();
    let mut report = PlacementReport {
        traces: traces.len(),
        users: users.len(),
        windows: traces.iter().map(|t| t.features.len()).sum(),
        by_user: Vec::new(),
        mlp: None,
        seen_windows: Score::default(),
        seen_votes: Score::default(),
        confusion: [[0; CLASSES]; CLASSES],
        trace_confusion: [[0; CLASSES]; CLASSES],
        by_trace: Vec::new(),
        cost: ModelCost {
            parameter_bytes: 0,
            file_bytes: 0,
            ns_window: 0.0,
            ns_sample: 0.0,
            rate_hz: 0.0,
            samples: traces.iter().map(|t| t.samples).sum(),
            extract_s,
        },
        sim: Vec::new(),
    };
    for user in &users {
        let scores = held_out_user(&traces, user, params, &mut report)?;
        report.by_user.push(scores);
    }
    if mlp {
        let rows = users
            .iter()
            .map(|u| mlp_held_out_user(&traces, u, params.l2))
            .collect::<Result<_, _>>()?;
        report.mlp = Some((params.l2, rows));
    }
    // The model on all traces: size and speed; then the simulator.
    let all = labelled(traces.iter());
    let model =
        train(&all, params, provenance("(eval)", &traces, params)).map_err(|e| e.to_string())?;
    let (ns_window, ns_sample, rate_hz) = timing(dir, &model)?;
    report.cost = ModelCost {
        parameter_bytes: model.parameter_bytes(),
        file_bytes: model.to_text().len(),
        ns_window,
        ns_sample,
        rate_hz,
        ..report.cost
    };
    report.sim = PhonePlacement::ALL
        .iter()
        .map(|&p| simulated(&model, p))
        .collect();
    Ok(report)
}

/// `user`'s traces under the logistic regression trained on the other users: the
/// user's row; its traces, the confusion matrices and the seen-class scores go into
/// `report`.
fn held_out_user(
    traces: &[TraceWindows],
    user: &str,
    params: &TrainParams,
    report: &mut PlacementReport,
) -> Result<UserScores, String> {
    let train_set = labelled(traces.iter().filter(|t| t.user != user));
    let model = train(&train_set, params, Vec::new()).map_err(|e| e.to_string())?;
    let mut seen = [false; CLASSES];
    for (_, p) in &train_set {
        seen[p.index()] = true;
    }
    let mine: Vec<&TraceWindows> = traces.iter().filter(|t| t.user == user).collect();
    let mut u = UserScores {
        user: user.to_string(),
        traces: mine.len(),
        missing: Placement::ALL
            .iter()
            .filter(|p| !seen[p.index()])
            .filter(|p| mine.iter().any(|t| t.label == **p))
            .map(|p| p.name())
            .collect(),
        ..UserScores::default()
    };
    for t in mine {
        let (raw, smooth) = predictions(&model, &t.features);
        let truth = t.label.index();
        let windows = Score {
            ok: raw.iter().filter(|p| **p == t.label).count(),
            n: raw.len(),
        };
        let smoothed = Score {
            ok: smooth.iter().filter(|p| **p == t.label).count(),
            n: smooth.len(),
        };
        for p in &raw {
            report.confusion[truth][p.index()] += 1;
        }
        u.windows.add(windows);
        u.smoothed.add(Score {
            ok: smoothed.ok,
            n: raw.len(),
        });
        let v = vote(&raw);
        if let Some(v) = v {
            report.trace_confusion[truth][v.index()] += 1;
            let hit = Score {
                ok: (v == t.label) as usize,
                n: 1,
            };
            u.votes.add(hit);
            if seen[truth] {
                report.seen_votes.add(hit);
            }
        }
        if seen[truth] {
            report.seen_windows.add(windows);
        }
        report.by_trace.push(TraceResult {
            name: t.name.clone(),
            truth: t.label,
            vote: v,
            windows,
            smoothed,
        });
    }
    Ok(u)
}

/// `user`'s traces under the MLP trained on the other users.
fn mlp_held_out_user(traces: &[TraceWindows], user: &str, l2: f64) -> Result<MlpScores, String> {
    let train_set = labelled(traces.iter().filter(|t| t.user != user));
    let m = crate::placement_mlp::train(&train_set, l2)?;
    let mut s = MlpScores {
        user: user.to_string(),
        windows: Score::default(),
        votes: Score::default(),
    };
    for t in traces.iter().filter(|t| t.user == user) {
        let pred: Vec<Placement> = t.features.iter().map(|f| m.predict(f)).collect();
        s.windows.add(Score {
            ok: pred.iter().filter(|p| **p == t.label).count(),
            n: pred.len(),
        });
        if let Some(v) = vote(&pred) {
            s.votes.add(Score {
                ok: (v == t.label) as usize,
                n: 1,
            });
        }
    }
    Ok(s)
}

/// Simulated walks in placement `p` (1.3 m/s, 120 s, seeds 1–3) under `model`.
fn simulated(model: &PlacementModel, p: PhonePlacement) -> SimResult {
    let class = Placement::from(p);
    let mut preds = Vec::new();
    for seed in 1..=3u64 {
        let mut sc = PhoneScenario::walk(seed, p, 1.3, 120.0);
        sc.gnss = false;
        let sim = simulate_phone(&sc);
        let feats = trace_features(sim.samples.iter().map(|s| (s.t_s, s.accel_mps2)));
        preds.extend(feats.iter().map(|f| predict(model, f)));
    }
    SimResult {
        placement: p,
        class,
        windows: Score {
            ok: preds.iter().filter(|q| **q == class).count(),
            n: preds.len(),
        },
        most_often: vote(&preds),
    }
}

/// A confusion matrix (rows: truth, columns: predicted) with each row's recall.
fn confusion_table(m: &[[usize; CLASSES]; CLASSES]) -> Table {
    let mut t = Table::new(
        std::iter::once("truth \\ predicted".to_string())
            .chain(Placement::ALL.iter().map(|p| p.to_string()))
            .chain(std::iter::once("recall".to_string())),
    );
    for (i, row) in m.iter().enumerate() {
        t.row(
            std::iter::once(Placement::ALL[i].to_string())
                .chain(row.iter().map(|v| v.to_string()))
                .chain(std::iter::once(pct(row[i], row.iter().sum()))),
        );
    }
    t
}

impl PlacementReport {
    /// The report as markdown: the leave-one-user-out table (and the MLP's), the
    /// seen-class scores, the confusion matrices, the traces, the model's cost, the
    /// simulator.
    fn render(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "## Phone placement, leave-one-user-out ({} Oxford traces, {} users, {} windows of 5.12 s every 1.28 s)\n",
            self.traces, self.users, self.windows
        );
        out.push_str(&self.user_table().render());
        out.push('\n');
        if let Some((l2, rows)) = &self.mlp {
            let _ = writeln!(
                out,
                "Comparison, same protocol: one-hidden-layer MLP (16 tanh units, {} bytes of parameters), L2 {l2}:\n",
                crate::placement_mlp::Mlp::parameter_bytes(),
            );
            out.push_str(&mlp_table(rows).render());
            out.push('\n');
        }
        let _ = writeln!(
            out,
            "Without the held-out traces whose class the training users never recorded: window accuracy {} ({} windows), trace accuracy {} ({} traces).\n",
            self.seen_windows.pct(),
            self.seen_windows.n,
            self.seen_votes.pct(),
            self.seen_votes.n
        );
        for (title, m) in [
            (
                "Confusion matrix, windows (rows: truth, columns: predicted)",
                &self.confusion,
            ),
            (
                "Confusion matrix, traces by majority vote",
                &self.trace_confusion,
            ),
        ] {
            let _ = writeln!(out, "{title}:\n");
            out.push_str(&confusion_table(m).render());
            out.push('\n');
        }
        let _ = writeln!(out, "Per trace (held-out model):\n");
        out.push_str(&self.trace_table().render());
        out.push('\n');
        out.push_str(&self.cost_lines());
        let _ = writeln!(
            out,
            "### Simulator (information only): model trained on all real traces, simulated walks at 1.3 m/s, 120 s, 3 seeds per placement\n"
        );
        out.push_str(&self.sim_table().render());
        out
    }

    fn user_table(&self) -> Table {
        let mut t = Table::new([
            "held-out user",
            "traces",
            "windows",
            "window acc.",
            "smoothed acc.",
            "trace acc. (vote)",
            "classes missing from training",
        ]);
        let mut all = UserScores::default();
        for u in &self.by_user {
            t.row([
                u.user.clone(),
                u.traces.to_string(),
                u.windows.n.to_string(),
                u.windows.pct(),
                u.smoothed.pct(),
                u.votes.pct(),
                if u.missing.is_empty() {
                    "–".to_string()
                } else {
                    u.missing.join(", ")
                },
            ]);
            all.windows.add(u.windows);
            all.smoothed.add(u.smoothed);
            all.votes.add(u.votes);
        }
        t.row([
            "**all**".to_string(),
            self.traces.to_string(),
            all.windows.n.to_string(),
            format!("**{}**", all.windows.pct()),
            format!("**{}**", all.smoothed.pct()),
            format!("**{}**", all.votes.pct()),
            String::new(),
        ]);
        t
    }

    fn trace_table(&self) -> Table {
        let mut t = Table::new(["trace", "truth", "vote", "window acc.", "smoothed acc."]);
        for r in &self.by_trace {
            t.row([
                r.name.clone(),
                r.truth.to_string(),
                r.vote.map(|p| p.name()).unwrap_or("–").to_string(),
                r.windows.pct(),
                r.smoothed.pct(),
            ]);
        }
        t
    }

    fn cost_lines(&self) -> String {
        let c = &self.cost;
        format!(
            "Model: logistic regression, {FEATURES} features × {CLASSES} classes: {} bytes of parameters (f64), model file {} bytes; classifier state {} bytes (`size_of::<PlacementClassifier>()`, plus the model's comment strings on the heap).\n\
             Cost (this machine, release build): {:.0} ns per window (features + model), {:.0} ns per sample for the whole classifier on a {:.0} Hz trace; feature extraction of all {} samples took {:.2} s.\n\n",
            c.parameter_bytes,
            c.file_bytes,
            std::mem::size_of::<PlacementClassifier>(),
            c.ns_window,
            c.ns_sample,
            c.rate_hz,
            c.samples,
            c.extract_s
        )
    }

    fn sim_table(&self) -> Table {
        let mut t = Table::new([
            "simulated placement",
            "class",
            "window acc.",
            "predicted most often",
        ]);
        let mut all = Score::default();
        for r in &self.sim {
            t.row([
                format!("{:?}", r.placement),
                r.class.to_string(),
                r.windows.pct(),
                r.most_often.map(|q| q.name()).unwrap_or("–").to_string(),
            ]);
            all.add(r.windows);
        }
        t.row([
            "**all**".to_string(),
            String::new(),
            format!("**{}**", all.pct()),
            String::new(),
        ]);
        t
    }
}

/// The MLP's leave-one-user-out table.
fn mlp_table(rows: &[MlpScores]) -> Table {
    let mut t = Table::new(["held-out user", "MLP window acc.", "MLP trace acc. (vote)"]);
    let (mut windows, mut votes) = (Score::default(), Score::default());
    for r in rows {
        t.row([r.user.clone(), r.windows.pct(), r.votes.pct()]);
        windows.add(r.windows);
        votes.add(r.votes);
    }
    t.row([
        "**all**".to_string(),
        format!("**{}**", windows.pct()),
        format!("**{}**", votes.pct()),
    ]);
    t
}
