//! What is personal in running pace, carried between sessions: the runner's
//! step-length line ([`PaceCalibration`]) and, when the app pushes raw acceleration,
//! the step-length model of its features ([`AccelStepModel`]). Export with
//! [`PaceTracker::calibration`](super::PaceTracker::calibration), import through
//! [`PaceConfig::calibration`](super::PaceConfig::calibration).
//!
//! Text form, version 1 (for an app's storage or `stridekit pace --calibration`; the
//! layout of [`crate::calibration`]: `#` comment lines anywhere, writing then reading
//! is exact):
//!
//! ```text
//! stridekit-pace-calibration 1
//! # learned by: stridekit pace run.fit
//! line 1.02 170.0 0.008 0.021
//! accel_model 0.378 -4.6e-5 0.0986 at 1.83 12.5 sigma 0.05 0.0015 0.012
//! ```
//!
//! `line STEP_LENGTH_M CADENCE_SPM SLOPE_M_PER_SPM STEP_LENGTH_STD_M` is required;
//! `accel_model A B C at F0 SV0 sigma σA σB σL` is optional (σL: the step length's
//! 1-σ at the reference features F0, SV0; see [`AccelStepModel`]). Unknown or repeated records, wrong
//! counts, non-numbers and values [`PaceCalibration::validate`] refuses are typed
//! [`CalibrationError`]s.

use std::fmt::Write as _;

use super::error::PaceError;
use crate::calibration::{self as text, records, CalibrationError};

/// First line of a pace calibration text (without the version).
pub const PACE_CALIBRATION_MAGIC: &str = "stridekit-pace-calibration";
/// The text format version this build reads and writes.
pub const PACE_CALIBRATION_VERSION: u32 = 1;

/// A runner's learned step-length line, carried between sessions.
///
/// Export it with [`PaceTracker::calibration`](super::PaceTracker::calibration) at the
/// end of a run with good GNSS (it is `None` until the step length is learned), store
/// it with the user's profile, and pass it as
/// [`PaceConfig::calibration`](super::PaceConfig::calibration) next time: the
/// tracker then gives calibrated pedometer speed from the first steps, with or without
/// GNSS (treadmill, indoor track, a watch without GNSS), and keeps refining it when
/// GNSS is good. It is part of the configuration, so snapshots keep it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaceCalibration {
    /// Step length at `cadence_spm`, metres.
    pub step_length_m: f64,
    /// Cadence at which `step_length_m` was learned, steps/min (both feet).
    pub cadence_spm: f64,
    /// How step length grows with cadence, metres per step/min.
    pub slope_m_per_spm: f64,
    /// 1-σ of `step_length_m` when it was exported, metres.
    pub step_length_std_m: f64,
    /// The step-length model of raw accelerometer input, learned when the app pushed
    /// raw acceleration ([`PaceTracker::push_accel`](super::PaceTracker::push_accel))
    /// during good GNSS; `None` when it was not. Imported, it gives the pedometer speed
    /// of a session without GNSS (and of an outage before GNSS has refined it) from
    /// each step's own acceleration, not only from the line at the cadence.
    pub accel_model: Option<AccelStepModel>,
}

/// The feature step-length model of raw accelerometer input, carried between
/// sessions inside a [`PaceCalibration`]: `L = A·F + B·SV + C`, with F the step
/// frequency (steps/s, Hz) and SV the variance of the acceleration magnitude over the
/// step ((m/s²)²), as the tracker's step detector measures them (method 3 of
/// docs/architecture.md). Its uncertainty is carried centred at the user's typical
/// features (F₀, SV₀), where the model was calibrated: the 1-σ of the slopes A and B
/// and of the step length at (F₀, SV₀). Centred like this the three are nearly
/// independent (A and C themselves are not: a user's step frequencies span a narrow
/// range), so an imported model is about as certain as it was when exported, and GNSS
/// in the next session refines it rather than re-fitting it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AccelStepModel {
    /// A, metres per step/s (m·s).
    pub a_m_s: f64,
    /// B, metres per (m/s²)².
    pub b_m_per_m2ps4: f64,
    /// C, metres.
    pub c_m: f64,
    /// F₀: the typical step frequency of the calibration, steps/s (Hz).
    pub ref_frequency_hz: f64,
    /// SV₀: the typical acceleration variance of the calibration, (m/s²)².
    pub ref_variance_m2ps4: f64,
    /// 1-σ of A, m·s.
    pub a_std_m_s: f64,
    /// 1-σ of B, metres per (m/s²)².
    pub b_std_m_per_m2ps4: f64,
    /// 1-σ of the modelled step length at (F₀, SV₀), metres.
    pub length_std_m: f64,
}

