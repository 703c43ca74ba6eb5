//! What is personal in pedestrian dead reckoning, learned once per user and phone
//! (`stridekit calibrate pdr`) and loaded into a [`super::PhoneNavigator`]:
//!
//! - the **step-length model** of the user: model kind, parameters θ of `L = θ·x`
//!   (as [`crate::steplength`]) and their 1-σ (how firmly they are known: the
//!   navigator's online GNSS calibration starts from them and can still refine them);
//! - optionally **how the user carries the phone**: the walking direction in the
//!   phone's body frame (for a phone read while walking, near its top edge, +y). It
//!   only fixes the walking direction's start; the navigator's own stride-axis and
//!   GNSS estimates take over after a carrying change.
//!
//! Text format, version 1 (UTF-8, `#` comment lines anywhere, one record per line):
//!
//! ```text
//! stridekit-pdr-calibration 1
//! # trained by: stridekit calibrate pdr --data …
//! step_length linear 0.4 0 -0.02 sigma 0.05 0.002 0.02
//! carrying 0 1 0
//! ```
//!
//! `step_length MODEL θ0 θ1 θ2 sigma σ0 σ1 σ2` is required (MODEL: `constant`,
//! `linear`, `linear_as_published`, `linear_frequency_only`, `weinberg`); `carrying X
//! Y Z` (a body-frame direction, normalised on reading) is optional. Files over
//! [`crate::calibration::MAX_CALIBRATION_BYTES`] or with more than
//! [`crate::calibration::MAX_CALIBRATION_LINES`] lines, a
//! wrong first line, unknown or repeated records, wrong counts, non-numbers,
//! non-finite values or σ ≤ 0 are typed [`CalibrationError`]s. Writing then reading
//! is exact (shortest round-trip floats).

use std::fmt::Write as _;

pub use crate::calibration::CalibrationError;
use crate::calibration::{self as text, records};
use crate::steplength::StepLengthModel;

/// First line of a calibration file (without the version).
pub const CALIBRATION_MAGIC: &str = "stridekit-pdr-calibration";
/// The format version this build reads and writes.
pub const CALIBRATION_VERSION: u32 = 1;

/// What is personal in PDR (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PdrCalibration {
    pub step_length_model: StepLengthModel,
    /// θ of `L = θ·x` (features per model: see `crate::steplength`).
    pub step_length_theta: [f64; 3],
    /// 1-σ of θ.
    pub step_length_sigma: [f64; 3],
    /// Walking direction in the phone's body frame (unit), if the user carries the
    /// phone one way.
    pub carrying_body: Option<[f64; 3]>,
}

fn model_name(m: StepLengthModel) -> &'static str {
    match m {
        StepLengthModel::Constant => "constant",
        StepLengthModel::Linear => "linear",
        StepLengthModel::LinearAsPublished => "linear_as_published",
        StepLengthModel::LinearFrequencyOnly => "linear_frequency_only",
        StepLengthModel::Weinberg => "weinberg",
        StepLengthModel::Pendulum => "pendulum",
    }
}

fn model_from_name(s: &str) -> Option<StepLengthModel> {
    StepLengthModel::ALL
        .into_iter()
        .find(|m| model_name(*m) == s)
}

impl PdrCalibration {
    /// Check every value.
    pub fn validate(&self) -> Result<(), CalibrationError> {
        let bad = |field, reason: &str| {
            Err(CalibrationError::Invalid {
                field,
                reason: reason.to_string(),
            })
        };
        if !self.step_length_theta.iter().all(|v| v.is_finite()) {
            return bad("step_length_theta", "must be finite");
        }
        if !self
            .step_length_sigma
            .iter()
            .all(|v| v.is_finite() && *v > 0.0 && *v < 100.0)
        {
            return bad("step_length_sigma", "must be in (0, 100)");
        }
        if let Some(f) = self.carrying_body {
            let n = f.iter().map(|v| v * v).sum::<f64>().sqrt();
            if !(n.is_finite() && (n - 1.0).abs() < 1e-6) {
                return bad("carrying_body", "must be a unit vector");
            }
        }
        Ok(())
    }

    /// The calibration as text (format version 1); `comments` become `#` lines.
    pub fn to_text(&self, comments: &[String]) -> String {
        let mut s = text::header(CALIBRATION_MAGIC, CALIBRATION_VERSION, comments);
        let [t0, t1, t2] = self.step_length_theta;
        let [s0, s1, s2] = self.step_length_sigma;
        let _ = writeln!(
            s,
            "step_length {} {t0:?} {t1:?} {t2:?} sigma {s0:?} {s1:?} {s2:?}",
            model_name(self.step_length_model)
        );
        if let Some([x, y, z]) = self.carrying_body {
            let _ = writeln!(s, "carrying {x:?} {y:?} {z:?}");
        }
        s
    }

