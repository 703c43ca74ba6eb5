//! Reference frames: which earth frame the outputs are expressed in, and how the
//! sensor's axes map onto the body frame.
//!
//! # Earth frame
//! The accelerometer measures *specific force*: at rest it reads +9.81 m/s² along
//! the local **up** direction (Android's convention; iOS Core Motion reports the
//! opposite sign in g and must be multiplied by −9.80665). The magnetometer sees the
//! geomagnetic field, whose horizontal part points to magnetic **north** and which
//! dips downwards in the northern hemisphere. Gravity and the field fix two earth
//! axes; the third follows from a right-handed frame:
//! - [`EarthFrame::Enu`]: x East, y North, z Up (stridekit's default, the frame of
//!   every other engine);
//! - [`EarthFrame::Ned`]: x North, y East, z Down (aerospace).
//!
//! Internally the filter runs in Madgwick's own frame, North-West-Up, and the
//! outputs are rotated by a constant quaternion: `q_ENU = R_z(+90°) ⊗ q_NWU`,
//! `q_NED = R_x(180°) ⊗ q_NWU`. North is *magnetic* north (no declination applied).
//!
//! # Body frame
//! The body frame is the sensor frame after an optional [`AxisRemap`] (Fusion's
//! `FusionAxes` idea): e.g. a watch mounted with its sensor rotated, or an app that
//! wants aerospace forward-right-down axes from a phone's right-up-out axes.

use super::error::AhrsError;

/// Earth frame in which orientation, Euler angles, earth-frame linear acceleration
/// and heading are expressed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum EarthFrame {
    /// x East, y North, z Up.
    #[default]
    Enu,
    /// x North, y East, z Down.
    Ned,
}

/// √½, the half-angle cosine/sine of a 90° rotation.
const SQRT_HALF: f64 = std::f64::consts::FRAC_1_SQRT_2;

impl EarthFrame {
    /// The unit vector pointing up, in this frame.
    pub fn up(self) -> [f64; 3] {
        match self {
            EarthFrame::Enu => [0.0, 0.0, 1.0],
            EarthFrame::Ned => [0.0, 0.0, -1.0],
        }
    }

    /// `q_frame = C ⊗ q_NWU`: the constant rotation from North-West-Up to this frame
    /// (w, x, y, z).
    pub(crate) fn nwu_to_frame(self) -> [f64; 4] {
        match self {
            EarthFrame::Enu => [SQRT_HALF, 0.0, 0.0, SQRT_HALF],
            EarthFrame::Ned => [0.0, 1.0, 0.0, 0.0],
        }
    }

    /// `q_frame = C ⊗ q_ENU`: the constant rotation from East-North-Up to this frame
    /// (NED: 180° about (1, 1, 0)/√2, which swaps x and y and negates z).
    pub(crate) fn enu_to_frame(self) -> [f64; 4] {
        match self {
            EarthFrame::Enu => [1.0, 0.0, 0.0, 0.0],
            EarthFrame::Ned => [0.0, SQRT_HALF, SQRT_HALF, 0.0],
        }
    }

    pub(crate) fn to_u8(self) -> u8 {
        match self {
            EarthFrame::Enu => 0,
            EarthFrame::Ned => 1,
        }
    }

    pub(crate) fn from_u8(v: u8) -> Option<Self> {
        match v {
            0 => Some(EarthFrame::Enu),
            1 => Some(EarthFrame::Ned),
            _ => None,
        }
    }
}

/// A proper rotation of the sensor axes by a signed permutation, applied to the
/// gyroscope, accelerometer and magnetometer at the door:
/// `body[i] = sign[i] · sensor[source[i]]`.
///
/// Only right-handed remaps are accepted (determinant +1): a mirror would make the
/// gyroscope and the accelerometer disagree about the sense of rotation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisRemap {
    source: [usize; 3],
    /// ±1.0 (multiplication by ±1 is exact).
    sign: [f64; 3],
}