/// Largest |A| of an imported accelerometer model, m·s (A·F at 4 steps/s: 8 m).
pub const MAX_ACCEL_MODEL_A_M_S: f64 = 2.0;
/// Largest |B| of an imported accelerometer model, metres per (m/s²)².
pub const MAX_ACCEL_MODEL_B_M_PER_M2PS4: f64 = 0.1;
/// Largest |C| of an imported accelerometer model, metres.
pub const MAX_ACCEL_MODEL_C_M: f64 = 5.0;
/// Range of the reference step frequency, Hz (steps of 0.2–2 s).
pub const ACCEL_MODEL_REF_FREQUENCY_HZ: (f64, f64) = (0.5, 5.0);
/// Largest reference acceleration variance, (m/s²)².
pub const MAX_ACCEL_MODEL_REF_VARIANCE_M2PS4: f64 = 1e4;
/// Largest 1-σ of an imported accelerometer model's parts (in their units).
pub const MAX_ACCEL_MODEL_STD: f64 = 10.0;

impl AccelStepModel {
    /// θ = (A, B, C).
    pub fn theta(&self) -> [f64; 3] {
        [self.a_m_s, self.b_m_per_m2ps4, self.c_m]
    }

    /// The reference feature vector x₀ = (F₀, SV₀, 1) of `L = θ·x`.
    pub fn reference(&self) -> [f64; 3] {
        [self.ref_frequency_hz, self.ref_variance_m2ps4, 1.0]
    }

    /// The modelled step length at the reference features, metres.
    pub fn reference_length_m(&self) -> f64 {
        let [a, b, c] = self.theta();
        a * self.ref_frequency_hz + b * self.ref_variance_m2ps4 + c
    }

    /// Check the fields (finite, within physical bounds, positive 1-σ).
    pub fn validate(&self) -> Result<(), PaceError> {
        let bad = |name: &str, expected: String, v: f64| {
            Err(PaceError::InvalidConfig {
                reason: format!("calibration: accel_model.{name} must be {expected}, got {v}"),
            })
        };
        let limits = [
            ("a_m_s", self.a_m_s, MAX_ACCEL_MODEL_A_M_S),
            (
                "b_m_per_m2ps4",
                self.b_m_per_m2ps4,
                MAX_ACCEL_MODEL_B_M_PER_M2PS4,
            ),
            ("c_m", self.c_m, MAX_ACCEL_MODEL_C_M),
        ];
        for (name, v, max) in limits {
            if !(v.is_finite() && v.abs() <= max) {
                return bad(name, format!("within ±{max}"), v);
            }
        }
        let (f_lo, f_hi) = ACCEL_MODEL_REF_FREQUENCY_HZ;
        let f = self.ref_frequency_hz;
        if !(f.is_finite() && (f_lo..=f_hi).contains(&f)) {
            return bad("ref_frequency_hz", format!("in {f_lo}..={f_hi} Hz"), f);
        }
        let sv = self.ref_variance_m2ps4;
        if !(sv.is_finite() && (0.0..=MAX_ACCEL_MODEL_REF_VARIANCE_M2PS4).contains(&sv)) {
            return bad(
                "ref_variance_m2ps4",
                format!("in 0..={MAX_ACCEL_MODEL_REF_VARIANCE_M2PS4}"),
                sv,
            );
        }
        let sigmas = [
            ("a_std_m_s", self.a_std_m_s),
            ("b_std_m_per_m2ps4", self.b_std_m_per_m2ps4),
            ("length_std_m", self.length_std_m),
        ];
        for (name, v) in sigmas {
            if !(v.is_finite() && v > 0.0 && v <= MAX_ACCEL_MODEL_STD) {
                return bad(name, format!("in (0, {MAX_ACCEL_MODEL_STD}]"), v);
            }
        }
        Ok(())
    }
}

