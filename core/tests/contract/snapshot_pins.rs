//! Snapshot bytes pinned: a hash (FNV-1a, 64 bits) and the length of the snapshots
//! taken along a fixed simulated walk, per engine. Refactoring an engine (splitting files, naming state)
//! must not move them; a deliberate change of behaviour or format updates the pin.

use stridekit_core::ahrs::{Ahrs, AhrsSettings, ImuSample};
use stridekit_core::foot::{
    AdaptiveThresholds, FixedThresholds, FootConfig, FootNavigator, ShoeDetector, SvmAdaptive,
    ZeroVelocityDetector,
};
use stridekit_core::geo::LocalFrame;
use stridekit_core::pace::{PaceConfig, PaceSample, PaceTracker};
use stridekit_core::pdr::{NavigatorConfig, PhoneNavigator};
use stridekit_core::stepdetect::{StepDetector, StepDetectorConfig};
use stridekit_sim::phone::{simulate_phone, PhoneEvent, PhonePlacement, PhoneScenario};
use stridekit_sim::{simulate_foot, simulate_run, FootScenario, RunScenario, StepReport};

/// Snapshots taken every this many inputs.
const EVERY: usize = 500;

/// Hash and total length of the snapshots taken every [`EVERY`] inputs and at the end
/// (not a CRC-32: a snapshot ends with its own, and a CRC over a message followed by
/// its CRC is the same for every message).
struct Pin {
    bytes: Vec<u8>,
}

impl Pin {
    fn new() -> Self {
        Self { bytes: Vec::new() }
    }
    fn take(&mut self, i: usize, snapshot: impl FnOnce() -> Vec<u8>) {
        if i % EVERY == 0 {
            self.bytes.extend(snapshot());
        }
    }
    fn finish(mut self, last: Vec<u8>) -> (u64, usize) {
        self.bytes.extend(last);
        let hash = self.bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
            (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3)
        });
        (hash, self.bytes.len())
    }
}

/// 60 s of walking with the phone in a front pocket, magnetometer and GNSS, event by
/// event with its index.
fn phone_walk(mut f: impl FnMut(usize, PhoneEvent)) {
    let sim = simulate_phone(&PhoneScenario::walk(
        3,
        PhonePlacement::FrontPocket,
        1.4,
        60.0,
    ));
    for (i, e) in sim
        .timeline(&LocalFrame::new(47.0, 8.0, 0.0))
        .into_iter()
        .enumerate()
    {
        f(i, e);
    }
}

fn imu(s: &stridekit_sim::phone::ImuSample, mag: bool) -> ImuSample {
    ImuSample {
        t_s: s.t_s,
        gyro_rads: s.gyro_radps,
        accel_mps2: s.accel_mps2,
        mag_ut: mag.then_some(s.mag_ut),
    }
}

fn navigator_pin(config: NavigatorConfig, mag: bool, gnss: bool) -> (u64, usize) {
    let mut nav = PhoneNavigator::new(config).unwrap();
    let mut pin = Pin::new();
    phone_walk(|i, e| {
        match e {
            PhoneEvent::Imu(s) => nav.push_imu(&imu(s, mag)).unwrap(),
            PhoneEvent::Fix(f) if gnss => {
                nav.push_fix(&f).unwrap();
            }
            PhoneEvent::Fix(_) => {}
        }
        pin.take(i, || nav.snapshot());
    });
    pin.finish(nav.snapshot())
}

fn ahrs_pin(settings: AhrsSettings) -> (u64, usize) {
    let mut ahrs = Ahrs::new(settings).unwrap();
    let mut pin = Pin::new();
    phone_walk(|i, e| {
        if let PhoneEvent::Imu(s) = e {
            ahrs.push(&imu(s, true)).unwrap();
        }
        pin.take(i, || ahrs.snapshot());
    });
    pin.finish(ahrs.snapshot())
}

#[test]
fn phone_navigator_snapshots_are_pinned() {
    let raw_gyro = NavigatorConfig {
        gyro_calibrated: false,
        ..NavigatorConfig::default()
    };
    let got = [
        navigator_pin(NavigatorConfig::default(), true, true),
        navigator_pin(NavigatorConfig::default(), false, true),
        navigator_pin(raw_gyro, true, false),
    ];
    assert_eq!(got, PINNED_NAVIGATOR, "{got:?}");
}

#[test]
fn ahrs_snapshots_are_pinned() {
    let got = [
        ahrs_pin(AhrsSettings::default()),
        ahrs_pin(AhrsSettings::madgwick()),
    ];
    assert_eq!(got, PINNED_AHRS, "{got:?}");
}

#[test]
fn step_detector_snapshots_are_pinned() {
    let mut d = StepDetector::new(StepDetectorConfig::default()).unwrap();
    let mut pin = Pin::new();
    phone_walk(|i, e| {
        if let PhoneEvent::Imu(s) = e {
            d.push_accel(s.t_s, s.accel_mps2).unwrap();
            while d.pop_step().is_some() {}
        }
        pin.take(i, || d.snapshot());
    });
    let got = pin.finish(d.snapshot());
    assert_eq!(got, PINNED_STEPS, "{got:?}");
}

#[test]
fn foot_navigator_snapshots_are_pinned() {
    let sim = simulate_foot(&FootScenario::walk(1, 1));
    let got = [
        ZeroVelocityDetector::default(),
        ZeroVelocityDetector::SvmAdaptive(SvmAdaptive::default()),
        ZeroVelocityDetector::Shoe(ShoeDetector::default()),
        ZeroVelocityDetector::Fixed(FixedThresholds::WALK),
        ZeroVelocityDetector::Adaptive(AdaptiveThresholds::default()),
    ]
    .map(|detector| {
        let mut nav = FootNavigator::new(FootConfig {
            detector,
            ..FootConfig::default()
        })
        .unwrap();
        let mut pin = Pin::new();
        for (i, s) in sim.samples.iter().enumerate() {
            nav.push(s).unwrap();
            pin.take(i, || nav.snapshot());
        }
        pin.finish(nav.snapshot())
    });
    assert_eq!(got, PINNED_FOOT, "{got:?}");
}

