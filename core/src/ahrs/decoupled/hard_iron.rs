//! Hard iron: a constant magnetometer offset in the body frame (magnetised parts of
//! the device, or a magnet fixed to it), learned online from the gyroscope, with no
//! calibration dance.
//!
//! The Earth's field is fixed in the gyroscope's almost-inertial frame I. Between an
//! anchor reading `m_a` and a later reading `m`, with `C` the body rotation between
//! them (from the strapdown `q_gyr`), `m − b = C (m_a − b)`, i.e.
//! `m − C m_a = (I − C) b`: linear in the offset `b`. A three-state Kalman filter takes
//! one such measurement whenever the body has turned by [`MIN_TURN_RAD`] since the
//! anchor (a turn shows `b` across its axis; the component along the axis needs a turn
//! about another axis), and the reading becomes the next anchor: a few checks per
//! second and one 3×3 update per turn, nothing on the other samples. A measurement the
//! model does not explain (a field that changed in space: a magnet passed, steel
//! nearby) is refused by its χ² ([`GATE_CHI2`]); an anchor older than [`MAX_SPAN_S`]
//! (gyroscope drift) is replaced without a measurement. The variance says how well
//! `b` is known (flag `mag_calibrating` while it is not); the offset wanders as a
//! random walk ([`RANDOM_WALK_UT`]) so a slowly drifting offset is followed.

use crate::ahrs::quat::{self, Quat};

/// The body must have turned this far since the anchor before a measurement, rad
/// (10°): |I − C| = 2 sin(θ/2) ≈ 0.17 then, so a 1 µT reading noise tells `b` to
/// ≈8 µT across the axis in one step and to ≈1 µT after a few dozen (a few seconds of
/// hand motion); smaller turns drown in the noise, larger ones come too seldom
/// (measured on BROAD: 20° converges later, 6° learns more of the field's gradients).
pub const MIN_TURN_RAD: f64 = 10.0 * std::f64::consts::PI / 180.0;
/// An anchor older than this is replaced without a measurement, s: both readings
/// must see the same field, and a hand or a walker carries the device some decimetres
/// in a second, through the field gradients of a building (measured on BROAD: 1 s
/// against 10 s, 2.22° against 2.24° unperturbed, 3.57° against 3.73° with a 10 µT
/// drift, 7.27° against 7.12° with a 10 µT offset). Fast turns teach the offset.
pub const MAX_SPAN_S: f64 = 1.0;
/// Noise of one reading per axis, µT: magnetometer noise and the field's
/// inhomogeneity over the few centimetres a hand moves the device while turning it.
pub const READING_NOISE_UT: f64 = 1.0;
/// Random walk of the offset, µT/√s: a drift of ≈0.1 µT/s (temperature, a changing
/// current in the device) is followed within seconds, a still one is held to a few
/// tenths of a µT.
pub const RANDOM_WALK_UT: f64 = 0.1;
/// χ² of a measurement above which it is refused (3 degrees of freedom, p = 0.001):
/// the field changed in space between the two readings.
pub const GATE_CHI2: f64 = 16.3;
/// The offset counts as known (flag `mag_calibrating` off) once its standard deviation
/// is below this on every axis, µT (≈8° of heading over a 20 µT horizontal field, at
/// most; the estimate keeps improving with every turn after).
pub const KNOWN_UT: f64 = 3.0;
/// Weight of one measurement in the running share of refused ones (a memory of ≈10
/// measurements, a few seconds of hand motion).
pub const REFUSAL_WEIGHT: f64 = 0.1;
/// A running share of refused measurements above this means the offset itself changed
/// (a magnet fixed to the device, or taken off it): the estimate is relearned from its
/// prior (a field that varies in space fails now and then, a changed offset always).
pub const REFUSED_SHARE_RELEARN: f64 = 0.9;
/// A smallest variance kept on the diagonal, µT² (rounding guard).
pub(crate) const MIN_VAR_UT2: f64 = 1e-6;

/// What [`HardIron::observe`] did with one reading.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Observed {
    /// How far the estimate moved, µT (0 without a measurement).
    pub(crate) shift_ut: f64,
}

