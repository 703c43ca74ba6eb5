//! What a sweep measured ([`Report`]: per recording, the unperturbed error and the
//! error under every perturbation) and its rendering as markdown, through one table
//! writer ([`table`]): the summary per perturbation, the worst 5 % of all
//! (recording, perturbation) cases, and one per-recording table per kind.

use std::fmt::Write as _;

use super::kinds::Perturbation;
use super::Engine;
use crate::stats::median;

/// Share of all (recording, perturbation) cases listed as the failure modes.
pub const WORST_SHARE: f64 = 0.05;

/// How an engine's per-recording errors are summarised (its headline statistic).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aggregate {
    Mean,
    Median,
}

impl Aggregate {
    fn name(self) -> &'static str {
        match self {
            Aggregate::Mean => "mean",
            Aggregate::Median => "median",
        }
    }

    pub fn of(self, v: &[f64]) -> f64 {
        let f: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
        match self {
            Aggregate::Mean if f.is_empty() => f64::NAN,
            Aggregate::Mean => f.iter().sum::<f64>() / f.len() as f64,
            Aggregate::Median => median(f),
        }
    }
}

/// One perturbation over every recording.
#[derive(Clone, Debug)]
pub struct Case {
    pub perturbation: Perturbation,
    /// Per recording (NaN: the engine produced nothing to score).
    pub errors: Vec<f64>,
    /// Samples the engine refused, summed over the recordings.
    pub refused: u64,
}

/// A whole sweep of one engine.
#[derive(Clone, Debug)]
pub struct Report {
    pub engine: Engine,
    /// What the error is, with unit (e.g. "total orientation error, RMSE °").
    pub metric: &'static str,
    /// Decimals of the error cells.
    pub decimals: usize,
    pub aggregate: Aggregate,
    pub recordings: Vec<String>,
    /// Unperturbed error per recording.
    pub baseline: Vec<f64>,
    pub cases: Vec<Case>,
    /// Lines printed under the title (what the sweep rests on, what was skipped).
    pub notes: Vec<String>,
}

/// One failure case: recording, perturbation, unperturbed and perturbed error.
#[derive(Clone, Debug)]
pub struct Worst {
    pub recording: String,
    pub perturbation: Perturbation,
    pub baseline: f64,
    pub error: f64,
}

impl Report {
    /// The worst [`WORST_SHARE`] of all cases by the error's growth (a case whose
    /// engine produced nothing ranks first).
    pub fn worst(&self) -> Vec<Worst> {
        let mut all: Vec<Worst> = Vec::new();
        for c in &self.cases {
            for (i, e) in c.errors.iter().enumerate() {
                all.push(Worst {
                    recording: self.recordings[i].clone(),
                    perturbation: c.perturbation,
                    baseline: self.baseline[i],
                    error: *e,
                });
            }
        }
        let growth = |w: &Worst| {
            if w.error.is_finite() {
                w.error - w.baseline
            } else {
                f64::INFINITY
            }
        };
        all.sort_by(|a, b| growth(b).total_cmp(&growth(a)));
        let n = ((all.len() as f64 * WORST_SHARE).ceil() as usize).min(all.len());
        all.truncate(n);
        all
    }
}

/// A markdown table.
pub fn table(header: &[String], rows: &[Vec<String>]) -> String {
    let mut out = format!("| {} |\n|", header.join(" | "));
    for _ in header {
        out.push_str("---|");
    }
    out.push('\n');
    for r in rows {
        let _ = writeln!(out, "| {} |", r.join(" | "));
    }
    out
}

fn cell(x: f64, decimals: usize) -> String {
    if x.is_finite() {
        format!("{x:.decimals$}")
    } else {
        "–".into()
    }
}

fn delta(x: f64, decimals: usize) -> String {
    if x.is_finite() {
        format!("{x:+.decimals$}")
    } else {
        "–".into()
    }
}

/// The report as markdown: the title and notes, the summary per perturbation, the
/// worst cases, and one per-recording table per kind.
pub fn render(r: &Report) -> String {
    let mut out = intro(r);
    let _ = writeln!(out, "Summary:\n");
    out.push_str(&summary_table(r));
    let _ = writeln!(
        out,
        "\nThe worst {:.0} % of the {} (recording, perturbation) cases by Δ (the failure modes):\n",
        WORST_SHARE * 100.0,
        r.cases.len() * r.recordings.len()
    );
    out.push_str(&worst_table(r));
    let mut kinds: Vec<&'static str> = r.cases.iter().map(|c| c.perturbation.kind()).collect();
    kinds.dedup();
    for kind in kinds {
        let _ = writeln!(out, "\nPer recording, {kind}: error (Δ)\n");
        out.push_str(&kind_table(r, kind));
    }
    out
}

/// What the sweep is, then its notes (and a blank line after them).
fn intro(r: &Report) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Perturbation bench, {}: {} recordings × {} perturbations; error = {} per recording, {} over recordings; Δ = perturbed − unperturbed of the same recording. One configuration (the engine's defaults); seeded: every run repeats.\n",
        r.engine.name(),
        r.recordings.len(),
        r.cases.len(),
        r.metric,
        r.aggregate.name(),
    );
    for n in &r.notes {
        let _ = writeln!(out, "{n}");
    }
    if !r.notes.is_empty() {
        out.push('\n');
    }
    out
}

