//! The map engine (`MapNavigator`): walls keep a track with a wrong heading in its
//! corridor, no plan is the navigator unchanged, a snapshot resumes bit for bit, the
//! same seed gives the same track, and bad starts, fixes and plans are refused or
//! survived as documented.

use std::sync::Arc;

use stridekit_core::ahrs::ImuSample;
use stridekit_core::map::{
    Declination, FloorPlan, MapConfig, MapError, MapEstimate, MapFix, MapNavigator, PlanGeometry,
    Polygon,
};
use stridekit_core::pdr::{NavigatorConfig, PhoneNavigator};
use stridekit_sim::phone::{simulate_phone, PhonePlacement, PhoneScenario, SimulatedPhone};

/// A straight walk (no turns) of `seconds` with the phone in hand, 100 Hz.
fn straight_walk(seconds: f64) -> SimulatedPhone {
    let mut sc = PhoneScenario::walk(21, PhonePlacement::InHand, 1.3, seconds);
    sc.turns = Some(Vec::new());
    sc.gnss = false;
    simulate_phone(&sc)
}

fn imu(sim: &SimulatedPhone) -> Vec<ImuSample> {
    sim.samples.iter().map(ImuSample::from).collect()
}

/// The true path every 2 s.
fn path(sim: &SimulatedPhone) -> Vec<[f64; 2]> {
    let mut p: Vec<[f64; 2]> = sim
        .truth
        .iter()
        .step_by(200)
        .map(|t| [t.east_m, t.north_m])
        .collect();
    let last = sim.truth[sim.truth.len() - 1];
    let q = p[p.len() - 1];
    if (q[0] - last.east_m).hypot(q[1] - last.north_m) > 0.5 {
        p.push([last.east_m, last.north_m]);
    }
    p
}

/// A corridor 3 m wide along the walk's true path (5 m beyond each end).
fn corridor_plan(sim: &SimulatedPhone) -> FloorPlan {
    let mut p = path(sim);
    let ext = |a: [f64; 2], b: [f64; 2]| {
        let (dx, dy) = (a[0] - b[0], a[1] - b[1]);
        let l = dx.hypot(dy);
        [a[0] + 5.0 * dx / l, a[1] + 5.0 * dy / l]
    };
    let (n, first) = (p.len(), ext(p[0], p[1]));
    let last = ext(p[n - 1], p[n - 2]);
    p.insert(0, first);
    p.push(last);
    // Offset each vertex by ±1.5 m along the normal of its neighbours' chord.
    let side = |k: f64| -> Vec<[f64; 2]> {
        (0..p.len())
            .map(|i| {
                let (a, b) = (p[i.saturating_sub(1)], p[(i + 1).min(p.len() - 1)]);
                let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                let l = dx.hypot(dy);
                [p[i][0] - k * dy / l, p[i][1] + k * dx / l]
            })
            .collect()
    };
    let mut ring = side(1.5);
    ring.extend(side(-1.5).into_iter().rev());
    ring.push(ring[0]);
    FloorPlan::new(
        &PlanGeometry {
            floor: 0,
            walkable: vec![Polygon::new(ring)],
            obstacles: Vec::new(),
        },
        None,
    )
    .unwrap()
}

/// Distance from `q` to the polyline `p`, m.
fn off_path(p: &[[f64; 2]], q: [f64; 2]) -> f64 {
    p.windows(2)
        .map(|w| {
            let (dx, dy) = (w[1][0] - w[0][0], w[1][1] - w[0][1]);
            let t = (((q[0] - w[0][0]) * dx + (q[1] - w[0][1]) * dy) / (dx * dx + dy * dy))
                .clamp(0.0, 1.0);
            (q[0] - w[0][0] - t * dx).hypot(q[1] - w[0][1] - t * dy)
        })
        .fold(f64::INFINITY, f64::min)
}

fn run(m: &mut MapNavigator, samples: &[ImuSample]) -> Vec<MapEstimate> {
    samples
        .iter()
        .map(|s| m.push(s).unwrap().expect("an estimate after a sample"))
        .collect()
}

