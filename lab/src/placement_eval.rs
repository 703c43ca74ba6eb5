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

/// `stridekit eval placement`.
/// `drop`: feature names to neutralise (set to 0 in training and test), for ablation.
pub fn eval_cmd(
    dir: &Path,
    drop: Option<&str>,
    l2: Option<f64>,
    mlp: bool,
) -> Result<String, String> {
    let drop: Vec<usize> = match drop {
        None => Vec::new(),
        Some(list) => list
            .split(',')
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
            .collect::<Result<_, _>>()?,
    };
    let (traces, extract_s) = load(dir, &drop)?;
    let mut params = TrainParams::default();
    if let Some(l2) = l2 {
        params.l2 = l2;
    }
    let mut users: Vec<String> = traces.iter().map(|t| t.user.clone()).collect();
    users.sort();
    users.dedup();
    let mut out = String::new();
    let total_windows: usize = traces.iter().map(|t| t.features.len()).sum();
    let _ = writeln!(
        out,
        "## Phone placement, leave-one-user-out ({} Oxford traces, {} users, {} windows of 5.12 s every 1.28 s)\n",
        traces.len(),
        users.len(),
        total_windows
    );
    let mut confusion = [[0usize; CLASSES]; CLASSES];
    let mut trace_confusion = [[0usize; CLASSES]; CLASSES];
    let (mut ok_w, mut ok_s, mut ok_t, mut n_w, mut n_t) = (0, 0, 0, 0, 0);
    // Excluding classes the held-out user's training set lacks.
    let (mut ok_w_seen, mut n_w_seen, mut ok_t_seen, mut n_t_seen) = (0, 0, 0, 0);
    let _ = writeln!(
        out,
        "| held-out user | traces | windows | window acc. | smoothed acc. | trace acc. (vote) | classes missing from training |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|");
    let mut trace_lines = String::new();
    for user in &users {
        let train_set = labelled(traces.iter().filter(|t| &t.user != user));
        let model = train(&train_set, &params, Vec::new()).map_err(|e| e.to_string())?;
        let mut seen = [false; CLASSES];
        for (_, p) in &train_set {
            seen[p.index()] = true;
        }
        let missing: Vec<&str> = Placement::ALL
            .iter()
            .filter(|p| !seen[p.index()])
            .filter(|p| traces.iter().any(|t| &t.user == user && t.label == **p))
            .map(|p| p.name())
            .collect();
        let (mut uw, mut us, mut ut, mut unw, mut unt) = (0, 0, 0, 0, 0);
        for t in traces.iter().filter(|t| &t.user == user) {
            let (raw, smooth) = predictions(&model, &t.features);
            let truth = t.label.index();
            let ok = raw.iter().filter(|p| **p == t.label).count();
            let oks = smooth.iter().filter(|p| **p == t.label).count();
            for p in &raw {
                confusion[truth][p.index()] += 1;
            }
            uw += ok;
            us += oks;
            unw += raw.len();
            let v = vote(&raw);
            if let Some(v) = v {
                trace_confusion[truth][v.index()] += 1;
                unt += 1;
                ut += (v == t.label) as usize;
                if seen[truth] {
                    n_t_seen += 1;
                    ok_t_seen += (v == t.label) as usize;
                }
            }
            if seen[truth] {
                n_w_seen += raw.len();
                ok_w_seen += ok;
            }
            let _ = writeln!(
                trace_lines,
                "| {} | {} | {} | {} | {} |",
                t.name,
                t.label,
                v.map(|p| p.name()).unwrap_or("–"),
                pct(ok, raw.len()),
                pct(oks, smooth.len())
            );
        }
        let _ = writeln!(
            out,
            "| {user} | {} | {unw} | {} | {} | {} | {} |",
            traces.iter().filter(|t| &t.user == user).count(),
            pct(uw, unw),
            pct(us, unw),
            pct(ut, unt),
            if missing.is_empty() {
                "–".to_string()
            } else {
                missing.join(", ")
            }
        );
        ok_w += uw;
        ok_s += us;
        ok_t += ut;
        n_w += unw;
        n_t += unt;
    }
    let _ = writeln!(
        out,
        "| **all** | {} | {n_w} | **{}** | **{}** | **{}** | |\n",
        traces.len(),
        pct(ok_w, n_w),
        pct(ok_s, n_w),
        pct(ok_t, n_t)
    );
    if mlp {
        let _ = writeln!(
            out,
            "Comparison, same protocol: one-hidden-layer MLP (16 tanh units, {} bytes of parameters), L2 {}:\n",
            crate::placement_mlp::Mlp::parameter_bytes(),
            params.l2
        );
        let _ = writeln!(
            out,
            "| held-out user | MLP window acc. | MLP trace acc. (vote) |"
        );
        let _ = writeln!(out, "|---|---|---|");
        let (mut ok, mut n, mut okt, mut nt) = (0, 0, 0, 0);
        for user in &users {
            let train_set = labelled(traces.iter().filter(|t| &t.user != user));
            let m = crate::placement_mlp::train(&train_set, params.l2)?;
            let (mut uo, mut un, mut uot, mut unt) = (0, 0, 0, 0);
            for t in traces.iter().filter(|t| &t.user == user) {
                let pred: Vec<Placement> = t.features.iter().map(|f| m.predict(f)).collect();
                uo += pred.iter().filter(|p| **p == t.label).count();
                un += pred.len();
                if let Some(v) = vote(&pred) {
                    unt += 1;
                    uot += (v == t.label) as usize;
                }
            }
            let _ = writeln!(out, "| {user} | {} | {} |", pct(uo, un), pct(uot, unt));
            ok += uo;
            n += un;
            okt += uot;
            nt += unt;
        }
        let _ = writeln!(
            out,
            "| **all** | **{}** | **{}** |\n",
            pct(ok, n),
            pct(okt, nt)
        );
    }
    let _ = writeln!(
        out,
        "Without the held-out traces whose class the training users never recorded: window accuracy {} ({n_w_seen} windows), trace accuracy {} ({n_t_seen} traces).\n",
        pct(ok_w_seen, n_w_seen),
        pct(ok_t_seen, n_t_seen)
    );
    for (title, m) in [
        (
            "Confusion matrix, windows (rows: truth, columns: predicted)",
            &confusion,
        ),
        (
            "Confusion matrix, traces by majority vote",
            &trace_confusion,
        ),
    ] {
        let _ = writeln!(out, "{title}:\n");
        let _ = write!(out, "| truth \\ predicted |");
        for p in Placement::ALL {
            let _ = write!(out, " {p} |");
        }
        let _ = write!(out, " recall |\n|---|");
        for _ in 0..=CLASSES {
            let _ = write!(out, "---|");
        }
        out.push('\n');
        for (i, row) in m.iter().enumerate() {
            let _ = write!(out, "| {} |", Placement::ALL[i]);
            for v in row {
                let _ = write!(out, " {v} |");
            }
            let _ = writeln!(out, " {} |", pct(row[i], row.iter().sum()));
        }
        out.push('\n');
    }
    let _ = writeln!(out, "Per trace (held-out model):\n");
    let _ = writeln!(
        out,
        "| trace | truth | vote | window acc. | smoothed acc. |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|");
    out.push_str(&trace_lines);
    out.push('\n');

    // The model on all traces: size and speed; then the simulator.
    let all = labelled(traces.iter());
    let model =
        train(&all, &params, provenance("(eval)", &traces, &params)).map_err(|e| e.to_string())?;
    let (ns_window, ns_sample, rate) = timing(dir, &model)?;
    let samples: usize = traces.iter().map(|t| t.samples).sum();
    let _ = writeln!(
        out,
        "Model: logistic regression, {FEATURES} features × {CLASSES} classes: {} bytes of parameters (f64), model file {} bytes; classifier state {} bytes (`size_of::<PlacementClassifier>()`, plus the model's comment strings on the heap).",
        model.parameter_bytes(),
        model.to_text().len(),
        std::mem::size_of::<PlacementClassifier>()
    );
    let _ = writeln!(
        out,
        "Cost (this machine, release build): {ns_window:.0} ns per window (features + model), {ns_sample:.0} ns per sample for the whole classifier on a {rate:.0} Hz trace; feature extraction of all {samples} samples took {extract_s:.2} s.\n"
    );

    let _ = writeln!(
        out,
        "### Simulator (information only): model trained on all real traces, simulated walks at 1.3 m/s, 120 s, 3 seeds per placement\n"
    );
    let _ = writeln!(
        out,
        "| simulated placement | class | window acc. | predicted most often |"
    );
    let _ = writeln!(out, "|---|---|---|---|");
    let (mut sok, mut sn) = (0, 0);
    for p in PhonePlacement::ALL {
        let class = Placement::from(p);
        let mut preds = Vec::new();
        for seed in 1..=3u64 {
            let mut sc = PhoneScenario::walk(seed, p, 1.3, 120.0);
            sc.gnss = false;
            let sim = simulate_phone(&sc);
            let feats = trace_features(sim.samples.iter().map(|s| (s.t_s, s.accel_mps2)));
            preds.extend(feats.iter().map(|f| predict(&model, f)));
        }
        let ok = preds.iter().filter(|q| **q == class).count();
        sok += ok;
        sn += preds.len();
        let _ = writeln!(
            out,
            "| {p:?} | {class} | {} | {} |",
            pct(ok, preds.len()),
            vote(&preds).map(|q| q.name()).unwrap_or("–")
        );
    }
    let _ = writeln!(out, "| **all** | | **{}** | |", pct(sok, sn));
    Ok(out)
}
