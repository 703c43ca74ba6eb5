//! One magnetometer sample seen in E' (the earth frame up to the heading): the
//! field's magnitude, its dip below the horizontal and the heading offset it
//! measures.

use super::heading::UNKNOWN_VAR_RAD2;
use crate::angle::atan2;

/// A field sample seen in E'.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Field {
    pub(crate) norm_ut: f64,
    pub(crate) dip_rad: f64,
    pub(crate) heading_rad: f64,
    /// tan² of the dip (how much a tilt error turns the measured heading, squared).
    pub(crate) tan2_dip: f64,
}

/// Magnitude, dip and measured heading offset of a field sample `e` seen in E', or
/// `None` for a zero field (angles by the fast [`atan2`], within 2e-6 rad of libm's).
#[inline(always)]
pub(crate) fn measure(e: &[f64; 3]) -> Option<Field> {
    let h2 = e[0] * e[0] + e[1] * e[1];
    let n2 = h2 + e[2] * e[2];
    if n2 <= 0.0 {
        return None;
    }
    let h = h2.sqrt();
    Some(Field {
        norm_ut: n2.sqrt(),
        dip_rad: atan2(-e[2], h),
        tan2_dip: if h2 > 0.0 {
            e[2] * e[2] / h2
        } else {
            UNKNOWN_VAR_RAD2
        },
        // Rz(δ) must turn the horizontal field (azimuth ψ east of north) to north:
        // δ = ψ.
        heading_rad: atan2(e[0], e[1]),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn magnitude_dip_and_heading_of_a_field() {
        // 20 µT north-east horizontal, 40 µT down.
        let h = 20.0 / 2f64.sqrt();
        let f = measure(&[h, h, -40.0]).unwrap();
        assert!((f.norm_ut - 2000f64.sqrt()).abs() < 1e-12);
        // Angles by the fast atan2: within 1e-8 rad (its measured error is 4e-9).
        assert!((f.dip_rad - 2f64.atan()).abs() < 1e-8);
        assert!((f.heading_rad - std::f64::consts::FRAC_PI_4).abs() < 1e-8);
        assert!((f.tan2_dip - 4.0).abs() < 1e-12);
        assert!(measure(&[0.0; 3]).is_none());
        assert_eq!(
            measure(&[0.0, 0.0, -40.0]).unwrap().tan2_dip,
            UNKNOWN_VAR_RAD2
        );
    }
}