/// The pace tracker along a simulated run; the calibration it would export is
/// appended (its `Debug` text: shortest round-trip digits, so bit-exact).
fn pace_pin(scenario: RunScenario, gnss_only: bool) -> (u64, usize) {
    let mut p = PaceTracker::new(PaceConfig::default()).unwrap();
    let mut pin = Pin::new();
    let samples = simulate_run(&scenario).samples();
    let used = samples
        .iter()
        .filter(|s| !(gnss_only && matches!(s, PaceSample::Steps(_))));
    for (i, s) in used.enumerate() {
        let _ = p.push(s);
        pin.take(i, || p.snapshot());
    }
    let mut last = p.snapshot();
    last.extend(format!("{:?}", p.calibration()).into_bytes());
    pin.finish(last)
}

#[test]
fn pace_tracker_snapshots_are_pinned() {
    let events_doppler = RunScenario {
        step_report: StepReport::Events,
        receiver_speed: true,
        duration_s: 900.0,
        ..RunScenario::demo(7)
    };
    let gnss_only = RunScenario {
        duration_s: 900.0,
        ..RunScenario::demo(11)
    };
    let got = [
        pace_pin(RunScenario::demo(5), false),
        pace_pin(events_doppler, false),
        pace_pin(gnss_only, true),
    ];
    assert_eq!(got, PINNED_PACE, "{got:?}");
}

// Recorded on main at 46f8dfb (before the engines were split into folders); the
// navigator's re-recorded on main at 0b6891a (snapshot format 8, the IMU merge rule);
// all re-recorded on main at 3b5df39, before the refactor was merged (the input
// guard's byte now packs the stream's unit, issue 36; navigator format 9; the
// decoupled filter's heading variance and gap handling, AHRS format 4, issue 39).
// Step detector format 11 (issue 39, i39-steps2): the steps held one step when sooner
// than the cadence join the snapshot; AHRS format 5 (i39-omag): the decoupled filter's
// magnetometer offset estimate and its setting; AHRS format 6 (i39-ogyro): its mean
// heading correction rate. The navigator carries them (and the default filter's
// inclination correction and renormalisations off the sample-to-sample chain, i39-speed2).
// Step detector format 12 and navigator format 10 (issue 39, i39-stepflag): each stored
// step's origin (seen or filled). Navigator format 11 (issue 39, i39-pdrgap): the
// walking direction's bridge of the heading across dropped samples.
// Re-recorded after merging i39-speed3 (AHRS rounding) with it; then for AHRS format 7
// (issue 39, i39-omag3: the decoupled filter's clip-run miss).
const PINNED_NAVIGATOR: [(u64, usize); 3] = [
    (17979186675723448126, 306019),
    (9399414079617839787, 306019),
    (14447083679486977587, 331077),
];
// The default filter's pin re-recorded for the fast atan2 of its magnetometer update
// (issue 39 speed; within 4e-9 rad of libm's, eval outputs unchanged), then for AHRS
// format 5 (i39-omag), then AHRS format 6 (i39-ogyro: running-mean average and
// heading floor after a lost integration, heading-drift bias state), then for the
// inclination correction's 1/|average| taken off the sample-to-sample chain (i39-speed2:
// the exact formula instead of a series to O(ε³), values move by ≈1e-12), then for the
// renormalisations' |q|² taken from the factors (i39-speed2; eval outputs byte-identical),
// then for AHRS format 7 (i39-omag3: the decoupled filter's clip-run miss; the Madgwick
// pin moves with the version byte only).
const PINNED_AHRS: [(u64, usize); 2] = [(1073981256677527784, 13706), (9994140219181868925, 5586)];
const PINNED_STEPS: (u64, usize) = (15844955469905237905, 46692);
// Foot format 12 (issue 39, i39-footzaru): the bias-jump check's still runs (the run under
// way, the stance's longest, the end of the last explained one) join the snapshot, and a
// foot still for 0.25 s reads the bias (estimates move).
// Foot format 11 (issue 39, i39-footclip): the accelerometer's ceiling per axis and sign,
// its clipped runs, and each buffered sample's unreported specific force and impact peak
// join the snapshot (estimates unchanged on this walk: nothing clips). Foot format 10 (issue 39, i39-footguard): the rotation the samples do not resolve (the
// last raw rate and its change, and each buffered sample's unresolved rotation per body
// axis) joins the
// snapshot, and the attitude variance grows by it (estimates move). Foot format 9 (issue 39, i39-footbias): the gyroscope bias jumps' state (the stance's
// stillest window, the last unexplained still rate, the stance's length) and their count
// join the snapshot. Format 8 (i39-foot2): the hole state (turn rate, pending
// stance check) (estimates unchanged on this walk). Format 7: the stillness floor, and the
// adaptive SHOE's threshold follows it (the default detector's estimates may move).
const PINNED_FOOT: [(u64, usize); 5] = [
    (5260763639901526236, 172398),
    (14548013626716452593, 173278),
    (9759985638644072477, 172046),
    (16202986450265612941, 172222),
    (14552639400852085970, 173982),
];
// Recorded on h37-pace at 06a5b1c, before core/src/pace/adaptive.rs was split.
const PINNED_PACE: [(u64, usize); 3] = [
    (15396665033210809671, 44002),
    (4462676194551652622, 34618),
    (15111130218364370262, 5737),
];
