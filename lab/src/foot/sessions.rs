//! Leave-one-session-out for `stridekit eval foot`: a session is a recording date
//! (the first 10 characters of a trial name, `YYYY-MM-DD`). Trials of one session
//! share subject, shoe, mounting and day; a model that has seen other trials of the
//! same session (the 6-fold CV) is optimistic about a new recording.
//!
//! [`Loso`]: each trial's SVM trained on the OTHER sessions only (same code as `train
//! zupt`); the other detectors' settings in that table were chosen once on the
//! training split (which holds trials of every session), said in the table.
//! [`DetectorLoso`]: the default detector's constants re-chosen without the session.

use stridekit_core::foot::{SvmModel, WindowStats};

use crate::foot::eval::{median, Outcome, Trial};
use crate::foot::train_zupt;

/// The session of a trial: its recording date.
pub fn session_of(name: &str) -> &str {
    name.get(..10).unwrap_or(name)
}

/// One SVM per session, trained on every other session; `None` for a session with
/// nothing else to train on (a folder of one session).
pub struct Loso {
    sessions: Vec<String>,
    models: Vec<Option<SvmModel>>,
}

impl Loso {
    pub fn train(trials: &[Trial], stats: &[Vec<(usize, WindowStats)>]) -> Result<Self, String> {
        let mut sessions: Vec<String> = trials
            .iter()
            .map(|t| session_of(&t.rec.name).to_string())
            .collect();
        sessions.dedup();
        let p = train_zupt::TrainParams::default();
        let mut models = Vec::new();
        for s in &sessions {
            let mut data = Vec::new();
            for (t, st) in trials.iter().zip(stats) {
                if session_of(&t.rec.name) != s {
                    data.extend(train_zupt::labelled_from(t, st)?);
                }
            }
            let others = trials.iter().any(|t| session_of(&t.rec.name) != s);
            models.push(if others {
                Some(train_zupt::train(
                    &data,
                    &p,
                    vec![format!("leave-one-session-out: without {s}")],
                )?)
            } else {
                None
            });
        }
        Ok(Self { sessions, models })
    }

    /// Whether there is more than one session (then every session has a model).
    pub fn available(&self) -> bool {
        self.models.iter().any(Option::is_some)
    }

    /// The model that never saw `trial`'s session; `None` when every trial is of
    /// that session.
    pub fn model_for(&self, trial: &str) -> Option<&SvmModel> {
        let s = session_of(trial);
        let i = self.sessions.iter().position(|x| x == s)?;
        self.models[i].as_ref()
    }
}

/// Median horizontal RMSE per session and over all trials, per method.
pub fn session_table(
    trials: &[Trial],
    names: &[String],
    results: &[Vec<Outcome>],
    loso: &Loso,
) -> String {
    let mut out = String::from(
        "\nPer session (recording date): median horizontal RMSE, m. Columns `(leave one session out)`: the SVM of each trial trained on the other sessions only; `(6-fold CV)`: trained on the other folds, which hold trials of the same session; the other detectors' settings and the filter defaults were chosen on the training split (all sessions), so they are not leave-one-session-out.\n\n| method |",
    );
    for s in &loso.sessions {
        let n = trials
            .iter()
            .filter(|t| session_of(&t.rec.name) == s)
            .count();
        out.push_str(&format!(" {s} ({n}) |"));
    }
    out.push_str(" all |\n|---|");
    for _ in &loso.sessions {
        out.push_str("---|");
    }
    out.push_str("---|\n");
    for (j, name) in names.iter().enumerate() {
        out.push_str(&format!("| {name} |"));
        for s in &loso.sessions {
            let v: Vec<f64> = trials
                .iter()
                .zip(results)
                .filter(|(t, _)| session_of(&t.rec.name) == s)
                .map(|(_, r)| r[j].rmse_h_m)
                .collect();
            out.push_str(&format!(" {:.3} |", median(v)));
        }
        out.push_str(&format!(
            " {:.3} |\n",
            median(results.iter().map(|r| r[j].rmse_h_m).collect::<Vec<f64>>())
        ));
    }
    out
}