#[test]
fn walls_keep_a_track_with_a_wrong_heading_in_its_corridor() {
    let sim = straight_walk(60.0);
    let samples = imu(&sim);
    let plan = Arc::new(corridor_plan(&sim));
    // The headings 20° off (a declination the phone does not have).
    let config = MapConfig {
        declination: Declination::Fixed(20f64.to_radians()),
        ..MapConfig::default()
    };
    let start = (sim.truth[0].east_m, sim.truth[0].north_m);
    let mut on_plan = MapNavigator::new(config, vec![plan]).unwrap();
    on_plan.start_at(start.0, start.1, Some(0.5), None).unwrap();
    let mut off_plan = MapNavigator::new(config, vec![]).unwrap();
    off_plan.start_at(start.0, start.1, None, None).unwrap();
    let (a, b) = (run(&mut on_plan, &samples), run(&mut off_plan, &samples));
    let p = path(&sim);
    let worst = a
        .iter()
        .map(|e| off_path(&p, [e.x_m, e.y_m]))
        .fold(0.0, f64::max);
    let drift = off_path(&p, [b[b.len() - 1].x_m, b[b.len() - 1].y_m]);
    assert!(
        drift > 10.0,
        "without the plan the 20° error shows: {drift:.1} m off the path"
    );
    assert!(
        worst < 2.5,
        "with the plan the corridor holds the track: {worst:.1} m off the path at worst"
    );
    let last = a[a.len() - 1];
    assert!(
        last.steps > 50 && last.floor == Some(0) && last.recoveries == 0,
        "{last:?}"
    );
    // A smoothed path came out, one point per step.
    let mut path = on_plan.smoothed_since(0).count();
    on_plan.smoothed_window(|_| path += 1);
    assert!(
        path as u64 <= last.steps && path > 10,
        "{path} smoothed points"
    );
}

#[test]
fn without_a_plan_it_is_the_navigator_unchanged() {
    let sim = straight_walk(20.0);
    let samples = imu(&sim);
    let mut nav = PhoneNavigator::new(NavigatorConfig::default()).unwrap();
    let mut m = MapNavigator::new(MapConfig::default(), vec![]).unwrap();
    for s in &samples {
        nav.push_imu(s).unwrap();
        let e = m.push(s).unwrap().unwrap();
        let n = nav.estimate().unwrap();
        assert_eq!(
            (e.x_m.to_bits(), e.y_m.to_bits()),
            (n.east_m.to_bits(), n.north_m.to_bits())
        );
        assert_eq!(
            (e.steps, e.distance_m.to_bits()),
            (n.steps, n.distance_m.to_bits())
        );
        assert_eq!(e.walking_azimuth_rad, n.walking_azimuth_rad);
        assert_eq!(e.floor, None);
    }
    assert_eq!(m.smoothed_fixed(), 0);
}

#[test]
fn a_snapshot_resumes_bit_for_bit_and_only_over_its_plans() {
    let sim = straight_walk(25.0);
    let samples = imu(&sim);
    let plan = Arc::new(corridor_plan(&sim));
    let config = MapConfig {
        particles: 200,
        smoothing_lag_steps: 16,
        ..MapConfig::default()
    };
    let mut whole = MapNavigator::new(config, vec![Arc::clone(&plan)]).unwrap();
    whole
        .start_at(sim.truth[0].east_m, sim.truth[0].north_m, None, None)
        .unwrap();
    let fix_at = samples.len() / 2;
    let fix = MapFix::plan(
        samples[fix_at].t_s,
        sim.truth[fix_at / 10].east_m,
        sim.truth[fix_at / 10].north_m,
        4.0,
    );
    let mut reference = Vec::new();
    for (i, s) in samples.iter().enumerate() {
        if i == fix_at {
            whole.push_fix(&fix).unwrap();
        }
        reference.push(whole.push(s).unwrap().unwrap());
    }
    for split in [1, 700, 1200, fix_at + 3, samples.len() - 5] {
        let mut a = MapNavigator::new(config, vec![Arc::clone(&plan)]).unwrap();
        a.start_at(sim.truth[0].east_m, sim.truth[0].north_m, None, None)
            .unwrap();
        for (i, s) in samples[..split].iter().enumerate() {
            if i == fix_at {
                a.push_fix(&fix).unwrap();
            }
            a.push(s).unwrap();
        }
        let bytes = a.snapshot();
        let mut b = MapNavigator::restore(&bytes, vec![Arc::clone(&plan)]).unwrap();
        assert_eq!(
            b.snapshot(),
            bytes,
            "split {split}: restore then snapshot is the identity"
        );
        for (i, s) in samples.iter().enumerate().skip(split) {
            if i == fix_at {
                b.push_fix(&fix).unwrap();
            }
            assert_eq!(
                b.push(s).unwrap().unwrap(),
                reference[i],
                "split {split}, sample {i}"
            );
        }
        assert!(
            b.snapshot() == whole.snapshot(),
            "split {split}: the same state at the end"
        );
        let (mut pa, mut pb) = (Vec::new(), Vec::new());
        whole.smoothed_window(|p| pa.push(p));
        b.smoothed_window(|p| pb.push(p));
        assert_eq!(pa, pb);
    }
    // Other plans, no plans, a corrupted snapshot: typed errors.
    let bytes = whole.snapshot();
    let other = Arc::new(FloorPlan::rectangles(0, [0.0, 0.0, 50.0, 50.0], &[]).unwrap());
    assert!(matches!(
        MapNavigator::restore(&bytes, vec![other]),
        Err(MapError::Snapshot(_))
    ));
    assert!(matches!(
        MapNavigator::restore(&bytes, vec![]),
        Err(MapError::Snapshot(_))
    ));
    let mut bad = bytes.clone();
    bad[bytes.len() / 2] ^= 1;
    assert!(MapNavigator::restore(&bad, vec![plan]).is_err());
}

