//! Tunables of the adaptive pace filter: each named once, with its unit and reason.
//! The filter's public parameters are in `super::super::config::AdaptiveParams`; these
//! are the fixed ones; the χ² gates and the fix-radius scale are `crate::stats`.

/// Expected normalised innovation squared of a 2-D fix (its degrees of freedom): the
/// starting value of the NIS average.
pub(super) const EXPECTED_NIS_2DOF: f64 = 2.0;
/// Weights of the NIS average: the old average, the new fix (a ~3-fix memory).
pub(super) const NIS_AVG_KEEP: f64 = 0.7;
pub(super) const NIS_AVG_GAIN: f64 = 0.3;
/// Largest NIS entering the average (one wild fix does not hold trust off for long).
pub(super) const NIS_AVG_CAP: f64 = 50.0;
/// Gate violations in a row (and their minimum duration, s) after which the filter
/// re-anchors on GNSS instead of treating fixes as outliers.
pub(super) const REANCHOR_AFTER_GATED: u32 = 3;
pub(super) const REANCHOR_AFTER_S: f64 = 5.0;
/// A gated fix is a turn between sparse fixes, not an outlier, when the GNSS velocity
/// reverses the filter's with both above this speed, m/s ...
pub(super) const REVERSAL_MIN_SPEED_MPS: f64 = 1.0;
/// ... and the ratio of the two speeds within this range (a plausible speed).
pub(super) const REVERSAL_SPEED_RATIO: std::ops::Range<f64> = 0.5..2.0;
/// After a re-anchor the direction is taken from the GNSS displacement when its speed
/// is above this, m/s (below, the displacement is jitter).
pub(super) const REANCHOR_DIRECTION_MIN_MPS: f64 = 0.5;
/// Smallest per-axis 1-σ of a fix with a reported accuracy, metres.
pub(super) const MIN_FIX_SIGMA_M: f64 = 0.5;
/// Share of a fix's reported error variance taken as white noise (rest: correlated).
pub(super) const WHITE_SHARE: f64 = 0.35;
/// Smallest 1-σ of a fix's white noise, metres.
pub(super) const MIN_WHITE_SIGMA_M: f64 = 0.3;
/// The correlated-error variance is raised to at least this share of what the fix
/// reports before an update (it follows the receiver's accuracy).
pub(super) const BIAS_VAR_FLOOR_SHARE: f64 = 0.1;
/// Pedometer (and stationary) updates at most this often, seconds.
pub(super) const PED_UPDATE_INTERVAL_S: f64 = 1.0;
/// Chords of the step-length path window join fixes at least this far apart, s.
pub(super) const CHORD_MIN_S: f64 = 4.0;
/// Length of a step-length path window, s, and the fewest steps it needs.
pub(super) const PATH_WINDOW_S: f64 = 20.0;
pub(super) const PATH_MIN_STEPS: f64 = 20.0;
/// Without step data, fixes moving slower than this over 15–30 s mean standing, m/s.
pub(super) const STILL_SPEED_MPS: f64 = 0.35;
pub(super) const STILL_LEAVE_SPEED_MPS: f64 = 0.6;
pub(super) const STILL_MIN_SPAN_S: f64 = 15.0;
pub(super) const STILL_MAX_SPAN_S: f64 = 30.0;
/// Recent fixes kept for the displacement test.
pub(super) const RECENT_FIXES: usize = 32;
/// Path windows starting sooner than this after a bout start teach no slope, s.
pub(super) const SLOPE_SETTLE_S: f64 = 20.0;
/// Share of a fix's error that does not cancel between window ends.
pub(super) const PATH_SIGMA_SHARE: f64 = 0.7;
/// Step data older than this is not used at a fix, seconds.
pub(super) const STEP_DATA_FRESH_S: f64 = 3.0;
/// Window of the cadence estimate, seconds.
pub(super) const CADENCE_WINDOW_S: f64 = 4.0;
/// Window of the slow cadence at which the step-length line is read, seconds.
pub(super) const SLOW_CADENCE_WINDOW_S: f64 = 20.0;
/// Time constant of the reference cadence c̄, seconds.
pub(super) const CADENCE_REF_TAU_S: f64 = 60.0;
/// ... and while the step length is still unknown, seconds.
pub(super) const CADENCE_REF_FAST_TAU_S: f64 = 3.0;
/// Longest step of the reference cadence's tracking, seconds (a gap in the steps
/// moves c̄ no further than 10 s of cadence would).
pub(super) const CADENCE_REF_MAX_DT_S: f64 = 10.0;
/// Cadence at which the initial step length applies, steps/s (168 steps/min).
pub(crate) const PRIOR_CADENCE: f64 = 2.8;
/// Initial step length (at PRIOR_CADENCE) when none is configured, metres, and its 1-σ.
pub(crate) const DEFAULT_STEP_LENGTH_M: f64 = 1.0;
pub(super) const STEP_LENGTH_PRIOR_SIGMA_M: f64 = 0.4;
/// 1-σ of a configured initial step length (`PaceConfig::initial_step_length_m`), m.
pub(super) const CONFIGURED_STEP_LENGTH_SIGMA_M: f64 = 0.1;
/// Prior slope of step length against cadence, m per (step/s), and its 1-σ.
pub(crate) const SLOPE_PRIOR: f64 = 0.5;
pub(super) const SLOPE_PRIOR_SIGMA: f64 = 0.3;
/// Random walk of the slope of the step-length line, per √s.
pub(super) const SLOPE_RW: f64 = 0.003;
/// The slope is learned only while the slow cadence is this far from c̄, steps/s
/// (about 5× the noise of the slow cadence: real pace changes, not noise).
pub(super) const SLOPE_MIN_CADENCE_DEV: f64 = 0.15;
/// Physical range of a step length read off the line, metres.
pub(super) const MIN_STEP_LENGTH_M: f64 = 0.2;
pub(super) const MAX_STEP_LENGTH_M: f64 = 3.0;
/// Range of the prior line's level moved to a first or reset cadence, metres.
pub(super) const MIN_PRIOR_STEP_LENGTH_M: f64 = 0.3;
pub(super) const MAX_PRIOR_STEP_LENGTH_M: f64 = 2.0;
/// Step length counts as learned once its 1-σ is below this, metres.
pub(super) const LEARNED_SIGMA_M: f64 = 0.08;
/// Smallest cadence 1-σ used, steps/s (the smoothed cadence is correlated in time).
pub(super) const MIN_CADENCE_SIGMA: f64 = 0.03;
/// Zero-velocity measurement noise while stationary, m/s.
pub(super) const ZUPT_SIGMA_MPS: f64 = 0.05;
/// Below this speed the filter has no direction of motion to measure speed along,
/// m/s (Doppler and pedometer updates wait; the pedometer alone is the output).
pub(super) const MIN_DIRECTED_SPEED_MPS: f64 = 0.3;
/// Smallest 1-σ of a receiver (Doppler) speed, m/s.
pub(super) const MIN_DOPPLER_SIGMA_MPS: f64 = 0.05;
/// Moving again after a stop: velocity 1-σ is this share of the pedometer speed ...
pub(super) const RESTART_SPEED_SHARE: f64 = 0.5;
/// ... plus this variance, (m/s)² (0.5 m/s: GNSS corrects it within a few fixes).
pub(super) const RESTART_SPEED_VAR: f64 = 0.25;
/// Trust in GNSS for learning needs the NIS average below this (2 expected).
pub(super) const TRUST_NIS: f64 = 4.0;
/// ... with the latest fix at most this old, seconds ...
pub(super) const TRUST_FIX_AGE_S: f64 = 5.0;
/// ... and this long since the last re-anchor, seconds.
pub(super) const TRUST_AFTER_RESET_S: f64 = 10.0;
/// Initial velocity 1-σ, m/s.
pub(super) const INITIAL_SPEED_SIGMA: f64 = 3.0;
/// Stationary contradicted by GNSS this many fixes in a row: step data is distrusted.
pub(super) const CONTRADICTIONS_TO_DISTRUST: u32 = 5;
/// A fix contradicts "stationary" when its NIS is beyond this many 2-DOF gates.
pub(super) const CONTRADICTION_GATES: f64 = 4.0;
/// Smallest speed whose direction is kept as the last direction of motion, m/s.
pub(super) const DIRECTION_MIN_SPEED_MPS: f64 = 1.0;
/// A freed direction has a velocity 1-σ per axis of this share of the speed, ...
pub(super) const FREE_DIRECTION_SPEED_SHARE: f64 = 0.5;
/// ... of at least this speed, m/s.
pub(super) const FREE_DIRECTION_MIN_SPEED_MPS: f64 = 1.0;
/// Speed below which the speed variance is the mean of both axes' (no direction), m/s.
pub(super) const SPEED_VAR_MIN_SPEED_MPS: f64 = 1e-3;