/// Leave-one-session-out for the default detector, the adaptive SHOE: its constants
/// (γ₀, p₀, k) are what the default navigator learned from these trials
/// (`eval foot --tune-adaptive-shoe`, training split). Every point of that tuner's
/// grid is replayed on every trial once; for each session the point with the best
/// objective (geometric mean of the horizontal RMSE) on the OTHER sessions' trials
/// is chosen, and the session's trials are scored with it.
pub struct DetectorLoso {
    /// (γ₀, p₀ m/s², k) of each grid point.
    grid: Vec<(f64, f64, f64)>,
    /// Horizontal RMSE per grid point per trial, m.
    rmse: Vec<Vec<f64>>,
    /// The session of each trial.
    session: Vec<String>,
    names: Vec<String>,
}

impl DetectorLoso {
    /// Replays the tuner's grid on every trial (the device profile of `eval foot`).
    pub fn measure(trials: &[Trial]) -> Result<Self, String> {
        use crate::foot::eval::{base_config, replay, score, Method};
        use crate::foot::tune_shoe::{adaptive, par_map, G0_GRID, K_GRID, P0_GRID_MPS2};
        let session: Vec<String> = trials
            .iter()
            .map(|t| session_of(&t.rec.name).to_string())
            .collect();
        let mut grid = Vec::new();
        // One session: nothing to leave out, nothing to replay.
        let several = session.iter().any(|s| s != &session[0]);
        for g0 in G0_GRID.iter().copied().filter(|_| several) {
            for p0 in P0_GRID_MPS2 {
                for k in K_GRID {
                    grid.push((g0, p0, k));
                }
            }
        }
        let mut rmse = Vec::with_capacity(grid.len());
        let pb = crate::progress::bar(grid.len(), "eval foot: leave one session out");
        for &(g0, p0, k) in &grid {
            pb.inc(1);
            let m = Method {
                name: "loso".into(),
                config: stridekit_core::foot::FootConfig {
                    detector: adaptive(g0, p0, k),
                    ..base_config()
                },
                labels: None,
            };
            let row = par_map(trials, |t| replay(t, &m).map(|e| score(t, &e).rmse_h_m))
                .into_iter()
                .collect::<Result<Vec<f64>, String>>()?;
            rmse.push(row);
        }
        pb.finish_and_clear();
        Ok(Self {
            grid,
            rmse,
            session,
            names: trials.iter().map(|t| t.rec.name.clone()).collect(),
        })
    }

    /// The grid point with the best objective over the trials `keep` says yes to.
    fn best(&self, keep: impl Fn(usize) -> bool) -> Option<usize> {
        let objective = |row: &Vec<f64>| {
            let v: Vec<f64> = (0..row.len())
                .filter(|&i| keep(i))
                .map(|i| row[i])
                .collect();
            if v.is_empty() {
                return f64::INFINITY;
            }
            (v.iter().map(|x| x.max(1e-6).ln()).sum::<f64>() / v.len() as f64).exp()
        };
        let scores: Vec<f64> = self.rmse.iter().map(objective).collect();
        (0..scores.len())
            .filter(|&j| scores[j].is_finite())
            .min_by(|&a, &b| scores[a].total_cmp(&scores[b]))
    }

    /// The grid point of the shipped defaults, when the grid holds it.
    fn shipped(&self) -> Option<usize> {
        let d = stridekit_core::foot::AdaptiveShoe::default();
        self.grid.iter().position(|&(g0, p0, k)| {
            g0 == d.shoe.threshold && p0 == d.ref_peak_mps2 && k == d.exponent
        })
    }