/// The offset estimate and its anchor.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct HardIron {
    /// Offset, body frame, µT, and its covariance, µT².
    pub(crate) b: [f64; 3],
    pub(crate) p: [[f64; 3]; 3],
    /// The anchor reading (raw, µT), the strapdown at it, and whether there is one.
    pub(crate) anchor_ut: [f64; 3],
    pub(crate) anchor_q: Quat,
    pub(crate) anchored: bool,
    /// Time since the anchor and since the covariance was last predicted, s.
    pub(crate) anchor_age_s: f64,
    pub(crate) unpredicted_s: f64,
    /// Running share of measurements refused (0..1).
    pub(crate) refused_share: f64,
}

impl HardIron {
    /// Nothing known: offset 0 with variance `max_ut`² per axis.
    pub(crate) fn new(max_ut: f64) -> Self {
        let v = (max_ut * max_ut).max(MIN_VAR_UT2);
        Self {
            p: [[v, 0.0, 0.0], [0.0, v, 0.0], [0.0, 0.0, v]],
            anchor_q: [1.0, 0.0, 0.0, 0.0],
            ..Self::default()
        }
    }

    /// The offset is not yet known to [`KNOWN_UT`] on some axis.
    pub(crate) fn calibrating(&self) -> bool {
        let k2 = KNOWN_UT * KNOWN_UT;
        (self.p[0][0] > k2) | (self.p[1][1] > k2) | (self.p[2][2] > k2)
    }

    /// Forget the anchor (a restart, or a rotation the gyroscope may have missed).
    pub(crate) fn drop_anchor(&mut self) {
        self.anchored = false;
    }

    /// One raw reading `m` with the strapdown `q_gyr` (body → I), `dt` s after the
    /// previous one; `max_ut` bounds every component of the offset.
    #[inline(always)]
    pub(crate) fn observe(&mut self, m: &[f64; 3], q_gyr: &Quat, dt: f64, max_ut: f64) -> Observed {
        self.anchor_age_s += dt;
        self.unpredicted_s += dt;
        if !self.anchored || self.anchor_age_s > MAX_SPAN_S {
            self.set_anchor(m, q_gyr);
            return Observed::default();
        }
        // Anchor body → current body: conj(q_gyr) ⊗ anchor_q.
        let q_rel = quat::mul(&quat::conj(q_gyr), &self.anchor_q);
        let half_sin2 = 1.0 - q_rel[0] * q_rel[0];
        let min_half_sin = (0.5 * MIN_TURN_RAD).sin();
        if half_sin2 < min_half_sin * min_half_sin {
            return Observed::default();
        }
        let shift_ut = self.measure(m, &q_rel, max_ut);
        self.set_anchor(m, q_gyr);
        Observed { shift_ut }
    }

    fn set_anchor(&mut self, m: &[f64; 3], q_gyr: &Quat) {
        self.anchor_ut = *m;
        self.anchor_q = *q_gyr;
        self.anchored = true;
        self.anchor_age_s = 0.0;
    }

    /// The Kalman update with y = m − C m_a, H = I − C; returns how far `b` moved (0
    /// when refused).
    #[cold]
    fn measure(&mut self, m: &[f64; 3], q_rel: &Quat, max_ut: f64) -> f64 {
        self.predict(max_ut);
        let c = rotation_matrix(q_rel);
        let cm = quat::rotate(q_rel, &self.anchor_ut);
        let h: [[f64; 3]; 3] =
            std::array::from_fn(|i| std::array::from_fn(|j| (i == j) as u8 as f64 - c[i][j]));
        let hb = mat_vec(&h, &self.b);
        let nu: [f64; 3] = std::array::from_fn(|i| m[i] - cm[i] - hb[i]);
        // S = H P Hᵀ + R, R = 2σ² I (noise of both readings).
        let ph_t = mat_mul_t(&self.p, &h);
        let mut s = mat_mul(&h, &ph_t);
        let r = 2.0 * READING_NOISE_UT * READING_NOISE_UT;
        for (i, row) in s.iter_mut().enumerate() {
            row[i] += r;
        }
        let Some(s_inv) = inverse_sym(&s) else {
            return 0.0;
        };
        let s_nu = mat_vec(&s_inv, &nu);
        let chi2 = nu[0] * s_nu[0] + nu[1] * s_nu[1] + nu[2] * s_nu[2];
        let refused = chi2 > GATE_CHI2;
        self.refused_share += REFUSAL_WEIGHT * (refused as u8 as f64 - self.refused_share);
        if refused {
            if self.refused_share > REFUSED_SHARE_RELEARN {
                self.relearn(max_ut);
            }
            return 0.0;
        }
        // K = P Hᵀ S⁻¹; b += K ν; P = (I − K H) P (symmetrised).
        let k = mat_mul(&ph_t, &s_inv);
        let db = mat_vec(&k, &nu);
        let mut shift2 = 0.0;
        for (b, d) in self.b.iter_mut().zip(db) {
            let new = (*b + d).clamp(-max_ut, max_ut);
            shift2 += (new - *b) * (new - *b);
            *b = new;
        }
        let khp = mat_mul(&mat_mul(&k, &h), &self.p);
        for (row, khp_row) in self.p.iter_mut().zip(khp) {
            for (v, d) in row.iter_mut().zip(khp_row) {
                *v -= d;
            }
        }
        self.symmetrise(max_ut);
        shift2.sqrt()
    }