impl PaceCalibration {
    /// Step length at a cadence (steps/min) on the calibrated line, metres (clamped
    /// to 0.2..=3 m).
    pub fn step_length_at(&self, cadence_spm: f64) -> f64 {
        (self.step_length_m + self.slope_m_per_spm * (cadence_spm - self.cadence_spm))
            .clamp(0.2, 3.0)
    }

    /// Check the fields (physical ranges).
    pub fn validate(&self) -> Result<(), PaceError> {
        let bad = |reason: &str| {
            Err(PaceError::InvalidConfig {
                reason: format!("calibration: {reason}"),
            })
        };
        if !(self.step_length_m.is_finite() && (0.2..=3.0).contains(&self.step_length_m)) {
            return bad("step_length_m must be in 0.2..=3.0 m");
        }
        if !(self.cadence_spm.is_finite() && (30.0..=300.0).contains(&self.cadence_spm)) {
            return bad("cadence_spm must be in 30..=300 steps/min");
        }
        if !(self.slope_m_per_spm.is_finite() && self.slope_m_per_spm.abs() <= 0.05) {
            return bad("slope_m_per_spm must be within ±0.05 m per step/min");
        }
        if !(self.step_length_std_m.is_finite() && (0.0..=1.0).contains(&self.step_length_std_m)) {
            return bad("step_length_std_m must be in 0..=1 m");
        }
        if let Some(m) = &self.accel_model {
            m.validate()?;
        }
        Ok(())
    }
}

impl PaceCalibration {
    /// The calibration as text (format version 1); `comments` become `#` lines.
    pub fn to_text(&self, comments: &[String]) -> String {
        let mut s = text::header(PACE_CALIBRATION_MAGIC, PACE_CALIBRATION_VERSION, comments);
        let _ = writeln!(
            s,
            "line {:?} {:?} {:?} {:?}",
            self.step_length_m, self.cadence_spm, self.slope_m_per_spm, self.step_length_std_m
        );
        if let Some(m) = &self.accel_model {
            let [a, b, c] = m.theta();
            let (f0, sv0) = (m.ref_frequency_hz, m.ref_variance_m2ps4);
            let (sa, sb, sl) = (m.a_std_m_s, m.b_std_m_per_m2ps4, m.length_std_m);
            let _ = writeln!(
                s,
                "accel_model {a:?} {b:?} {c:?} at {f0:?} {sv0:?} sigma {sa:?} {sb:?} {sl:?}"
            );
        }
        s
    }

