//! The learned odometry (`stridekit_core::odometry`) on the real indoor walks, in the
//! same table as the PDR (`eval pdr --data DIR`), and its training on them
//! (`stridekit train odometry --android DIR`).
//!
//! Labels: the velocity between consecutive waypoints (straight legs at constant
//! speed: the waypoints interpolated linearly). The map's axes are not the engine's
//! ENU, and the direction labels are expressed in the engine's stabilised frame, so
//! each training walk's waypoints are first turned into the engine's frame by the
//! rotation that best maps them onto the track of the current model (the shipped,
//! simulator-trained one) at the waypoint times: the frame alignment RoNIN does with
//! its start orientation, done here from the track because there is no orientation
//! truth. Speeds do not depend on it. Training is leave one floor out: each floor is
//! scored by a model fitted on the other floors' walks only.

use crate::odometry::train::{fit_model, labelled_windows, samples_of, LabelledWindow, RecTruth};
use stridekit_core::odometry::{
    OdometryConfig, OdometryModel, PhoneOdometry, PipelineParams, PlacementSource,
};
use stridekit_core::placement::Placement;
use stridekit_formats::InertialRecording;

use crate::pdr::metrics::{apply_rigid, best_rigid, evaluate, track_at, TrackPoint};
use crate::pdr::real::{floors, MethodResult};
use crate::pdr::walks::Walk;

/// The odometry's track over a walk (position at each window centre), starting at
/// the origin at the first sample.
pub fn track(w: &Walk, model: &OdometryModel) -> Result<Vec<TrackPoint>, String> {
    let cfg = OdometryConfig {
        placement: PlacementSource::Unknown,
        ..OdometryConfig::default()
    };
    let mut eng = PhoneOdometry::new(cfg, model.clone()).map_err(|e| e.to_string())?;
    let mut out = vec![TrackPoint {
        t_s: w.rec.samples.first().map_or(0.0, |s| s.t_s),
        ..Default::default()
    }];
    out.extend(
        eng.push_batch(&samples_of(&w.rec))
            .estimates
            .iter()
            .map(|e| TrackPoint {
                t_s: e.t_s,
                x_m: e.position_m[0],
                y_m: e.position_m[1],
                distance_m: 0.0,
            }),
    );
    Ok(out)
}

/// Labelled windows of one walk, its waypoints aligned to `model`'s track.
fn windows(
    w: &Walk,
    model: &OdometryModel,
    params: PipelineParams,
) -> Result<Vec<LabelledWindow>, String> {
    let t = track(w, model)?;
    let wp = &w.rec.truth;
    let est: Vec<(f64, f64)> = wp
        .iter()
        .map(|p| {
            let q = track_at(&t, p.0);
            (q.0, q.1)
        })
        .collect();
    let truth: Vec<(f64, f64)> = wp.iter().map(|p| (p.1, p.2)).collect();
    let to_engine = best_rigid(&truth, &est);
    // The walk's waypoints turned into the engine's frame, linearly interpolated.
    let aligned = InertialRecording {
        truth: wp
            .iter()
            .zip(&truth)
            .map(|(p, q)| {
                let a = apply_rigid(*q, to_engine);
                (p.0, a.0, a.1)
            })
            .collect(),
        ..Default::default()
    };
    // Only windows inside the waypoint span have labels.
    let (t0, t1) = (wp[0].0, wp[wp.len() - 1].0);
    Ok(labelled_windows(
        &samples_of(&w.rec),
        &RecTruth(&aligned),
        Some(Placement::InHand),
        params,
    )
    .into_iter()
    .filter(|x| x.features.t_start_s >= t0 && x.features.t_end_s <= t1)
    .collect())
}

/// Fit a model on `walks` (all hand-held: the general and the in-hand regressors).
pub fn train(
    walks: &[&Walk],
    params: PipelineParams,
    comments: Vec<String>,
) -> Result<OdometryModel, String> {
    let shipped = OdometryModel::shipped();
    let mut all = Vec::new();
    for w in walks {
        all.extend(windows(w, &shipped, params)?);
    }
    fit_model(&all, params, comments).ok_or_else(|| "too few labelled windows to fit".to_string())
}

fn score(
    name: &str,
    walks: &[Walk],
    model_of: impl Fn(&Walk) -> Option<OdometryModel>,
) -> Result<MethodResult, String> {
    let mut by_walk = Vec::new();
    let pb = crate::progress::bar(walks.len(), name);
    for w in walks {
        pb.inc(1);
        let Some(model) = model_of(w) else { continue };
        let t = track(w, &model)?;
        if let Some(m) = evaluate(&t, &w.rec.truth) {
            by_walk.push((w.floor.clone(), m));
        }
    }
    pb.finish_and_clear();
    Ok(MethodResult {
        name: name.into(),
        by_walk,
    })
}

/// The odometry rows of `eval pdr --data`: the shipped (simulator-trained) model and
/// the model trained on the real walks, leave one floor out.
pub fn methods(walks: &[Walk]) -> Result<Vec<MethodResult>, String> {
    let params = PipelineParams::default();
    let mut lofo = std::collections::BTreeMap::new();
    let fl = floors(walks);
    let pb = crate::progress::bar(fl.len(), "training odometry (leave one floor out)");
    for f in fl {
        let train_walks: Vec<&Walk> = walks.iter().filter(|w| w.floor != f).collect();
        // A folder with one floor has nothing to train on for it: its walks are left
        // out of the leave-one-floor-out row.
        if let Ok(m) = train(&train_walks, params, Vec::new()) {
            lofo.insert(f.clone(), m);
        }
        pb.inc(1);
    }
    pb.finish_and_clear();
    let shipped = OdometryModel::shipped();
    Ok(vec![
        score(
            "learned odometry, shipped model (simulator-trained)",
            walks,
            |_| Some(shipped.clone()),
        )?,
        score(
            "learned odometry, trained on these walks leave-one-floor-out",
            walks,
            |w| lofo.get(&w.floor).cloned(),
        )?,
    ])
}