    /// The markdown section: per held-out session the constants chosen without it and
    /// its trials' median / worst, then every trial scored without its session beside
    /// the shipped defaults and a refit on all trials.
    pub fn table(&self) -> String {
        // "–" where there is no figure (the shipped point outside the grid).
        let m = |v: f64| {
            if v.is_finite() {
                format!("{v:.3}")
            } else {
                "–".to_string()
            }
        };
        let fmt = |p: Option<usize>| {
            p.map_or("–".to_string(), |j| {
                let (g0, p0, k) = self.grid[j];
                format!("γ₀ {g0:.1e}, p₀ {p0} m/s², k {k}")
            })
        };
        let worst = |idx: &[usize], col: &dyn Fn(usize) -> f64| -> (f64, String) {
            idx.iter()
                .map(|&i| (col(i), self.names[i].clone()))
                .filter(|(v, _)| v.is_finite())
                .max_by(|a, b| a.0.total_cmp(&b.0))
                .unwrap_or((f64::NAN, "–".into()))
        };
        let mut sessions = self.session.clone();
        sessions.dedup();
        if self.grid.is_empty() {
            return "\nLeave one session out, the default detector (adaptive SHOE): the folder holds one recording session, so there is none to leave out.\n".into();
        }
        let n = self.names.len();
        let shipped = self.shipped();
        let all = self.best(|_| true);
        let mut out = format!(
            "\nLeave one session out, the default detector (adaptive SHOE). What the default navigator learned from these trials is the detector's three constants γ₀, p₀, k (chosen by `eval foot --tune-adaptive-shoe` on the training split); it uses no trained model (the SVM is not the default) and no accelerometer alignment (none is applied here); the device profile (gyro timing, gyroscope range) and the filter's noise constants are not refitted. Per held-out session: γ₀, p₀, k re-chosen on the other sessions' trials with the tuner's grid ({} points) and objective (geometric mean of the horizontal RMSE), then the session's trials replayed with them. Horizontal RMSE after the best rotation about the vertical + translation, m.\n\n| held-out session | trials | constants chosen without it | median | worst | shipped defaults: median | worst |\n|---|---|---|---|---|---|---|\n",
            self.grid.len()
        );
        let mut loso = vec![f64::NAN; n];
        for s in &sessions {
            let idx: Vec<usize> = (0..n).filter(|&i| &self.session[i] == s).collect();
            let others = (0..n).any(|i| &self.session[i] != s);
            let pick = if others {
                self.best(|i| &self.session[i] != s)
            } else {
                None
            };
            for &i in &idx {
                loso[i] = pick.map_or(f64::NAN, |j| self.rmse[j][i]);
            }
            let held: Vec<f64> = idx.iter().map(|&i| loso[i]).collect();
            let (w, wn) = worst(&idx, &|i| loso[i]);
            let sh: Vec<f64> = idx
                .iter()
                .map(|&i| shipped.map_or(f64::NAN, |j| self.rmse[j][i]))
                .collect();
            let (sw, swn) = worst(&idx, &|i| shipped.map_or(f64::NAN, |j| self.rmse[j][i]));
            out.push_str(&format!(
                "| {s} | {} | {} | {} | {} ({wn}) | {} | {} ({swn}) |\n",
                idx.len(),
                if others {
                    fmt(pick)
                } else {
                    "no other session".into()
                },
                m(median(held)),
                m(w),
                m(median(sh)),
                m(sw),
            ));
        }
        let every: Vec<usize> = (0..n).collect();
        let (lw, lwn) = worst(&every, &|i| loso[i]);
        let col = |p: Option<usize>| -> Vec<f64> {
            (0..n)
                .map(|i| p.map_or(f64::NAN, |j| self.rmse[j][i]))
                .collect()
        };
        let (sw, swn) = worst(&every, &|i| col(shipped)[i]);
        let (aw, awn) = worst(&every, &|i| col(all)[i]);
        out.push_str(&format!(
            "\nAdaptive SHOE over all {n} trials: leave one session out median {} m, worst {} m ({lwn}); shipped defaults (γ₀, p₀, k from the training split, all sessions) median {} m, worst {} m ({swn}); refitted on all {n} trials ({}) median {} m, worst {} m ({awn}).\n",
            m(median(loso.clone())),
            m(lw),
            m(median(col(shipped))),
            m(sw),
            fmt(all),
            m(median(col(all))),
            m(aw),
        ));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_session_is_scored_with_constants_chosen_without_it() {
        // Point 0 is best on session A, point 1 on session B: each session's trials
        // must be scored with the other session's choice.
        let d = DetectorLoso {
            grid: vec![(1.0, 1.0, 1.0), (2.0, 2.0, 2.0)],
            rmse: vec![vec![0.01, 0.02, 0.90], vec![0.50, 0.60, 0.03]],
            session: vec!["A".into(), "A".into(), "B".into()],
            names: vec!["a1".into(), "a2".into(), "b1".into()],
        };
        assert_eq!(d.best(|i| d.session[i] != "A"), Some(1));
        assert_eq!(d.best(|i| d.session[i] != "B"), Some(0));
        let t = d.table();
        assert!(
            t.contains("| A | 2 | γ₀ 2.0e0, p₀ 2 m/s², k 2 | 0.550 | 0.600 (a2) |"),
            "{t}"
        );
        assert!(
            t.contains("| B | 1 | γ₀ 1.0e0, p₀ 1 m/s², k 1 | 0.900 | 0.900 (b1) |"),
            "{t}"
        );
        assert!(
            t.contains("leave one session out median 0.600 m, worst 0.900 m (b1)"),
            "{t}"
        );
        assert!(!t.contains("NaN"), "{t}");
    }
}
