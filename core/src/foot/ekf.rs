//! Strapdown mechanisation in the local level ENU frame and its 15-state error-state
//! Kalman filter.
//!
//! Nominal state: attitude `q` (body → ENU), velocity `v`, position `p`, accelerometer
//! bias `b_a`, gyroscope bias `b_g`. Error state `δx = [δp, δv, φ, δb_a, δb_g]`
//! (estimate − truth; `φ` is the attitude error in the ENU frame, `Ĉ = (I + [φ×]) C`).
//! Error dynamics: `δṗ = δv`, `δv̇ = −[f_n×] φ − Ĉ δb_a`, `φ̇ = −Ĉ δb_g`, biases random
//! walks. The covariance is propagated by blocks (F is sparse), then symmetrised with
//! a floor on the diagonal; the zero-velocity update uses `P ← P − K S Kᵀ`, which
//! keeps it symmetric. The attitude variance also grows by the rotation the samples did
//! not resolve (`unresolved.rs`).

use nalgebra::{Matrix3, SMatrix, UnitQuaternion, Vector3};

use super::config::Correction;
use super::types::BodySample;

pub(crate) type Cov = SMatrix<f64, 15, 15>;
pub(crate) const IP: usize = 0;
pub(crate) const IV: usize = 3;
pub(crate) const IA: usize = 6;
pub(crate) const IBA: usize = 9;
pub(crate) const IBG: usize = 12;

/// Smallest variance kept on the diagonal.
const VAR_FLOOR: f64 = 1e-14;
/// Largest variance kept per state (position 1 000 km, velocity 100 m/s, tilt 1 rad,
/// heading π, accelerometer bias 10 m/s², gyroscope bias 1 rad/s, all 1-σ): beyond
/// these the linearised filter means nothing, and capping (by scaling the state's row
/// and column, which keeps P positive semi-definite) keeps it finite.
const VAR_CAP: [f64; 15] = [
    1e12,
    1e12,
    1e12,
    1e4,
    1e4,
    1e4,
    1.0,
    1.0,
    std::f64::consts::PI * std::f64::consts::PI,
    100.0,
    100.0,
    100.0,
    1.0,
    1.0,
    1.0,
];
/// Speed assumed for the position uncertainty across a gap, m/s (a brisk walk: the
/// foot may have gone anywhere within it).
const GAP_SPEED_MPS: f64 = 2.0;
/// Tilt error past which the small-angle error model cannot re-level the foot, rad
/// (90°: beyond it the sine of the error falls as the error grows).
pub(crate) const UPSIDE_DOWN_RAD: f64 = std::f64::consts::FRAC_PI_2;
/// Longest gap the covariance grows with, s (a year; keeps the arithmetic finite).
const MAX_GAP_GROWTH_S: f64 = 3.2e7;