impl Default for AxisRemap {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl AxisRemap {
    /// Body axes = sensor axes.
    pub const IDENTITY: Self = Self {
        source: [0, 1, 2],
        sign: [1.0, 1.0, 1.0],
    };

    /// `body[i] = (negate[i] ? −1 : +1) · sensor[source[i]]`. `source` must be a
    /// permutation of 0, 1, 2 and the result a rotation (not a mirror).
    pub fn new(source: [usize; 3], negate: [bool; 3]) -> Result<Self, AhrsError> {
        let mut seen = [false; 3];
        for &s in &source {
            if s > 2 || seen[s] {
                return Err(AhrsError::InvalidSettings {
                    field: "axis_remap",
                    reason: "source must be a permutation of 0, 1, 2",
                });
            }
            seen[s] = true;
        }
        // Parity of the permutation (number of inversions) times the signs.
        let inversions = (source[0] > source[1]) as u8
            + (source[0] > source[2]) as u8
            + (source[1] > source[2]) as u8;
        let negations = negate.iter().filter(|&&n| n).count() as u8;
        if (inversions + negations) % 2 == 1 {
            return Err(AhrsError::InvalidSettings {
                field: "axis_remap",
                reason: "a mirror (determinant −1), not a rotation",
            });
        }
        let sign = negate.map(|n| if n { -1.0 } else { 1.0 });
        Ok(Self { source, sign })
    }

    /// Which sensor axis feeds each body axis.
    pub fn source(&self) -> [usize; 3] {
        self.source
    }

    /// Whether each body axis is negated.
    pub fn negate(&self) -> [bool; 3] {
        self.sign.map(|s| s < 0.0)
    }

    /// A sensor-frame vector in the body frame.
    #[inline]
    pub fn apply(&self, v: [f64; 3]) -> [f64; 3] {
        [
            self.sign[0] * v[self.source[0]],
            self.sign[1] * v[self.source[1]],
            self.sign[2] * v[self.source[2]],
        ]
    }
}

impl AxisRemap {
    /// Snapshot codec: per body axis, its sensor axis (u8) and whether it is negated.
    pub(crate) fn write(&self, w: &mut crate::snapshot::Writer) {
        for (src, neg) in self.source().iter().zip(self.negate()) {
            w.u8(*src as u8);
            w.bool(neg);
        }
    }

    /// Read what [`Self::write`] wrote; a remap that is not a rotation is refused.
    pub(crate) fn read(
        r: &mut crate::snapshot::Reader,
    ) -> Result<Self, crate::snapshot::SnapshotError> {
        let mut source = [0usize; 3];
        let mut negate = [false; 3];
        for i in 0..3 {
            source[i] = r.u8()? as usize;
            negate[i] = r.bool()?;
        }
        Self::new(source, negate).map_err(|_| crate::snapshot::SnapshotError::Invalid("axis remap"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn remap_validation() {
        assert!(AxisRemap::new([0, 1, 2], [false; 3]).is_ok());
        // Swap x/y and negate z: a 180° rotation about the x = y diagonal.
        let r = AxisRemap::new([1, 0, 2], [false, false, true]).unwrap();
        assert_eq!(r.apply([1.0, 2.0, 3.0]), [2.0, 1.0, -3.0]);
        assert_eq!(r.negate(), [false, false, true]);
        // A plain swap is a mirror.
        assert!(AxisRemap::new([1, 0, 2], [false; 3]).is_err());
        assert!(AxisRemap::new([0, 0, 2], [false; 3]).is_err());
        assert!(AxisRemap::new([0, 1, 3], [false; 3]).is_err());
        // Cyclic permutation: a rotation.
        assert!(AxisRemap::new([1, 2, 0], [false; 3]).is_ok());
        assert!(AxisRemap::new([0, 1, 2], [true, true, false]).is_ok());
    }

    #[test]
    fn frames_roundtrip() {
        for f in [EarthFrame::Enu, EarthFrame::Ned] {
            assert_eq!(EarthFrame::from_u8(f.to_u8()), Some(f));
        }
        assert_eq!(EarthFrame::from_u8(7), None);
    }
}