#[test]
fn the_same_seed_gives_the_same_track() {
    let sim = straight_walk(15.0);
    let samples = imu(&sim);
    let plan = Arc::new(corridor_plan(&sim));
    let go = |seed: u64| {
        let config = MapConfig {
            seed,
            particles: 300,
            ..MapConfig::default()
        };
        let mut m = MapNavigator::new(config, vec![Arc::clone(&plan)]).unwrap();
        m.start_at(sim.truth[0].east_m, sim.truth[0].north_m, Some(2.0), None)
            .unwrap();
        run(&mut m, &samples)
    };
    assert_eq!(go(1), go(1));
    assert_ne!(go(1), go(2));
}

fn open_square() -> Arc<FloorPlan> {
    Arc::new(
        FloorPlan::rectangles(0, [0.0, 0.0, 100.0, 100.0], &[[40.0, 40.0, 60.0, 60.0]]).unwrap(),
    )
}

#[test]
fn a_start_off_the_plan_is_snapped_or_refused_and_changes_nothing() {
    let mut m = MapNavigator::new(MapConfig::default(), vec![open_square()]).unwrap();
    // Inside the obstacle, 2 m from its edge: moved onto the walkable area.
    m.start_at(42.0, 50.0, Some(0.5), None).unwrap();
    let sim = straight_walk(2.0);
    let e = m.push(&imu(&sim)[0]).unwrap().unwrap();
    assert!(e.flags.start_snapped);
    assert!(e.x_m < 40.5 && (e.y_m - 50.0).abs() < 2.0, "{e:?}");
    // Deep inside (10 m) or off the plan: refused, nothing changes.
    let before = m.snapshot();
    for (x, y) in [(50.0, 50.0), (-30.0, 10.0), (f64::NAN, 1.0)] {
        let r = m.start_at(x, y, None, None);
        assert!(
            matches!(r, Err(MapError::OffPlan { .. }) | Err(MapError::Input(_))),
            "{r:?}"
        );
        assert!(m.snapshot() == before, "a refused fix changed the state");
    }
    assert!(matches!(
        m.start_at(10.0, 10.0, None, Some(3)),
        Err(MapError::UnknownFloor { floor: 3 })
    ));
    assert!(matches!(
        m.set_floor(7),
        Err(MapError::UnknownFloor { floor: 7 })
    ));
    assert!(m.snapshot() == before, "a refused sample changed the state");
}

#[test]
fn a_plan_every_step_crosses_a_wall_of_is_survived_and_said() {
    // Walls every 0.3 m both ways: no step fits between them.
    let mut obstacles = Vec::new();
    for k in 0..200 {
        let v = 0.3 * k as f64;
        obstacles.push([v, 0.0, v + 0.02, 60.0]);
        obstacles.push([0.0, v, 60.0, v + 0.02]);
    }
    let plan = Arc::new(FloorPlan::rectangles(0, [0.0, 0.0, 60.0, 60.0], &obstacles).unwrap());
    let config = MapConfig {
        particles: 100,
        ..MapConfig::default()
    };
    let mut m = MapNavigator::new(config, vec![plan]).unwrap();
    m.start_at(30.1, 30.1, Some(1.0), None).unwrap();
    let sim = straight_walk(12.0);
    let out = run(&mut m, &imu(&sim));
    let last = out[out.len() - 1];
    assert!(last.steps > 8, "{}", last.steps);
    assert!(
        last.recoveries >= 5,
        "every step failed: {} recoveries",
        last.recoveries
    );
    assert!(out
        .iter()
        .all(|e| e.x_m.is_finite() && e.y_m.is_finite() && e.position_std_m.is_finite()));
    assert!(out.iter().any(|e| e.flags.recovered));
}