#[inline]
fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Process noise per second.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Noise {
    pub acc_var_per_s: f64,
    pub gyro_var_per_s: f64,
    pub acc_bias_var_per_s: f64,
    pub gyro_bias_var_per_s: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Strapdown {
    pub q: UnitQuaternion<f64>,
    pub v: Vector3<f64>,
    pub p: Vector3<f64>,
    pub ba: Vector3<f64>,
    pub bg: Vector3<f64>,
    pub cov: Cov,
    /// Local gravity magnitude, m/s².
    pub g: f64,
    /// Raw body-frame specific force and rate of the previous sample (the
    /// mechanisation integrates their average with the current one).
    pub prev_f: Vector3<f64>,
    pub prev_w: Vector3<f64>,
}

impl Strapdown {
    pub fn new(
        q: UnitQuaternion<f64>,
        g: f64,
        bg: Vector3<f64>,
        initial_std: &[f64; 15],
        prev_f: Vector3<f64>,
        prev_w: Vector3<f64>,
    ) -> Self {
        let mut cov = Cov::zeros();
        for (i, s) in initial_std.iter().enumerate() {
            cov[(i, i)] = s * s;
        }
        Self {
            q,
            v: Vector3::zeros(),
            p: Vector3::zeros(),
            ba: Vector3::zeros(),
            bg,
            cov,
            g,
            prev_f,
            prev_w,
        }
    }

    /// Advance by one sample `s` (body axes): integrate the bias-corrected rates
    /// (average of this sample and the previous one) over `dt_int` and propagate the
    /// covariance over it, the attitude variance grown by the rotation the samples did
    /// not resolve (`s.unresolved_rad`, about each body axis, turned into the
    /// navigation frame); across a gap (`dt_cov > dt_int`) the rest of the gap only
    /// widens the diagonal (white noise on velocity, attitude and biases, [`GAP_SPEED_MPS`] on
    /// position): the linearised cross-terms over hours would be meaningless and,
    /// fed back by the next zero-velocity update, throw the state kilometres away.
    /// The covariance is left for [`condition`](Self::condition), once per sample
    /// after the zero-velocity update (if any).
    #[inline]
    pub fn propagate(
        &mut self,
        s: &BodySample,
        dt_int: f64,
        dt_cov: f64,
        n: &Noise,
        gyro_interval_mean: bool,
    ) {
        let w_raw = Vector3::from(s.w);
        let f_raw = Vector3::from(s.f);
        // Trapezoidal: the average of this sample and the previous one over the
        // interval (second order; a zero-order hold of the newest sample lags half a
        // step, which matters across dropped samples and at low rates). A gyroscope
        // that reports interval means already stands for the interval.
        let w = if gyro_interval_mean {
            w_raw - self.bg
        } else {
            (w_raw + self.prev_w) * 0.5 - self.bg
        };
        let f = (f_raw + self.prev_f) * 0.5 - self.ba;
        self.prev_w = w_raw;
        self.prev_f = f_raw;
        let half = UnitQuaternion::from_scaled_axis(w * (0.5 * dt_int));
        // Specific force rotated with the mid-interval attitude.
        let q_mid = self.q * half;
        let f_n = q_mid * f;
        self.q = q_mid * half;
        let a = f_n - Vector3::new(0.0, 0.0, self.g);
        let v_old = self.v;
        self.v += a * dt_int;
        self.p += (v_old + self.v) * (0.5 * dt_int);

        let c = *self.q.to_rotation_matrix().matrix();
        self.propagate_cov(&c, &f_n, dt_int, n);
        if s.unresolved_rad != [0.0; 3] {
            let d = Matrix3::from_diagonal(&Vector3::from(s.unresolved_rad.map(|r| r * r)));
            let add = c * d * c.transpose();
            self.cov.fixed_view_mut::<3, 3>(IA, IA).add_assign(&add);
        }
        if s.clip_unknown_mps2 != [0.0; 3] {
            // The velocity change clipped axes did not report (`accel_clip.rs`).
            let d = Matrix3::from_diagonal(&Vector3::from(
                s.clip_unknown_mps2.map(|u| (u * dt_int) * (u * dt_int)),
            ));
            let add = c * d * c.transpose();
            self.cov.fixed_view_mut::<3, 3>(IV, IV).add_assign(&add);
        }
        if dt_cov > dt_int {
            self.widen(dt_cov - dt_int, n);
        }
    }

    /// Samples were lost over a rotation of up to `missed` rad: the attitude may be
    /// off by that much about any axis (capped at the covariance's caps), and the
    /// velocity by what a swinging foot does meanwhile ([`GAP_SPEED_MPS`]). The next
    /// zero-velocity updates then re-level the foot at once instead of trusting the
    /// attitude the gap broke (gravity leaking through a tilt error drives the
    /// position away stride after stride).
    #[cold]
    pub fn lost(&mut self, missed: f64) {
        let var = missed * missed;
        for i in 0..3 {
            self.cov[(IA + i, IA + i)] += var;
            self.cov[(IV + i, IV + i)] += GAP_SPEED_MPS * GAP_SPEED_MPS;
        }
    }

    /// The heading of the foot's x axis, rad (ENU, counter-clockwise from East).
    pub fn toe_yaw(&self) -> f64 {
        let x = self.q * Vector3::x();
        x.y.atan2(x.x)
    }

    /// Add `var` rad² to the heading variance.
    #[cold]
    pub fn widen_heading(&mut self, var: f64) {
        self.cov[(IA + 2, IA + 2)] += var;
    }

    /// Turn the attitude by `angle` rad about the vertical.
    #[cold]
    pub fn turn(&mut self, angle: f64) {
        self.q = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), angle) * self.q;
    }

    /// At rest: if the attitude puts the measured specific force `f_b` (body axes,
    /// gravity alone) more than [`UPSIDE_DOWN_RAD`] from the vertical, roll and pitch
    /// are taken from it (by the smallest rotation that does it) with variance
    /// `tilt_var`, tied to no other state. The error model is of small angles: past
    /// 90° the update turns the attitude the wrong way (a hole in a swing can leave
    /// the foot upside down, the velocity then runs to 20 m/s). Returns whether it did.
    #[cold]
    pub fn relevel_if_upside_down(&mut self, f_b: &Vector3<f64>, tilt_var: f64) -> bool {
        let f = f_b - self.ba;
        if (self.q * f).angle(&Vector3::z()) <= UPSIDE_DOWN_RAD {
            return false;
        }
        // The smallest rotation that puts gravity back up: an error in one axis (the
        // swing's pitch) is undone exactly, where keeping the toe's heading would
        // turn the foot round when the error tipped the toe past the vertical.
        let Some(r) = UnitQuaternion::rotation_between(&(self.q * f), &Vector3::z()) else {
            return false;
        };
        self.q = r * self.q;
        let heading_var = self.cov[(IA + 2, IA + 2)];
        for i in 0..3 {
            self.decouple(IA + i, tilt_var);
        }
        self.cov[(IA + 2, IA + 2)] = heading_var;
        true
    }

    /// State `i` with variance `var` and no covariance with the others.
    fn decouple(&mut self, i: usize, var: f64) {
        for j in 0..15 {
            self.cov[(i, j)] = 0.0;
            self.cov[(j, i)] = 0.0;
        }
        self.cov[(i, i)] = var;
    }

    /// Grow the diagonal of the covariance for `extra` seconds without data.
    #[cold]
    fn widen(&mut self, extra: f64, n: &Noise) {
        let t = extra.min(MAX_GAP_GROWTH_S);
        let pos = (GAP_SPEED_MPS * t).powi(2);
        for i in 0..3 {
            self.cov[(IP + i, IP + i)] += pos;
            self.cov[(IV + i, IV + i)] += n.acc_var_per_s * t;
            self.cov[(IA + i, IA + i)] += n.gyro_var_per_s * t;
            self.cov[(IBA + i, IBA + i)] += n.acc_bias_var_per_s * t;
            self.cov[(IBG + i, IBG + i)] += n.gyro_bias_var_per_s * t;
        }
    }

    fn propagate_cov(&mut self, c: &Matrix3<f64>, f_n: &Vector3<f64>, dt: f64, n: &Noise) {
        let a_va = -skew(f_n) * dt; // δv ← φ
        let a_cb = -c * dt; // δv ← δb_a and φ ← δb_g
                            // P ← F P (row blocks; every increment is computed from the old rows first).
        {
            let p = &self.cov;
            let add_p = p.fixed_rows::<3>(IV) * dt;
            let add_v = a_va * p.fixed_rows::<3>(IA) + a_cb * p.fixed_rows::<3>(IBA);
            let add_a = a_cb * p.fixed_rows::<3>(IBG);
            self.cov.fixed_rows_mut::<3>(IP).add_assign(&add_p);
            self.cov.fixed_rows_mut::<3>(IV).add_assign(&add_v);
            self.cov.fixed_rows_mut::<3>(IA).add_assign(&add_a);
        }
        // P ← P Fᵀ (column blocks, likewise).
        {
            let m = &self.cov;
            let add_p = m.fixed_columns::<3>(IV) * dt;
            let add_v = m.fixed_columns::<3>(IA) * a_va.transpose()
                + m.fixed_columns::<3>(IBA) * a_cb.transpose();
            let add_a = m.fixed_columns::<3>(IBG) * a_cb.transpose();
            self.cov.fixed_columns_mut::<3>(IP).add_assign(&add_p);
            self.cov.fixed_columns_mut::<3>(IV).add_assign(&add_v);
            self.cov.fixed_columns_mut::<3>(IA).add_assign(&add_a);
        }
        for i in 0..3 {
            self.cov[(IV + i, IV + i)] += n.acc_var_per_s * dt;
            self.cov[(IA + i, IA + i)] += n.gyro_var_per_s * dt;
            self.cov[(IBA + i, IBA + i)] += n.acc_bias_var_per_s * dt;
            self.cov[(IBG + i, IBG + i)] += n.gyro_bias_var_per_s * dt;
        }
    }

    /// Symmetrise, cap and floor the diagonal (once per sample, after the
    /// propagation and the zero-velocity update). Returns whether every element is
    /// finite afterwards.
    #[allow(clippy::needless_range_loop)] // (i, j) index pairs read best as such
    pub fn condition(&mut self) -> bool {
        // Column-major storage: `m[j][i]` is element (i, j).
        let m = &mut self.cov.data.0;
        let mut all_finite = true;
        for i in 0..15 {
            for j in (i + 1)..15 {
                let s = 0.5 * (m[j][i] + m[i][j]);
                m[j][i] = s;
                m[i][j] = s;
                all_finite &= s.is_finite();
            }
        }
        let mut capped = false;
        for i in 0..15 {
            let d = self.cov.data.0[i][i];
            if d > VAR_CAP[i] {
                self.cap(i, d);
                capped = true;
            }
            let d = &mut self.cov.data.0[i][i];
            if d.is_nan() || *d < VAR_FLOOR {
                *d = VAR_FLOOR;
            }
            all_finite &= d.is_finite();
        }
        if capped {
            // A cap rescales a row and column (by 0 when the variance was infinite).
            return finite(self.cov.as_slice());
        }
        all_finite
    }

    /// Scale row and column `i` so that the variance becomes the cap.
    #[cold]
    fn cap(&mut self, i: usize, d: f64) {
        let s = if d.is_finite() {
            (VAR_CAP[i] / d).sqrt()
        } else {
            0.0
        };
        for j in 0..15 {
            self.cov[(i, j)] *= s;
            self.cov[(j, i)] *= s;
        }
        self.cov[(i, i)] = VAR_CAP[i];
    }

    /// Zero-velocity update with measurement noise σ (m/s); feeds back what
    /// `correction` says. An update whose normalised innovation squared exceeds
    /// `gate_nis` has its innovation covariance inflated to meet it (the update pulls
    /// part of the way). Returns false (and changes nothing) if the innovation
    /// covariance cannot be inverted. The covariance is left for
    /// [`condition`](Self::condition).
    pub fn zupt(&mut self, sigma_mps: f64, gate_nis: Option<f64>, correction: Correction) -> bool {
        let r = sigma_mps * sigma_mps;
        let s = self.cov.fixed_view::<3, 3>(IV, IV) + Matrix3::from_diagonal_element(r);
        let Some(s_inv) = s.try_inverse() else {
            return false;
        };
        let nis = self.v.dot(&(s_inv * self.v));
        let (s, s_inv) = match gate_nis {
            Some(g) if nis > g => (s * (nis / g), s_inv * (g / nis)),
            _ => (s, s_inv),
        };
        let v = self.v;
        self.update3(IV, &v, &s, &s_inv, correction)
    }

    /// Normalised innovation squared of a zero-angular-rate update (see
    /// [`bias_jump`](Self::bias_jump)); `None` if its covariance cannot be inverted.
    pub fn zaru_nis(&self, w_mean: &Vector3<f64>, r: f64) -> Option<f64> {
        let y = self.bg - w_mean;
        let s = self.cov.fixed_view::<3, 3>(IBG, IBG) + Matrix3::from_diagonal_element(r);
        let s_inv = s.try_inverse()?;
        Some(y.dot(&(s_inv * y)))
    }

    /// Zero-angular-rate update: the foot stood still while the gyroscope read
    /// `w_mean` (body axes, raw) with variance `r` per axis. Returns false (and changes
    /// nothing) if the innovation covariance cannot be inverted or the correction is
    /// not finite.
    #[cold]
    pub fn zaru(&mut self, w_mean: &Vector3<f64>, r: f64) -> bool {
        let y = self.bg - w_mean;
        let s = self.cov.fixed_view::<3, 3>(IBG, IBG) + Matrix3::from_diagonal_element(r);
        let Some(s_inv) = s.try_inverse() else {
            return false;
        };
        self.update3(IBG, &y, &s, &s_inv, Correction::Full)
    }

    /// Zero-angular-rate update after a bias jump: the foot stood still while the
    /// gyroscope read `w_mean` (body axes, raw), so the bias error is `b̂_g − w_mean`
    /// with variance `r` per axis, and the bias moved by more than its random walk
    /// allows: each axis' bias variance first grows by its excess (its innovation
    /// squared over its innovation variance), then the update is taken. Returns false
    /// (and changes nothing) if the innovation covariance cannot be inverted. The
    /// covariance is left for [`condition`](Self::condition).
    #[cold]
    pub fn bias_jump(&mut self, w_mean: &Vector3<f64>, r: f64) -> bool {
        let y = self.bg - w_mean;
        let before = self.cov;
        for i in 0..3 {
            let excess = y[i] * y[i] - self.cov[(IBG + i, IBG + i)] - r;
            if excess > 0.0 {
                self.cov[(IBG + i, IBG + i)] += excess;
            }
        }
        let s = self.cov.fixed_view::<3, 3>(IBG, IBG) + Matrix3::from_diagonal_element(r);
        let Some(s_inv) = s.try_inverse() else {
            self.cov = before;
            return false;
        };
        if !self.update3(IBG, &y, &s, &s_inv, Correction::Full) {
            self.cov = before;
            return false;
        }
        true
    }

    /// The Kalman update of a measurement of the three states from index `i`
    /// (H = [0 … I₃ … 0]) with innovation `y`, its covariance `s` and `s⁻¹`; feeds back
    /// what `correction` says. Returns false (and changes nothing) if the correction is
    /// not finite.
    fn update3(
        &mut self,
        i: usize,
        y: &Vector3<f64>,
        s: &Matrix3<f64>,
        s_inv: &Matrix3<f64>,
        correction: Correction,
    ) -> bool {
        let k = self.cov.fixed_columns::<3>(i) * s_inv; // 15 × 3
        let dx = k * y;
        if !dx.iter().all(|x| x.is_finite()) {
            return false;
        }
        let ks = k * s;
        self.cov -= ks * k.transpose();

        let dp = Vector3::new(dx[IP], dx[IP + 1], dx[IP + 2]);
        let dv = Vector3::new(dx[IV], dx[IV + 1], dx[IV + 2]);
        let mut phi = Vector3::new(dx[IA], dx[IA + 1], dx[IA + 2]);
        let dba = Vector3::new(dx[IBA], dx[IBA + 1], dx[IBA + 2]);
        let dbg = Vector3::new(dx[IBG], dx[IBG + 1], dx[IBG + 2]);
        self.v -= dv;
        match correction {
            Correction::Full => {
                self.p -= dp;
                self.ba -= dba;
                self.bg -= dbg;
            }
            Correction::AsPublished => {
                // Pitch and roll only: drop the vertical (heading) component.
                phi.z = 0.0;
            }
        }
        self.q = UnitQuaternion::from_scaled_axis(-phi) * self.q;
        true
    }

    /// Whether everything but the covariance is finite.
    pub fn state_is_finite(&self) -> bool {
        finite(self.q.coords.as_slice())
            & finite(self.v.as_slice())
            & finite(self.p.as_slice())
            & finite(self.ba.as_slice())
            & finite(self.bg.as_slice())
            & finite(self.prev_f.as_slice())
            & finite(self.prev_w.as_slice())
    }

    pub fn is_finite(&self) -> bool {
        self.state_is_finite() & finite(self.cov.as_slice())
    }
}

/// Whether every value is finite. `x · 0` is ±0 for a finite x and NaN otherwise;
/// four independent sums with no early exit vectorise.
fn finite(s: &[f64]) -> bool {
    let mut acc = [0.0_f64; 4];
    let mut chunks = s.chunks_exact(4);
    for c in &mut chunks {
        for k in 0..4 {
            acc[k] += c[k] * 0.0;
        }
    }
    let mut r = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for x in chunks.remainder() {
        r += x * 0.0;
    }
    r == 0.0
}

use std::ops::AddAssign;
