//! One stride's horizontal acceleration statistics: its principal axis (the walking
//! axis, up to sign) and the gait cue that tells forward from backward (how the
//! acceleration along the axis co-varies with the vertical velocity).

/// A stride with fewer samples has no axis.
const MIN_STRIDE_SAMPLES: f64 = 8.0;
/// Floor of the across-axis variance in the along/across ratio, (m/s²)².
const MIN_ACROSS_VAR: f64 = 1e-12;
/// Time constant of the leaky vertical velocity, s (keeps it bounded).
const VZ_LEAK_TAU_S: f64 = 1.0;

/// The stride being accumulated: its sums, its steps so far and the vertical velocity.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Stride {
    pub(super) sums: StrideStats,
    /// Steps since the last stride closed (0 or 1).
    pub(super) steps: u32,
    /// Vertical velocity (integrated vertical acceleration, leaky), m/s.
    pub(super) vz_mps: f64,
}

impl Stride {
    /// One sample of linear acceleration in ENU, m/s², `dt` after the previous one.
    pub(super) fn push(&mut self, dt: f64, lin_acc_enu_mps2: [f64; 3]) {
        let [e, n, up] = lin_acc_enu_mps2;
        self.vz_mps = self.vz_mps * (1.0 - dt / VZ_LEAK_TAU_S) + up * dt;
        self.sums.add(e, n, self.vz_mps);
    }

    /// A step: every second one closes the stride and returns its statistics.
    pub(super) fn push_step(&mut self) -> Option<StrideStats> {
        self.steps += 1;
        if self.steps < 2 {
            return None;
        }
        self.steps = 0;
        Some(std::mem::take(&mut self.sums))
    }
}

/// Accumulated horizontal acceleration statistics over one stride.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct StrideStats {
    pub(super) n: f64,
    pub(super) se: f64,
    pub(super) sn: f64,
    pub(super) see: f64,
    pub(super) snn: f64,
    pub(super) sen: f64,
    /// Vertical velocity (integrated vertical acceleration) and its products with the
    /// horizontal components, for the forward/backward cue.
    pub(super) svz: f64,
    pub(super) sevz: f64,
    pub(super) snvz: f64,
}

impl StrideStats {
    fn add(&mut self, e: f64, n: f64, vz: f64) {
        self.n += 1.0;
        self.se += e;
        self.sn += n;
        self.see += e * e;
        self.snn += n * n;
        self.sen += e * n;
        self.svz += vz;
        self.sevz += e * vz;
        self.snvz += n * vz;
    }

    /// Principal axis azimuth (mod π) and the along/across variance ratio.
    pub(super) fn axis(&self) -> Option<(f64, f64)> {
        if self.n < MIN_STRIDE_SAMPLES {
            return None;
        }
        let (me, mn) = (self.se / self.n, self.sn / self.n);
        let cee = self.see / self.n - me * me;
        let cnn = self.snn / self.n - mn * mn;
        let cen = self.sen / self.n - me * mn;
        let tr = cee + cnn;
        let det = cee * cnn - cen * cen;
        let disc = (0.25 * tr * tr - det).max(0.0).sqrt();
        let (l1, l2) = (0.5 * tr + disc, (0.5 * tr - disc).max(MIN_ACROSS_VAR));
        // Eigenvector of l1: angle of (e, n) measured as an azimuth (from north, cw).
        let az = 0.5 * (2.0 * cen).atan2(cnn - cee);
        Some((az, l1 / l2))
    }

    /// Covariance between acceleration along azimuth `az` and vertical velocity.
    pub(super) fn forward_vz_cov(&self, az: f64) -> f64 {
        let (s, c) = az.sin_cos();
        let n = self.n.max(1.0);
        let a_mean = (s * self.se + c * self.sn) / n;
        let vz_mean = self.svz / n;
        (s * self.sevz + c * self.snvz) / n - a_mean * vz_mean
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stride along azimuth `az` (back and forth, `a` m/s²) with vertical velocity
    /// in phase (`sign` +1) or in anti-phase (−1) with the forward acceleration.
    fn stride(az: f64, a: f64, sign: f64) -> StrideStats {
        let mut s = StrideStats::default();
        for i in 0..100 {
            let ph = i as f64 * 0.0628;
            let fwd = a * ph.sin();
            let side = 0.1 * a * ph.cos();
            let e = fwd * az.sin() + side * az.cos();
            let n = fwd * az.cos() - side * az.sin();
            s.add(e, n, sign * ph.sin());
        }
        s
    }

    #[test]
    fn the_axis_is_the_direction_of_largest_variance_mod_pi() {
        for az in [0.3, 1.2, -1.0] {
            let (axis, ratio) = stride(az, 2.0, 1.0).axis().unwrap();
            assert!((axis - az).abs() < 1e-3, "{az}: {axis}");
            assert!((ratio - 100.0).abs() < 5.0, "{ratio}");
        }
        let (axis, _) = stride(2.5, 2.0, 1.0).axis().unwrap();
        assert!((axis - (2.5 - std::f64::consts::PI)).abs() < 1e-3);
        assert!(StrideStats::default().axis().is_none());
    }

    #[test]
    fn the_gait_cue_is_the_sign_of_forward_vertical_covariance() {
        assert!(stride(0.4, 2.0, 1.0).forward_vz_cov(0.4) > 0.0);
        assert!(stride(0.4, 2.0, -1.0).forward_vz_cov(0.4) < 0.0);
    }

    #[test]
    fn every_second_step_closes_the_stride() {
        let mut s = Stride::default();
        s.push(0.01, [1.0, 0.0, 0.5]);
        assert!(s.push_step().is_none());
        let closed = s.push_step().unwrap();
        assert_eq!(closed.n, 1.0);
        assert_eq!(s.sums, StrideStats::default());
        assert_eq!(s.vz_mps, 0.005);
    }
}