#[test]
fn fixes_far_off_the_plan_are_held_back_then_believed_when_they_agree() {
    let mut m = MapNavigator::new(MapConfig::default(), vec![open_square()]).unwrap();
    m.start_at(10.0, 50.0, Some(1.0), None).unwrap();
    let sim = straight_walk(10.0);
    let samples = imu(&sim);
    m.push(&samples[0]).unwrap();
    let t = samples[0].t_s;
    // One fix 80 m away: no particle explains it, held back.
    let e = m
        .push_fix(&MapFix::plan(t + 0.01, 90.0, 50.0, 3.0))
        .unwrap()
        .unwrap();
    let e = if e.fixes_rejected == 0 {
        m.push(&samples[400]).unwrap().unwrap() // weighed once it waited for its steps
    } else {
        e
    };
    assert_eq!(e.fixes_rejected, 1, "{e:?}");
    assert!((e.x_m - 10.0).abs() < 3.0);
    // A second that agrees with it: the walker is there.
    m.push_fix(&MapFix::plan(t + 5.0, 90.5, 50.5, 3.0)).unwrap();
    let e = m.push(&samples[900]).unwrap().unwrap();
    assert!(e.recoveries >= 1 && e.flags.recovered, "{e:?}");
    assert!((e.x_m - 90.0).abs() < 5.0, "{e:?}");
    // Bad fixes: typed, nothing changes.
    let before = m.snapshot();
    for f in [
        MapFix::plan(t + 6.0, f64::NAN, 1.0, 3.0),
        MapFix::plan(t + 6.0, 1.0, 1.0, -1.0),
        MapFix::plan(t + 1.0, 1.0, 1.0, 3.0), // before the last fix
        MapFix::lat_lon(t + 7.0, 30.0, 120.0, 3.0), // the plan has no geographic reference
        MapFix {
            floor: Some(4),
            ..MapFix::plan(t + 8.0, 1.0, 1.0, 3.0)
        },
    ] {
        assert!(m.push_fix(&f).is_err(), "{f:?}");
        assert!(
            m.snapshot() == before,
            "a refused fix changed the state: {f:?}"
        );
    }
    // A rejected IMU sample changes nothing either.
    let mut bad = samples[901];
    bad.gyro_rads[0] = f64::INFINITY;
    assert!(m.push(&bad).is_err());
    assert!(m.snapshot() == before, "a refused sample changed the state");
}

#[test]
fn a_fix_on_another_floor_moves_the_walker_there() {
    let f0 = Arc::new(FloorPlan::rectangles(0, [0.0, 0.0, 50.0, 50.0], &[]).unwrap());
    let f1 = Arc::new(
        FloorPlan::rectangles(1, [0.0, 0.0, 50.0, 50.0], &[[0.0, 0.0, 20.0, 50.0]]).unwrap(),
    );
    assert!(matches!(
        MapNavigator::new(MapConfig::default(), vec![Arc::clone(&f0), Arc::clone(&f0)]),
        Err(MapError::DuplicateFloor { floor: 0 })
    ));
    let mut m = MapNavigator::new(MapConfig::default(), vec![f0, f1]).unwrap();
    m.start_at(10.0, 10.0, None, None).unwrap();
    let sim = straight_walk(2.0);
    let e = m.push(&imu(&sim)[0]).unwrap().unwrap();
    assert_eq!(e.floor, Some(0));
    let fix = MapFix {
        floor: Some(1),
        ..MapFix::plan(e.t_s, 30.0, 30.0, 2.0)
    };
    let e = m.push_fix(&fix).unwrap().unwrap();
    assert_eq!(e.floor, Some(1));
    assert!(
        (e.x_m - 30.0).abs() < 2.0 && (e.y_m - 30.0).abs() < 2.0,
        "{e:?}"
    );
    // Back to floor 0 by the app: particles keep their places (walkable there too).
    m.set_floor(0).unwrap();
    let e = m.estimate().unwrap();
    assert_eq!(e.floor, Some(0));
    assert!((e.x_m - 30.0).abs() < 2.0);
}

#[test]
fn no_start_spreads_over_the_floor_and_says_so() {
    let m = MapNavigator::new(MapConfig::default(), vec![open_square()]).unwrap();
    let mut m = m;
    let sim = straight_walk(2.0);
    let e = m.push(&imu(&sim)[0]).unwrap().unwrap();
    assert!(
        e.flags.global && !e.flags.converged && e.flags.ambiguous,
        "{e:?}"
    );
    assert!(e.position_std_m > 20.0, "{e:?}");
}

#[test]
fn settings_no_walk_could_use_are_refused() {
    for c in [
        MapConfig {
            particles: 3,
            ..MapConfig::default()
        },
        MapConfig {
            heading_sigma_rad: f64::NAN,
            ..MapConfig::default()
        },
        MapConfig {
            smoothing_lag_steps: 0,
            ..MapConfig::default()
        },
        MapConfig {
            declination: Declination::Fixed(7.0),
            ..MapConfig::default()
        },
        MapConfig {
            wall_crossing_weight: 2.0,
            ..MapConfig::default()
        },
    ] {
        assert!(
            matches!(MapNavigator::new(c, vec![]), Err(MapError::Config { .. })),
            "{c:?}"
        );
    }
}
