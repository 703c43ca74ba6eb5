//! The SDK's one random-number generator: xoshiro256** seeded by SplitMix64; normal
//! draws as the sum of four 16-bit uniforms of one draw (Irwin-Hall, scaled to unit
//! variance: tails end at ±3.46 σ, which process noise does not miss), no logarithm, so
//! a step of a thousand particles stays cheap. In-tree so that a seed gives the same
//! numbers in every build (the map engine's particles; the simulators build on it).

use crate::snapshot::{Reader, SnapshotError, Writer};

/// xoshiro256**: its four words are the state (snapshotted by the map engine).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rng {
    s: [u64; 4],
}

/// √3 / 65 536: the sum of four 16-bit uniforms (each k / 65 536) has variance 1/3.
const IRWIN_HALL_SCALE: f64 = 1.732_050_807_568_877_2 / 65_536.0;
/// The mean of that sum, in the same units (4 × 65 535 / 2).
const IRWIN_HALL_MEAN: f64 = 131_070.0;

impl Rng {
    pub fn new(seed: u64) -> Self {
        let mut x = seed;
        let mut next = || {
            x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = x;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        };
        Self {
            s: [next(), next(), next(), next()],
        }
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        let r = self.s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = self.s[1] << 17;
        self.s[2] ^= self.s[0];
        self.s[3] ^= self.s[1];
        self.s[1] ^= self.s[2];
        self.s[0] ^= self.s[3];
        self.s[2] ^= t;
        self.s[3] = self.s[3].rotate_left(45);
        r
    }

    /// Uniform in [0, 1).
    #[inline]
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Standard normal (approximately: see the module docs).
    #[inline]
    pub fn normal(&mut self) -> f64 {
        let r = self.next_u64();
        let sum = (r & 0xFFFF) + (r >> 16 & 0xFFFF) + (r >> 32 & 0xFFFF) + (r >> 48);
        (sum as f64 - IRWIN_HALL_MEAN) * IRWIN_HALL_SCALE
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        self.s.iter().for_each(|&v| w.u64(v));
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let s = [r.u64()?, r.u64()?, r.u64()?, r.u64()?];
        if s == [0; 4] {
            return Err(SnapshotError::Invalid("random state all zero"));
        }
        Ok(Self { s })
    }
}

#[cfg(test)]
mod tests {
    use super::Rng;

    #[test]
    fn normals_have_unit_variance_and_bounded_tails() {
        let mut r = Rng::new(3);
        let n = 200_000;
        let xs: Vec<f64> = (0..n).map(|_| r.normal()).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        assert!(
            mean.abs() < 0.01 && (var - 1.0).abs() < 0.01,
            "{mean} {var}"
        );
        assert!(xs.iter().all(|x| x.abs() <= 3.4642));
        let u: Vec<f64> = (0..1000).map(|_| r.uniform()).collect();
        assert!(u.iter().all(|u| (0.0..1.0).contains(u)));
        assert_eq!(Rng::new(9).next_u64(), Rng::new(9).next_u64());
    }
}
