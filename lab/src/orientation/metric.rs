//! BROAD's error metric (Laidig et al. 2021, the benchmark's own definition):
//! the error quaternion in the earth frame, e = q_est ⊗ q_truth⁻¹, its total angle
//! 2·acos|e_w|, its heading part (rotation about the vertical) 2·atan(|e_z / e_w|)
//! and its inclination part 2·acos √(e_w² + e_z²); the RMSE of each over the samples
//! of the movement phases that have truth (occluded markers are skipped), in degrees.
//! Evaluation code: lives in the CLI, not in the shipped core.

/// Sums of squared errors of one trial.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorSums {
    pub n: usize,
    pub total2: f64,
    pub heading2: f64,
    pub inclination2: f64,
}

/// RMSE of the three errors, degrees.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rmse {
    pub total_deg: f64,
    pub heading_deg: f64,
    pub inclination_deg: f64,
}

/// The three error angles (total, heading, inclination), radians, of an estimate
/// against the truth (both body → earth, `[w, x, y, z]`, any norm).
pub fn error_angles(est: &[f64; 4], truth: &[f64; 4]) -> (f64, f64, f64) {
    let n = |q: &[f64; 4]| (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    let (ne, nt) = (n(est), n(truth));
    let a = est.map(|c| c / ne);
    // truth⁻¹ = conjugate of the unit quaternion.
    let b = [
        truth[0] / nt,
        -truth[1] / nt,
        -truth[2] / nt,
        -truth[3] / nt,
    ];
    let e = [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ];
    let ne = n(&e);
    let (w, z) = (e[0] / ne, e[3] / ne);
    let total = 2.0 * w.abs().min(1.0).acos();
    let heading = 2.0 * z.abs().atan2(w.abs());
    let inclination = 2.0 * (w * w + z * z).sqrt().min(1.0).acos();
    (total, heading, inclination)
}

impl ErrorSums {
    /// Add one scored sample.
    pub fn add(&mut self, est: &[f64; 4], truth: &[f64; 4]) {
        let (t, h, i) = error_angles(est, truth);
        self.n += 1;
        self.total2 += t * t;
        self.heading2 += h * h;
        self.inclination2 += i * i;
    }

    pub fn rmse(&self) -> Rmse {
        let r = |s: f64| (s / self.n.max(1) as f64).sqrt().to_degrees();
        if self.n == 0 {
            return Rmse {
                total_deg: f64::NAN,
                heading_deg: f64::NAN,
                inclination_deg: f64::NAN,
            };
        }
        Rmse {
            total_deg: r(self.total2),
            heading_deg: r(self.heading2),
            inclination_deg: r(self.inclination2),
        }
    }
}

impl Rmse {
    /// Mean over trials (BROAD averages the per-trial RMSEs).
    pub fn mean<'a>(items: impl IntoIterator<Item = &'a Rmse>) -> Rmse {
        let (mut t, mut h, mut i, mut n) = (0.0, 0.0, 0.0, 0usize);
        for r in items {
            t += r.total_deg;
            h += r.heading_deg;
            i += r.inclination_deg;
            n += 1;
        }
        let n = n.max(1) as f64;
        Rmse {
            total_deg: t / n,
            heading_deg: h / n,
            inclination_deg: i / n,
        }
    }

    /// `total / heading / inclination` with two decimals.
    pub fn cell(&self) -> String {
        format!(
            "{:.2} / {:.2} / {:.2}",
            self.total_deg, self.heading_deg, self.inclination_deg
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axis_angle(axis: [f64; 3], angle: f64) -> [f64; 4] {
        let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
        let s = (0.5 * angle).sin() / n;
        [(0.5 * angle).cos(), axis[0] * s, axis[1] * s, axis[2] * s]
    }

    fn mul(a: &[f64; 4], b: &[f64; 4]) -> [f64; 4] {
        [
            a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
            a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
            a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
            a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
        ]
    }

    #[test]
    fn heading_and_inclination_parts_separate() {
        let truth = axis_angle([0.3, -1.0, 0.5], 1.1);
        // An error of 4° about the vertical (earth frame: left-multiplied).
        let est = mul(&axis_angle([0.0, 0.0, 1.0], 4f64.to_radians()), &truth);
        let (t, h, i) = error_angles(&est, &truth);
        assert!((t.to_degrees() - 4.0).abs() < 1e-9);
        assert!((h.to_degrees() - 4.0).abs() < 1e-9);
        assert!(i.abs() < 1e-6);
        // 3° about a horizontal earth axis: inclination only.
        let est = mul(&axis_angle([1.0, 1.0, 0.0], -3f64.to_radians()), &truth);
        let (t, h, i) = error_angles(&est, &truth);
        assert!((t.to_degrees() - 3.0).abs() < 1e-9);
        assert!(h.abs() < 1e-9);
        assert!((i.to_degrees() - 3.0).abs() < 1e-9);
        // Sign of the quaternion does not matter; scale neither.
        let neg = est.map(|c| -2.0 * c);
        let (t2, _, i2) = error_angles(&neg, &truth);
        assert!((t2 - t).abs() < 1e-12 && (i2 - i).abs() < 1e-12);
    }

    #[test]
    fn rmse_and_mean() {
        let mut s = ErrorSums::default();
        let id = [1.0, 0.0, 0.0, 0.0];
        s.add(&axis_angle([0.0, 0.0, 1.0], 3f64.to_radians()), &id);
        s.add(&axis_angle([0.0, 0.0, 1.0], -4f64.to_radians()), &id);
        let r = s.rmse();
        assert!((r.heading_deg - 12.5f64.sqrt()).abs() < 1e-9);
        assert!(r.inclination_deg.abs() < 1e-6);
        let m = Rmse::mean(&[r, Rmse::default()]);
        assert!((m.total_deg - r.total_deg / 2.0).abs() < 1e-12);
        assert!(ErrorSums::default().rmse().total_deg.is_nan());
    }
}