/// The summary: the unperturbed row, then one row per perturbation.
fn summary_table(r: &Report) -> String {
    let (d, agg) = (r.decimals, r.aggregate);
    let header: Vec<String> = [
        "perturbation".to_string(),
        "level".into(),
        format!("{} error", agg.name()),
        format!("{} Δ", agg.name()),
        "worst recording".into(),
        "worst Δ".into(),
        "refused samples".into(),
    ]
    .to_vec();
    let worst_base = r
        .baseline
        .iter()
        .enumerate()
        .filter(|(_, e)| e.is_finite())
        .max_by(|a, b| a.1.total_cmp(b.1));
    let mut rows = vec![vec![
        "none (as recorded)".to_string(),
        String::new(),
        cell(agg.of(&r.baseline), d),
        String::new(),
        worst_base.map_or("–".into(), |(i, e)| {
            format!("{} {}", r.recordings[i], cell(*e, d))
        }),
        String::new(),
        String::new(),
    ]];
    rows.extend(r.cases.iter().map(|c| summary_row(r, c)));
    table(&header, &rows)
}

/// One perturbation's summary row: its error and Δ over the recordings, its worst
/// recording and worst Δ ("no output" when the engine produced nothing), refusals.
fn summary_row(r: &Report, c: &Case) -> Vec<String> {
    let (d, agg) = (r.decimals, r.aggregate);
    let deltas: Vec<f64> = c
        .errors
        .iter()
        .zip(&r.baseline)
        .map(|(e, b)| e - b)
        .collect();
    let worst = c.errors.iter().enumerate().max_by(|a, b| {
        let key = |x: &f64| if x.is_finite() { *x } else { f64::INFINITY };
        key(a.1).total_cmp(&key(b.1))
    });
    let worst_delta = deltas
        .iter()
        .map(|x| if x.is_finite() { *x } else { f64::INFINITY })
        .fold(f64::NEG_INFINITY, f64::max);
    vec![
        c.perturbation.kind().to_string(),
        c.perturbation.level(),
        cell(agg.of(&c.errors), d),
        delta(agg.of(&deltas), d),
        worst.map_or("–".into(), |(i, e)| {
            format!("{} {}", r.recordings[i], cell(*e, d))
        }),
        if worst_delta == f64::INFINITY {
            "no output".into()
        } else {
            delta(worst_delta, d)
        },
        c.refused.to_string(),
    ]
}

/// The worst [`WORST_SHARE`] of the cases ([`Report::worst`]).
fn worst_table(r: &Report) -> String {
    let d = r.decimals;
    let header: Vec<String> = ["recording", "perturbation", "unperturbed", "perturbed", "Δ"]
        .map(String::from)
        .to_vec();
    let rows: Vec<Vec<String>> = r
        .worst()
        .iter()
        .map(|w| {
            vec![
                w.recording.clone(),
                w.perturbation.label(),
                cell(w.baseline, d),
                cell(w.error, d),
                delta(w.error - w.baseline, d),
            ]
        })
        .collect();
    table(&header, &rows)
}

/// Per recording, the perturbations of one kind: error (Δ) at every level.
fn kind_table(r: &Report, kind: &str) -> String {
    let d = r.decimals;
    let cases: Vec<&Case> = r
        .cases
        .iter()
        .filter(|c| c.perturbation.kind() == kind)
        .collect();
    let mut header = vec!["recording".to_string(), "unperturbed".into()];
    header.extend(cases.iter().map(|c| c.perturbation.level()));
    let rows: Vec<Vec<String>> = r
        .recordings
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let mut row = vec![name.clone(), cell(r.baseline[i], d)];
            row.extend(cases.iter().map(|c| {
                let e = c.errors[i];
                format!("{} ({})", cell(e, d), delta(e - r.baseline[i], d))
            }));
            row
        })
        .collect();
    table(&header, &rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_worst_cases_rank_by_growth_and_a_silent_engine_first() {
        let r = Report {
            engine: Engine::Orientation,
            metric: "x",
            decimals: 2,
            aggregate: Aggregate::Mean,
            recordings: (0..10).map(|i| format!("r{i}")).collect(),
            baseline: vec![1.0; 10],
            cases: vec![
                Case {
                    perturbation: Perturbation::Jitter { share: 0.1 },
                    errors: (0..10).map(|i| 1.0 + i as f64 * 0.1).collect(),
                    refused: 0,
                },
                Case {
                    perturbation: Perturbation::ClipAccel { g: 2.0 },
                    errors: (0..10)
                        .map(|i| if i == 3 { f64::NAN } else { 1.0 })
                        .collect(),
                    refused: 5,
                },
            ],
            notes: vec![],
        };
        let w = r.worst();
        assert_eq!(w.len(), 1);
        assert_eq!(w[0].recording, "r3");
        let text = render(&r);
        assert!(text.contains("| r9 | 1.00 | 1.90 (+0.90) |"), "{text}");
        assert!(text.contains("no output"));
    }
}