    /// The offset changed: keep the estimate as a start, with the prior's variance.
    #[cold]
    fn relearn(&mut self, max_ut: f64) {
        let v = (max_ut * max_ut).max(MIN_VAR_UT2);
        self.p = [[v, 0.0, 0.0], [0.0, v, 0.0], [0.0, 0.0, v]];
        self.refused_share = 0.0;
    }

    /// The offset's random walk since the last prediction.
    fn predict(&mut self, max_ut: f64) {
        let q = RANDOM_WALK_UT * RANDOM_WALK_UT * self.unpredicted_s;
        self.unpredicted_s = 0.0;
        for i in 0..3 {
            self.p[i][i] += q;
        }
        self.symmetrise(max_ut);
    }

    /// Symmetric, diagonal within [MIN_VAR_UT2, max_ut²].
    fn symmetrise(&mut self, max_ut: f64) {
        let max_var = (max_ut * max_ut).max(MIN_VAR_UT2);
        for i in 0..3 {
            self.p[i][i] = self.p[i][i].clamp(MIN_VAR_UT2, max_var);
            for j in 0..i {
                let v = 0.5 * (self.p[i][j] + self.p[j][i]);
                self.p[i][j] = v;
                self.p[j][i] = v;
            }
        }
    }
}

type Mat3 = [[f64; 3]; 3];

/// The rotation matrix of unit `q` (v' = R v as [`quat::rotate`]), column by column.
fn rotation_matrix(q: &Quat) -> Mat3 {
    let cols: [[f64; 3]; 3] = std::array::from_fn(|j| {
        let mut e = [0.0; 3];
        e[j] = 1.0;
        quat::rotate(q, &e)
    });
    std::array::from_fn(|i| std::array::from_fn(|j| cols[j][i]))
}

fn mat_vec(a: &Mat3, v: &[f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2])
}

fn mat_mul(a: &Mat3, b: &Mat3) -> Mat3 {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j])
    })
}

/// a · bᵀ.
fn mat_mul_t(a: &Mat3, b: &Mat3) -> Mat3 {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| a[i][0] * b[j][0] + a[i][1] * b[j][1] + a[i][2] * b[j][2])
    })
}

/// Inverse of a symmetric positive-definite 3×3 matrix by cofactors, or `None` when
/// singular.
fn inverse_sym(s: &Mat3) -> Option<Mat3> {
    let c00 = s[1][1] * s[2][2] - s[1][2] * s[2][1];
    let c01 = s[1][2] * s[2][0] - s[1][0] * s[2][2];
    let c02 = s[1][0] * s[2][1] - s[1][1] * s[2][0];
    let det = s[0][0] * c00 + s[0][1] * c01 + s[0][2] * c02;
    if !(det.is_finite() && det > 0.0) {
        return None;
    }
    let c11 = s[0][0] * s[2][2] - s[0][2] * s[2][0];
    let c12 = s[0][1] * s[2][0] - s[0][0] * s[2][1];
    let c22 = s[0][0] * s[1][1] - s[0][1] * s[1][0];
    let inv = 1.0 / det;
    Some([
        [c00 * inv, c01 * inv, c02 * inv],
        [c01 * inv, c11 * inv, c12 * inv],
        [c02 * inv, c12 * inv, c22 * inv],
    ])
}
