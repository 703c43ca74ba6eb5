//! The local magnetic field as a magnetometer sees it however it turns: a strength and
//! a dip. A sample whose strength or dip departs from the learned ones by more than a
//! gate is disturbed (steel, magnets, electronics); the decoupled filter and the
//! walking direction of PDR share this test.

/// How far a field sample may depart from the learned field and still be undisturbed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FieldGate {
    /// Strength, µT.
    pub(crate) strength_ut: f64,
    /// Dip (angle below the horizontal), rad.
    pub(crate) dip_rad: f64,
}

impl FieldGate {
    /// Whether a sample (`strength_ut`, `dip_rad`) departs from the reference
    /// (`ref_strength_ut`, `ref_dip_rad`) by more than the gate in either.
    /// Branch-free: whether a field is disturbed follows the data.
    #[inline(always)]
    pub(crate) fn departs(
        &self,
        strength_ut: f64,
        dip_rad: f64,
        ref_strength_ut: f64,
        ref_dip_rad: f64,
    ) -> bool {
        ((strength_ut - ref_strength_ut).abs() > self.strength_ut)
            | ((dip_rad - ref_dip_rad).abs() > self.dip_rad)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn either_strength_or_dip_beyond_the_gate_is_a_departure() {
        let gate = FieldGate {
            strength_ut: 6.0,
            dip_rad: 0.14,
        };
        assert!(!gate.departs(48.0, 1.1, 45.0, 1.0));
        assert!(gate.departs(52.0, 1.0, 45.0, 1.0));
        assert!(gate.departs(45.0, 0.8, 45.0, 1.0));
        assert!(
            !gate.departs(51.0, 1.14, 45.0, 1.0),
            "at the gate is within it"
        );
    }
}
