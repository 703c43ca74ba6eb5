//! The engine's own random numbers: xoshiro256** seeded by SplitMix64, normal draws by
//! Marsaglia's polar method. In-tree so that a seed gives the same particles in every
//! build; its four words and the spare normal go into the snapshot.

use crate::snapshot::{Reader, SnapshotError, Writer};

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Rng {
    s: [u64; 4],
    /// The second normal of the last polar draw (NaN: none).
    spare: f64,
}

impl Rng {
    pub(crate) fn new(seed: u64) -> Self {
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
            spare: f64::NAN,
        }
    }

    #[inline]
    pub(crate) fn next_u64(&mut self) -> u64 {
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
    pub(crate) fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Standard normal.
    #[inline]
    pub(crate) fn normal(&mut self) -> f64 {
        if !self.spare.is_nan() {
            let v = self.spare;
            self.spare = f64::NAN;
            return v;
        }
        loop {
            let u = 2.0 * self.uniform() - 1.0;
            let v = 2.0 * self.uniform() - 1.0;
            let s = u * u + v * v;
            if s > 0.0 && s < 1.0 {
                let m = (-2.0 * s.ln() / s).sqrt();
                self.spare = v * m;
                return u * m;
            }
        }
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        self.s.iter().for_each(|&v| w.u64(v));
        w.f64(self.spare);
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self, SnapshotError> {
        let s = [r.u64()?, r.u64()?, r.u64()?, r.u64()?];
        if s == [0; 4] {
            return Err(SnapshotError::Invalid("random state all zero"));
        }
        let spare = r.f64_or_nan()?;
        if spare.abs() > 40.0 {
            return Err(SnapshotError::Invalid("spare normal draw"));
        }
        Ok(Self { s, spare })
    }
}