/// Acceleration noise is isotropic below this speed, m/s, ...
pub(super) const ISOTROPIC_BELOW_MPS: f64 = 0.5;
/// ... and fully along/cross-track this much faster, m/s.
pub(super) const ANISOTROPY_RAMP_MPS: f64 = 1.0;

/// GNSS silent this long while steps arrive: the pedometer carries the speed, s.
pub(super) const GNSS_SILENT_S: f64 = 2.0;
/// Below this epoch GNSS weight the prior step length is the one in use (reported
/// before it is learned).
pub(super) const PRIOR_IN_USE_MAX_GNSS_WEIGHT: f64 = 0.8;

/// Smallest 1-σ of an imported step length, metres, and its relative change between
/// sessions (added in quadrature).
pub(super) const CALIBRATION_MIN_SIGMA_M: f64 = 0.01;
pub(super) const CALIBRATION_DRIFT: f64 = 0.02;
/// An imported line at least this uncertain, metres, holds nothing learned (the
/// population prior's is 0.4 m; a line learned from GNSS is within a few cm): it is
/// not imported, so it does not override `initial_step_length_m` or the prior's
/// slope. A calibration exported for its accelerometer model alone (a walk) has one.
pub(super) const UNLEARNED_LINE_SIGMA_M: f64 = 0.2;
/// 1-σ of an imported slope, m per (step/s).
pub(super) const CALIBRATED_SLOPE_SIGMA: f64 = 0.15;
/// Ranges of an exported line: cadence, steps/min; slope, m per (step/min); 1-σ, m.
pub(super) const EXPORT_MIN_CADENCE_SPM: f64 = 30.0;
pub(super) const EXPORT_MAX_CADENCE_SPM: f64 = 300.0;
pub(super) const EXPORT_MAX_SLOPE_M_PER_SPM: f64 = 0.05;
pub(super) const EXPORT_MAX_SIGMA_M: f64 = 1.0;
/// Seconds per minute (cadence steps/s ↔ steps/min).
pub(super) const S_PER_MIN: f64 = 60.0;

/// A disagreement with GNSS this close to the mean cadence of the line's windows,
/// steps/s (15 steps/min), says the line's level is wrong (`on_pedometer_disagrees`).
pub(super) const RELEARN_CADENCE_BAND: f64 = 0.25;

/// Steps in accepted path windows before the session mean is exported (≈ 3 min).
pub(super) const SESSION_MIN_STEPS: f64 = 500.0;

/// Largest variance the filter keeps, in its own units (m², (m/s)², ...): (100 km)².
/// A prediction across a gap of months (the input layer allows jumps up to a year)
/// would otherwise grow P as dt³ past what a snapshot stores (1e30); nothing is
/// known better than this after such a gap anyway.
pub(super) const MAX_VARIANCE: f64 = 1e10;