    /// Parse a calibration text (see the module docs).
    pub fn parse(text: &str) -> Result<Self, CalibrationError> {
        let mut step: Option<(StepLengthModel, [f64; 3], [f64; 3])> = None;
        let mut carrying: Option<[f64; 3]> = None;
        for r in records(text, CALIBRATION_MAGIC, CALIBRATION_VERSION)? {
            match r.name() {
                "step_length" => {
                    if step.is_some() {
                        return Err(r.error("a second step_length record"));
                    }
                    let layout = "step_length MODEL θ0 θ1 θ2 sigma σ0 σ1 σ2";
                    r.expect_fields(9, layout)?;
                    if r.fields[5] != "sigma" {
                        return Err(r.error(format!("expected: {layout}")));
                    }
                    let model = model_from_name(r.fields[1]).ok_or_else(|| {
                        r.error(format!(
                            "unknown step-length model {:?}",
                            text::truncate(r.fields[1])
                        ))
                    })?;
                    let theta = [r.number(2)?, r.number(3)?, r.number(4)?];
                    let sigma = [r.number(6)?, r.number(7)?, r.number(8)?];
                    step = Some((model, theta, sigma));
                }
                "carrying" => {
                    if carrying.is_some() {
                        return Err(r.error("a second carrying record"));
                    }
                    r.expect_fields(4, "carrying X Y Z")?;
                    let v = [r.number(1)?, r.number(2)?, r.number(3)?];
                    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
                    if n.is_nan() || n <= 1e-6 {
                        return Err(r.error("carrying direction is zero"));
                    }
                    // Normalised once: a unit vector (as written) is kept bit for bit.
                    carrying = Some(if (n - 1.0).abs() < 1e-9 {
                        v
                    } else {
                        v.map(|x| x / n)
                    });
                }
                other => return Err(r.error(format!("unknown record {:?}", text::truncate(other)))),
            }
        }
        let (step_length_model, step_length_theta, step_length_sigma) =
            step.ok_or(CalibrationError::Missing("step_length"))?;
        let c = Self {
            step_length_model,
            step_length_theta,
            step_length_sigma,
            carrying_body: carrying,
        };
        c.validate()?;
        Ok(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> PdrCalibration {
        PdrCalibration {
            step_length_model: StepLengthModel::Linear,
            step_length_theta: [0.31, 0.0012, 0.1234567890123],
            step_length_sigma: [0.02, 0.001, 0.01],
            carrying_body: Some([0.0, 1.0, 0.0]),
        }
    }

    #[test]
    fn text_round_trips_exactly() {
        let c = sample();
        let t = c.to_text(&["trained by: test".into(), "two\nlines".into()]);
        assert!(t.starts_with("stridekit-pdr-calibration 1\n# trained by: test\n# two\n# lines\n"));
        assert_eq!(PdrCalibration::parse(&t).unwrap(), c);
        // A direction that is not unit is normalised, then stable.
        let odd = t.replace("carrying 0.0 1.0 0.0", "carrying 0.08 0.996 0");
        let once = PdrCalibration::parse(&odd).unwrap();
        assert_eq!(PdrCalibration::parse(&once.to_text(&[])).unwrap(), once);
        let no_carry = PdrCalibration {
            carrying_body: None,
            ..c
        };
        assert_eq!(
            PdrCalibration::parse(&no_carry.to_text(&[])).unwrap(),
            no_carry
        );
    }

    #[test]
    fn bad_texts_are_typed_errors() {
        use CalibrationError as E;
        let ok = sample().to_text(&[]);
        let parse = PdrCalibration::parse;
        assert!(matches!(parse(""), Err(E::NotCalibration { .. })));
        assert!(matches!(
            parse("stridekit-odometry 2\n"),
            Err(E::NotCalibration { .. })
        ));
        assert!(matches!(
            parse(&ok.replace("calibration 1", "calibration 2")),
            Err(E::Version { .. })
        ));
        assert!(matches!(
            parse("stridekit-pdr-calibration 1\n"),
            Err(E::Missing(_))
        ));
        for (bad, what) in [
            (ok.replace("linear", "quadratic"), "model"),
            (ok.replace("0.31", "NaN"), "NaN"),
            (ok.replace("0.31", "x"), "text"),
            (ok.replace(" sigma", " sigmas"), "layout"),
            (ok.replace("carrying 0.0 1.0 0.0", "carrying 0 0 0"), "zero"),
            (ok.replace("carrying 0.0 1.0 0.0", "carrying 1 2"), "count"),
            (format!("{ok}carrying 1 0 0\n"), "repeat"),
            (format!("{ok}bias 1 2 3\n"), "unknown"),
        ] {
            assert!(matches!(parse(&bad), Err(E::Line { .. })), "{what}: {bad}");
        }
        assert!(matches!(
            parse(&ok.replace("sigma 0.02", "sigma -0.02")),
            Err(E::Invalid { .. })
        ));
        let huge = format!("{ok}{}", "#\n".repeat(40_000));
        assert!(matches!(parse(&huge), Err(E::TooLarge { .. })));
        let long = format!("{ok}{}", "#\n".repeat(1200));
        assert!(matches!(parse(&long), Err(E::TooManyLines { .. })));
    }
}
