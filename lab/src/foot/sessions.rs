//! Leave-one-session-out for `stridekit eval foot`: a session is a recording date
//! (the first 10 characters of a trial name, `YYYY-MM-DD`). Trials of one session
//! share subject, shoe, mounting and day; a model that has seen other trials of the
//! same session (the 6-fold CV) is optimistic about a new recording. Here each
//! trial's SVM is trained on the OTHER sessions only (same code as `train zupt`).
//!
//! Only the SVM is re-trained per fold: the fixed thresholds, the adaptive and SHOE
//! settings and the filter defaults were chosen once on the training split (which
//! holds trials of every session), so their figures here are not
//! leave-one-session-out (said in the table).

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