    /// Parse a calibration text (see the module docs); the result is validated.
    pub fn parse(text: &str) -> Result<Self, CalibrationError> {
        let mut line: Option<[f64; 4]> = None;
        let mut accel_model: Option<AccelStepModel> = None;
        for r in records(text, PACE_CALIBRATION_MAGIC, PACE_CALIBRATION_VERSION)? {
            match r.name() {
                "line" => {
                    if line.is_some() {
                        return Err(r.error("a second line record"));
                    }
                    r.expect_fields(
                        5,
                        "line STEP_LENGTH_M CADENCE_SPM SLOPE_M_PER_SPM STEP_LENGTH_STD_M",
                    )?;
                    line = Some([r.number(1)?, r.number(2)?, r.number(3)?, r.number(4)?]);
                }
                "accel_model" => {
                    if accel_model.is_some() {
                        return Err(r.error("a second accel_model record"));
                    }
                    let layout = "accel_model A B C at F0 SV0 sigma σA σB σL";
                    r.expect_fields(11, layout)?;
                    if r.fields[4] != "at" || r.fields[7] != "sigma" {
                        return Err(r.error(format!("expected: {layout}")));
                    }
                    accel_model = Some(AccelStepModel {
                        a_m_s: r.number(1)?,
                        b_m_per_m2ps4: r.number(2)?,
                        c_m: r.number(3)?,
                        ref_frequency_hz: r.number(5)?,
                        ref_variance_m2ps4: r.number(6)?,
                        a_std_m_s: r.number(8)?,
                        b_std_m_per_m2ps4: r.number(9)?,
                        length_std_m: r.number(10)?,
                    });
                }
                other => return Err(r.error(format!("unknown record {:?}", text::truncate(other)))),
            }
        }
        let [step_length_m, cadence_spm, slope_m_per_spm, step_length_std_m] =
            line.ok_or(CalibrationError::Missing("line"))?;
        let c = Self {
            step_length_m,
            cadence_spm,
            slope_m_per_spm,
            step_length_std_m,
            accel_model,
        };
        c.validate().map_err(|e| CalibrationError::Invalid {
            field: "pace calibration",
            reason: match e {
                PaceError::InvalidConfig { reason } => reason,
                other => other.to_string(),
            },
        })?;
        Ok(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> PaceCalibration {
        PaceCalibration {
            step_length_m: 1.0234567890123,
            cadence_spm: 171.25,
            slope_m_per_spm: 0.0083333333333,
            step_length_std_m: 0.021,
            accel_model: Some(AccelStepModel {
                a_m_s: 0.3781117891718111,
                b_m_per_m2ps4: -4.5812025378060006e-5,
                c_m: 0.09856747153190781,
                ref_frequency_hz: 1.8312345678901234,
                ref_variance_m2ps4: 12.512345678901234,
                a_std_m_s: 0.14132184735020203,
                b_std_m_per_m2ps4: 0.0019937188916670907,
                length_std_m: 0.0123456789,
            }),
        }
    }

    #[test]
    fn text_round_trips_exactly() {
        let c = sample();
        let t = c.to_text(&["learned by: test".into()]);
        assert!(t.starts_with("stridekit-pace-calibration 1\n# learned by: test\nline "));
        assert_eq!(PaceCalibration::parse(&t).unwrap(), c);
        let line_only = PaceCalibration {
            accel_model: None,
            ..c
        };
        let t = line_only.to_text(&[]);
        assert!(!t.contains("accel_model"));
        assert_eq!(PaceCalibration::parse(&t).unwrap(), line_only);
    }

    #[test]
    fn bad_texts_are_typed_errors() {
        use CalibrationError as E;
        let ok = sample().to_text(&[]);
        let parse = PaceCalibration::parse;
        assert!(matches!(parse(""), Err(E::NotCalibration { .. })));
        assert!(matches!(
            parse("stridekit-pdr-calibration 1\nstep_length constant 0 0 1 sigma 1 1 1\n"),
            Err(E::NotCalibration { .. })
        ));
        assert!(matches!(
            parse(&ok.replace("calibration 1", "calibration 2")),
            Err(E::Version { .. })
        ));
        assert!(matches!(
            parse("stridekit-pace-calibration 1\n# nothing\n"),
            Err(E::Missing("line"))
        ));
        let line = ok.lines().nth(1).unwrap().to_string();
        for (bad, what) in [
            (ok.replace("line 1.0234567890123", "line NaN"), "NaN"),
            (ok.replace("line 1.0234567890123", "line x"), "text"),
            (ok.replace(" 0.021\n", "\n"), "count"),
            (ok.replace(" sigma ", " sigmas "), "layout"),
            (ok.replace(" at ", " @ "), "layout at"),
            (format!("{ok}{line}\n"), "repeat"),
            (format!("{ok}walking_line 0.7 112\n"), "unknown"),
        ] {
            assert!(matches!(parse(&bad), Err(E::Line { .. })), "{what}: {bad}");
        }
        for bad in [
            ok.replace("line 1.0234567890123", "line 7.5"),
            ok.replace("sigma 0.14132184735020203", "sigma 0"),
        ] {
            assert!(matches!(parse(&bad), Err(E::Invalid { .. })), "{bad}");
        }
        let huge = format!("{ok}{}", "#\n".repeat(40_000));
        assert!(matches!(parse(&huge), Err(E::TooLarge { .. })));
    }
}
