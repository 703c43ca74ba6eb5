//! `stridekit eval pdr`: pedestrian dead reckoning on the phone simulator. GNSS is
//! available for the first 5 minutes of a 15-minute walk, then lost; the error of the
//! final position is reported as a share of the distance walked without GNSS.

use std::fmt::Write as _;

use stridekit_core::ahrs::ImuSample;
use stridekit_core::geo::LocalFrame;
use stridekit_core::pace::GnssFix;
use stridekit_core::pdr::{NavigatorConfig, PhoneNavigator};
use stridekit_core::sim::phone::{simulate_phone, PhonePlacement, PhoneScenario};

/// GNSS is lost at this time, s, and the walk ends at `WALK_S`.
const OUTAGE_START_S: f64 = 300.0;
const WALK_S: f64 = 900.0;

/// One placement and seed: (steps detected, true steps, distance error %, end error %).
fn run(placement: PhonePlacement, seed: u64) -> Result<(u64, usize, f64, f64), String> {
    let mut sc = PhoneScenario::walk(seed, placement, 1.4, WALK_S);
    sc.gnss_outages = vec![(OUTAGE_START_S, WALK_S)];
    let sim = simulate_phone(&sc);
    let frame = LocalFrame::new(47.0, 8.0, 0.0);
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).map_err(|e| e.to_string())?;
    let mut fi = 0;
    for s in &sim.samples {
        while fi < sim.fixes.len() && sim.fixes[fi].t_s <= s.t_s {
            let f = sim.fixes[fi];
            let (lat, lon) = frame.to_geodetic(f.east_m, f.north_m);
            nav.push_fix(&GnssFix::new(f.t_s, lat, lon).with_accuracy(f.accuracy_m))
                .map_err(|e| e.to_string())?;
            fi += 1;
        }
        nav.push_imu(&ImuSample {
            t_s: s.t_s,
            gyro_rads: s.gyro_radps,
            accel_mps2: s.accel_mps2,
            mag_ut: Some(s.mag_ut),
        })
        .map_err(|e| e.to_string())?;
    }
    let e = nav.estimate();
    let end = sim.truth.last().ok_or("empty simulation")?;
    let first = sim.fixes.first().ok_or("no GNSS fix")?;
    let (te, tn) = (end.east_m - first.east_m, end.north_m - first.north_m);
    let walked = end.distance_m - sim.truth_at(OUTAGE_START_S).distance_m;
    let pos_err = (e.east_m - te).hypot(e.north_m - tn);
    let dist_err = 100.0 * (e.distance_m - end.distance_m) / end.distance_m;
    Ok((e.steps, sim.steps.len(), dist_err, 100.0 * pos_err / walked))
}

pub fn report(seeds: u64) -> Result<String, String> {
    let placements = [
        PhonePlacement::InHand,
        PhonePlacement::FrontPocket,
        PhonePlacement::BackPocket,
        PhonePlacement::Bag,
        PhonePlacement::NeckPouch,
        PhonePlacement::Armband,
        PhonePlacement::SwingingArm,
    ];
    let mut out = String::new();
    let _ = writeln!(
        out,
        "PDR on the phone simulator: 15-minute walk at 1.4 m/s, GNSS for the first 5 minutes, then lost; {seeds} seeds per placement.\n"
    );
    let _ = writeln!(out, "| placement | steps detected / true | distance error | end-point error, % of the 10-minute outage walk (median / worst) |");
    let _ = writeln!(out, "|---|---|---|---|");
    let mut all = Vec::new();
    for (k, p) in placements.iter().enumerate() {
        let mut errs = Vec::new();
        let (mut steps, mut truth, mut dist) = (0u64, 0usize, 0.0);
        for s in 0..seeds {
            let (st, tr, de, pe) = run(*p, 100 + 10 * k as u64 + s)?;
            steps += st;
            truth += tr;
            dist += de.abs();
            errs.push(pe);
        }
        errs.sort_by(f64::total_cmp);
        all.extend(errs.iter().copied());
        let _ = writeln!(
            out,
            "| {p:?} | {steps} / {truth} | {:.2} % | {:.1} % / {:.1} % |",
            dist / seeds as f64,
            errs[errs.len() / 2],
            errs[errs.len() - 1]
        );
    }
    all.sort_by(f64::total_cmp);
    let _ = writeln!(
        out,
        "| **all** | | | {:.1} % / {:.1} % |",
        all[all.len() / 2],
        all[all.len() - 1]
    );
    Ok(out)
}
