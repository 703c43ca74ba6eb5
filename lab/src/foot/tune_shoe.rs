//! `stridekit eval foot --tune-adaptive-shoe` (also the last part of `--tune`): on
//! the TRAINING split only (even positions in name order), with the device profile,
//! the gyro-timing model and the adaptive SHOE detector's γ₀, p₀, k by a full grid.
//! Objective: the geometric mean over the training trials of the horizontal RMSE
//! after alignment (the metric; every trial counts, none dominates).

use std::path::Path;

use stridekit_core::foot::{
    AdaptiveShoe, FootConfig, GyroTiming, ShoeDetector, ZeroVelocityDetector,
};

use crate::foot::eval::{base_config, load_with_info, median, replay, score, Method, Trial};

/// The grid of the adaptive SHOE's constants: γ₀, p₀ (m/s²) and k. Leave-one-session-out
/// in `eval foot` refits on the same grid (`sessions::DetectorLoso`).
pub const G0_GRID: [f64; 5] = [2.5e3, 5e3, 1e4, 2e4, 4e4];
pub const P0_GRID_MPS2: [f64; 4] = [10.0, 15.0, 20.0, 30.0];
pub const K_GRID: [f64; 6] = [2.0, 2.5, 3.0, 3.5, 4.0, 5.0];

/// `f` over `items` on two threads (the machine is shared), results in order.
pub(crate) fn par_map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let chunk = items.len().div_ceil(2).max(1);
    std::thread::scope(|s| {
        let hs: Vec<_> = items
            .chunks(chunk)
            .map(|c| s.spawn(|| c.iter().map(&f).collect::<Vec<R>>()))
            .collect();
        hs.into_iter()
            .flat_map(|h| h.join().expect("worker"))
            .collect()
    })
}

/// (geometric mean, median) of the horizontal RMSE over `trials`.
fn objective(trials: &[Trial], m: &Method) -> Result<(f64, f64), String> {
    let r = par_map(trials, |t| replay(t, m).map(|e| score(t, &e).rmse_h_m))
        .into_iter()
        .collect::<Result<Vec<f64>, String>>()?;
    let geo = (r.iter().map(|x| x.max(1e-6).ln()).sum::<f64>() / r.len().max(1) as f64).exp();
    Ok((geo, median(r)))
}

pub(crate) fn adaptive(g0: f64, p0: f64, k: f64) -> ZeroVelocityDetector {
    ZeroVelocityDetector::AdaptiveShoe(AdaptiveShoe {
        shoe: ShoeDetector {
            threshold: g0,
            ..ShoeDetector::default()
        },
        ref_peak_mps2: p0,
        exponent: k,
    })
}

pub fn run(dir: &Path) -> Result<String, String> {
    let train: Vec<Trial> = load_with_info(dir)?
        .into_iter()
        .enumerate()
        .filter(|(i, _)| i % 2 == 0)
        .map(|(_, (t, _))| t)
        .collect();
    let mut out = format!(
        "Adaptive SHOE and gyro timing on the training split ({} trials; objective: geometric mean of the horizontal RMSE, m; median in brackets).\n\n",
        train.len()
    );
    // 1. Gyro timing, with the oracle labels (the filter alone) and with the
    //    previous default parameters of the detector.
    for (labels, what) in [
        (Some("best"), "oracle labels"),
        (None, "adaptive shoe (defaults)"),
    ] {
        for timing in [GyroTiming::Instantaneous, GyroTiming::IntervalMean] {
            let m = Method {
                name: what.into(),
                config: FootConfig {
                    gyro_timing: timing,
                    ..base_config()
                },
                labels: labels.map(String::from),
            };
            let (g, md) = objective(&train, &m)?;
            out.push_str(&format!("{what}, gyro {timing:?}: {g:.4} ({md:.4})\n"));
        }
    }
    // 2. Gyro timing × γ₀ × p₀ × k, jointly, with the device profile.
    let mut rows = Vec::new();
    for timing in [GyroTiming::Instantaneous, GyroTiming::IntervalMean] {
        for g0 in G0_GRID {
            for p0 in P0_GRID_MPS2 {
                for k in K_GRID {
                    let m = Method {
                        name: "tune".into(),
                        config: FootConfig {
                            detector: adaptive(g0, p0, k),
                            gyro_timing: timing,
                            ..base_config()
                        },
                        labels: None,
                    };
                    let (g, md) = objective(&train, &m)?;
                    rows.push((g, md, timing, g0, p0, k));
                }
            }
        }
    }
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    out.push_str(&format!(
        "\nadaptive shoe, gyro timing × γ₀ × p₀ × k, best 12 of {}:\n",
        rows.len()
    ));
    for (g, md, timing, g0, p0, k) in rows.iter().take(12) {
        out.push_str(&format!(
            "gyro {timing:?}, γ₀ {g0:e}, p₀ {p0} m/s², k {k}: {g:.4} ({md:.4})\n"
        ));
    }
    for timing in [GyroTiming::Instantaneous, GyroTiming::IntervalMean] {
        if let Some((g, md, _, g0, p0, k)) = rows.iter().find(|r| r.2 == timing) {
            out.push_str(&format!(
                "best with gyro {timing:?}: γ₀ {g0:e}, p₀ {p0} m/s², k {k}: {g:.4} ({md:.4})\n"
            ));
        }
    }
    let (g, _, timing, g0, p0, k) = rows[0];
    out.push_str(&format!(
        "→ gyro {timing:?}, adaptive shoe γ₀ {g0:e}, p₀ {p0} m/s², k {k}: {g:.4}\n"
    ));
    Ok(out)
}
