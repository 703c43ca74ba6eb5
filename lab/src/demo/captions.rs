//! The demo report's captions: what each chart shows, with the figures measured on
//! the run ([`Facts`]), and what the methods are.

use super::facts::{Facts, FAST_MPS};
use super::{NAMES, PACE_MIN_MPS};
use crate::replay::pace::min_s;

/// What the methods in the tables and plots are (names as [`NAMES`]).
pub(super) const METHODS_EXPLAINED: &str =
    "Methods: **raw GNSS diff** = distance between consecutive fixes \
over their time (what a naive app shows); **GNSS EMA** = the same, smoothed (exponential moving \
average); **AsPublished** = the pace-fusion method as its paper publishes it (GNSS and pedometer \
blended by a fixed rule); **stridekit (default)** = the SDK's filter (GNSS, cadence and a step \
length learned from GNSS in one Kalman filter, with GNSS outliers rejected).";

pub(super) const METHODS_HTML: &str = "<dl>\
<dt>raw GNSS diff</dt><dd>distance between consecutive fixes over their time: what a naive app shows.</dd>\
<dt>GNSS EMA</dt><dd>the same, smoothed by an exponential moving average.</dd>\
<dt>AsPublished</dt><dd>the pace-fusion method exactly as its paper publishes it: GNSS and the pedometer blended by a fixed rule.</dd>\
<dt>stridekit (default)</dt><dd>the SDK's filter: GNSS, cadence and a step length learned from GNSS in one Kalman filter, GNSS outliers rejected; in outages the speed comes from the steps.</dd>\
</dl>";

/// `4.7` m/s as the captions write speeds.
fn mps(v: f64) -> String {
    format!("{v:.1} m/s")
}

/// Signed percent of `v` against `truth`.
fn pct(v: f64, truth: f64) -> String {
    format!("{:+.0} %", 100.0 * (v - truth) / truth)
}

/// "first" … for the captions.
fn ordinal(k: usize) -> &'static str {
    ["first", "second", "third", "fourth"]
        .get(k)
        .copied()
        .unwrap_or("next")
}

/// The figures of the report with the caption under each: what the chart shows, with
/// the figures measured on this run (`facts`); the treadmill one when the run exported
/// a calibration.
pub(super) fn figures(facts: &Facts, treadmill: bool) -> Vec<(&'static str, String)> {
    let ours = NAMES[3];
    let pe = &facts.pace_error;
    let mut f = vec![
        (
            "pace.svg",
            format!(
                "Pace as a watch shows it: the truth, the raw GNSS diff pace (grey dots: the spikes a \
                 naive app shows) and {ours}'s. Shaded: disturbed GNSS (yellow), no GNSS (grey), the \
                 runner stopped (blue). Slower than {} /km (standing) pace is not drawn. Where the \
                 runner runs with GNSS, {ours}'s pace is within {:.0} s/km of the truth half of the \
                 time (raw GNSS diff: {:.0} s/km); without GNSS, {:.0} s/km.",
                min_s(1000.0 / PACE_MIN_MPS),
                pe[3][0],
                pe[0][0],
                pe[3][2],
            ),
        ),
        ("speed.svg", speed_caption(facts)),
        (
            "gnss_weight.svg",
            format!(
                "How much each method's speed rests on GNSS (1) or on the steps (0). AsPublished \
                 leans on GNSS whenever it has it (median weight {:.2} while running); {ours} \
                 learns its step length from GNSS and reports GNSS's share of what is known about \
                 the last minute's pace: while the runner runs, GNSS and the learned steps share it \
                 (median weight {:.2}), and the speed follows the steps between fixes, so GNSS \
                 errors do not reach it; at stops there are no steps and it follows GNSS (median \
                 weight {:.2}). Without GNSS (grey) both run on the steps (median weights {:.2} and \
                 {:.2}).",
                facts.weight_running[0],
                facts.weight_running[1],
                facts.weight_stopped,
                facts.weight_outage[0],
                facts.weight_outage[1],
            ),
        ),
        ("step_length.svg", step_caption(facts)),
        ("track.svg", track_caption(facts)),
    ];
    if treadmill {
        f.push(("treadmill.svg", treadmill_caption(facts)));
    }
    f
}

fn speed_caption(facts: &Facts) -> String {
    let d = &facts.disturbed_rmse;
    let mut s = format!(
        "The same run in m/s with every method, for engineers (GNSS EMA has no value without \
         GNSS). In the disturbed stretches \
         (yellow) GNSS EMA and AsPublished follow the GNSS errors (speed RMSE there {:.2} and \
         {:.2} m/s); {}'s RMSE there is {:.2} m/s. Without GNSS (grey) the speed comes from \
         the steps:",
        d[1], d[2], NAMES[3], d[3]
    );
    for (k, o) in facts.outages.iter().enumerate() {
        s += &format!(
            " in the {} outage ({:.0}–{:.0} min) the truth averages {}, {} {} ({}) and \
             AsPublished {} ({}); at the outage's top speed, {}, {} reads {} ({});",
            ordinal(k),
            o.start_min,
            o.end_min,
            mps(o.truth_mps),
            NAMES[3],
            mps(o.ours_mps),
            pct(o.ours_mps, o.truth_mps),
            mps(o.published_mps),
            pct(o.published_mps, o.truth_mps),
            mps(o.top_truth_mps),
            NAMES[3],
            mps(o.top_ours_mps),
            pct(o.top_ours_mps, o.top_truth_mps),
        );
    }
    s.pop();
    s += ". Where the runner goes faster than anything the step length was learned at, the \
          steps are read short (step length chart).";
    s
}

fn step_caption(facts: &Facts) -> String {
    let mut s = format!(
        "The step length {} learns from GNSS while it is good (a line against cadence), against \
         the truth; in outages it carries the speed:",
        NAMES[3]
    );
    for (k, o) in facts.outages.iter().enumerate() {
        s += &format!(
            " {:.2} m against {:.2} m in the {} ({});",
            o.ours_step_m,
            o.truth_step_m,
            ordinal(k),
            pct(o.ours_step_m, o.truth_step_m)
        );
    }
    s.pop();
    s += ". At stops there are no steps: the truth is not drawn and the learned value is held.";
    s
}

fn track_caption(facts: &Facts) -> String {
    let worst: Vec<String> = facts
        .outages
        .iter()
        .enumerate()
        .map(|(k, o)| {
            if k == 0 {
                format!(
                    "{:.0} m from the truth in the first outage",
                    o.worst_position_m
                )
            } else {
                format!("{:.0} m in the {}", o.worst_position_m, ordinal(k))
            }
        })
        .collect();
    format!(
        "Where the runner was: the GNSS fixes, the truth and {}'s fused position. With GNSS it \
         stays on the truth; without GNSS this input has no compass, so the position goes on in \
         the last direction at the fused speed (the straight lines; at worst {}), and snaps back \
         when GNSS returns.",
        NAMES[3],
        worst.join(" and ")
    )
}

fn treadmill_caption(facts: &Facts) -> String {
    let mut s = String::from(
        "The next session without any GNSS (a treadmill, an indoor track): the same run's steps \
         alone, paced with the step length this run learned from GNSS (exported as a calibration, \
         imported next time) or with the population prior.",
    );
    if let Some(u) = facts.usual {
        s += &format!(
            " At the run's usual paces (slower than {} /km) the truth averages {}: calibrated {} \
             ({}), prior {} ({}), this runner's difference from the population.",
            min_s(1000.0 / FAST_MPS),
            mps(u.truth),
            mps(u.calibrated),
            pct(u.calibrated, u.truth),
            mps(u.prior),
            pct(u.prior, u.truth),
        );
    }
    if let Some(f) = facts.fast {
        s += &format!(
            " In the fast intervals ({} and faster) the truth averages {}: calibrated {} ({}), \
             its line learned at the usual paces extrapolating short; prior {} ({}).",
            mps(FAST_MPS),
            mps(f.truth),
            mps(f.calibrated),
            pct(f.calibrated, f.truth),
            mps(f.prior),
            pct(f.prior, f.truth),
        );
    }
    s + " Walks use the population walking line either way."
}
