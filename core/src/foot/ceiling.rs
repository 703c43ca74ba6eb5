//! Gyroscope ceiling detection: whether a recording's gyroscope clipped, and at what rate.
//!
//! A clipped gyroscope leaves a mark no smooth swing peak does: the rate climbs steeply,
//! stops dead at the same magnitude, stays flat for a few samples, and does so again at
//! the next fast stride, at the same value, with nothing above it. Per sensor axis and
//! sign, [`GyroCeilingDetector`] looks for those **flat tops**: at least
//! [`MIN_FLAT_SAMPLES`] consecutive samples within [`FLAT_SHARE`] of each other, above
//! [`MIN_CEILING_RADS`], reached at least [`SHARPNESS`] times faster than the run then
//! changes (a parabolic peak sampled at any rate scores at most about 8 on that ratio: it
//! slows down gradually). It groups the flat tops by level; a ceiling is a group of at
//! least [`MIN_FLAT_TOPS`] flat tops within [`LEVEL_SHARE`] of each other, above which
//! the axis never went by more than [`ABOVE_SHARE`]. A smooth peak above any given rate,
//! a wider-range IMU's swing, is never one.
//!
//! Causal and allocation-free (fixed state per axis and sign): it can run beside a live
//! stream, but a device's range is a constant, so the file replays run it over the whole
//! recording first and give the navigator the range it found
//! ([`FootConfig::gyro_range_rads`](super::FootConfig::gyro_range_rads)); without such
//! evidence (or a range the app states) nothing is repaired. docs/lab/2026-12-06-foot-history.md, "Device
//! assumptions".

use super::clip::AT_RANGE;

/// Smallest ceiling looked for, rad/s: just below the narrowest range of a MEMS
/// gyroscope (±125 °/s = 2.18 rad/s); below it a foot at rest or turning slowly is flat.
pub const MIN_CEILING_RADS: f64 = 2.0;
/// A flat top's samples lie within this share of its highest magnitude of each other
/// (the UofT MicroStrain's clipped pitch rate wanders by up to 0.05 rad/s at 9.1 rad/s:
/// its output is calibrated after the sensing element saturates).
pub const FLAT_SHARE: f64 = 0.006;
/// Fewest consecutive samples of a flat top (two equal samples happen at any peak).
pub const MIN_FLAT_SAMPLES: u32 = 3;
/// A flat top is reached at least this many times faster (rise per sample over the two
/// samples before it) than it changes inside (spread per sample). A parabola's ratio is
/// at most about 8 (three samples straddling its top); a clip's is 20 to 1000.
pub const SHARPNESS: f64 = 16.0;
/// Spread per sample below this share of the level is taken as this (a float-exact
/// plateau would otherwise make any rise "sharp").
const SPREAD_FLOOR_SHARE: f64 = 1.0e-5;
/// Flat tops at one ceiling: the same value reached several times, not one odd stride.
pub const MIN_FLAT_TOPS: u32 = 3;
/// Flat tops within this share of each other are at the same level.
pub const LEVEL_SHARE: f64 = 0.01;
/// Nothing on that axis and sign more than this share above the flat tops' level.
pub const ABOVE_SHARE: f64 = 0.02;
/// Levels kept per axis and sign (the highest; a ceiling is at the top).
const LEVELS: usize = 8;

/// A ceiling found on one sensor axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GyroCeiling {
    /// Sensor axis (0 = x, 1 = y, 2 = z, as recorded, before any remap).
    pub axis: usize,
    /// The ceiling is on the positive side of the axis.
    pub positive: bool,
    /// The lowest sample of the flat tops, rad/s (magnitude): where clipping begins.
    pub ceiling_rads: f64,
    /// How many flat tops sat at it.
    pub flat_tops: u32,
    /// The largest magnitude the axis reached on that side, rad/s.
    pub peak_rads: f64,
}

impl GyroCeiling {
    /// The gyroscope range to configure so that the navigator's clip threshold
    /// (99 % of the range) is this ceiling.
    pub fn range_rads(&self) -> f64 {
        self.ceiling_rads / AT_RANGE
    }
}

/// One group of flat tops at about the same level.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Level {
    /// The first flat top's middle value (the group's reference), its highest middle
    /// value and its lowest sample, rad/s.
    reference: f64,
    highest: f64,
    lowest: f64,
    count: u32,
}

/// The run of near-equal samples in progress on one side of an axis.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Run {
    n: u32,
    lo: f64,
    hi: f64,
    /// Rise per sample over the two samples before the run (NaN: unknown).
    rise: f64,
}

/// One axis, one sign: magnitudes on that side (the other sign counts negative).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Side {
    /// The previous two values (newest first; NaN before them).
    prev: [f64; 2],
    run: Run,
    peak: f64,
    levels: [Level; LEVELS],
}

impl Side {
    fn new() -> Self {
        Self {
            prev: [f64::NAN; 2],
            run: Run::default(),
            peak: 0.0,
            levels: [Level::default(); LEVELS],
        }
    }

    fn push(&mut self, x: f64) {
        self.peak = self.peak.max(x);
        let r = self.run;
        let (lo, hi) = (r.lo.min(x), r.hi.max(x));
        if r.n > 0 && x >= MIN_CEILING_RADS && hi - lo <= FLAT_SHARE * hi {
            self.run = Run {
                n: r.n + 1,
                lo,
                hi,
                ..r
            };
        } else {
            self.close();
            self.run = if x >= MIN_CEILING_RADS {
                Run {
                    n: 1,
                    lo: x,
                    hi: x,
                    rise: (x - self.prev[1]) / 2.0,
                }
            } else {
                Run::default()
            };
        }
        self.prev = [x, self.prev[0]];
    }

    /// The run in progress ended: keep it if it was a flat top.
    fn close(&mut self) {
        let r = self.run;
        if r.n < MIN_FLAT_SAMPLES {
            return;
        }
        let spread = ((r.hi - r.lo) / f64::from(r.n - 1)).max(SPREAD_FLOOR_SHARE * r.hi);
        if r.rise > SHARPNESS * spread {
            self.add_level((r.lo + r.hi) / 2.0, r.lo);
        }
    }

    fn add_level(&mut self, middle: f64, lowest: f64) {
        let near = |l: &Level| l.count > 0 && (middle - l.reference).abs() <= LEVEL_SHARE * middle;
        if let Some(l) = self.levels.iter_mut().find(|l| near(l)) {
            l.highest = l.highest.max(middle);
            l.lowest = l.lowest.min(lowest);
            l.count += 1;
            return;
        }
        // A free slot, else the lowest group if this one is higher (ceilings are on top).
        let slot = self
            .levels
            .iter_mut()
            .min_by(|a, b| {
                (a.count > 0, a.reference)
                    .partial_cmp(&(b.count > 0, b.reference))
                    .unwrap_or(std::cmp::Ordering::Equal)
            })
            .filter(|l| l.count == 0 || l.reference < middle);
        if let Some(l) = slot {
            *l = Level {
                reference: middle,
                highest: middle,
                lowest,
                count: 1,
            };
        }
    }

    /// The ceiling of this side, if the evidence is there (the run in progress counts
    /// as ended).
    fn ceiling(&self) -> Option<(f64, u32)> {
        let mut side = *self;
        side.close();
        side.levels
            .iter()
            .filter(|l| l.count >= MIN_FLAT_TOPS && side.peak <= l.highest * (1.0 + ABOVE_SHARE))
            .max_by_key(|l| l.count)
            .map(|l| (l.lowest, l.count))
    }
}

/// Streaming detector of a clipped gyroscope (module docs). Push every sample's rates
/// in the sensor's own axes, then ask [`ceiling`](Self::ceiling).
#[derive(Clone, Debug, PartialEq)]
pub struct GyroCeilingDetector {
    /// Per sensor axis: the positive and the negative side.
    sides: [[Side; 2]; 3],
}

impl Default for GyroCeilingDetector {
    fn default() -> Self {
        Self::new()
    }
}

impl GyroCeilingDetector {
    pub fn new() -> Self {
        Self {
            sides: [[Side::new(); 2]; 3],
        }
    }

    /// One sample's angular rate, rad/s, sensor axes. Non-finite values are ignored
    /// (the navigator refuses them).
    pub fn push(&mut self, gyro_rads: [f64; 3]) {
        if !gyro_rads.iter().all(|w| w.is_finite()) {
            return;
        }
        for (sides, w) in self.sides.iter_mut().zip(gyro_rads) {
            sides[0].push(w);
            sides[1].push(-w);
        }
    }

    /// Every axis and sign with a ceiling so far.
    pub fn ceilings(&self) -> impl Iterator<Item = GyroCeiling> + '_ {
        self.sides.iter().enumerate().flat_map(|(axis, sides)| {
            sides.iter().enumerate().filter_map(move |(k, side)| {
                side.ceiling().map(|(c, n)| GyroCeiling {
                    axis,
                    positive: k == 0,
                    ceiling_rads: c,
                    flat_tops: n,
                    peak_rads: side.peak,
                })
            })
        })
    }

    /// The lowest ceiling found on any axis (a gyroscope has one range; the lowest
    /// clipped side bounds it), or `None`: no evidence of clipping.
    pub fn ceiling(&self) -> Option<GyroCeiling> {
        self.ceilings()
            .min_by(|a, b| a.ceiling_rads.total_cmp(&b.ceiling_rads))
    }

    /// The largest magnitude seen on any axis, rad/s.
    pub fn peak_rads(&self) -> f64 {
        self.sides
            .iter()
            .flatten()
            .map(|s| s.peak)
            .fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A walk's pitch rate: one `peak·sin` swing pulse of `width_s` per second, a slow
    /// negative lobe between, at `rate_hz`, with a small stride-to-stride variation.
    fn strides(rate_hz: f64, width_s: f64, peak: f64, seconds: f64) -> Vec<f64> {
        let n = (seconds * rate_hz) as usize;
        (0..n)
            .map(|k| {
                let t = k as f64 / rate_hz;
                let (stride, ph) = (t.floor(), t.fract());
                let p = peak * (1.0 + 0.02 * (stride * 1.7).sin());
                if ph < width_s {
                    p * (std::f64::consts::PI * ph / width_s).sin()
                } else {
                    -2.0 * (std::f64::consts::PI * (ph - width_s) / (1.0 - width_s)).sin()
                }
            })
            .collect()
    }

    fn detect(rates: &[f64], axis: usize) -> GyroCeilingDetector {
        let mut d = GyroCeilingDetector::new();
        for &w in rates {
            let mut g = [0.01, -0.02, 0.03];
            g[axis] = w;
            d.push(g);
        }
        d
    }

    #[test]
    fn smooth_peaks_above_any_rate_are_not_a_ceiling() {
        for rate in [100.0, 200.0, 400.0, 1000.0] {
            for width in [0.15, 0.25, 0.4] {
                for peak in [9.5, 12.0, 30.0] {
                    let d = detect(&strides(rate, width, peak, 30.0), 1);
                    assert_eq!(d.ceiling(), None, "{rate} Hz, {width} s, {peak} rad/s");
                    assert!(d.peak_rads() > 0.97 * peak);
                }
            }
        }
    }

    #[test]
    fn clipped_peaks_give_their_ceiling() {
        for rate in [100.0, 200.0, 400.0, 1000.0] {
            for ceiling in [4.3, 9.13, 34.9] {
                let rates: Vec<f64> = strides(rate, 0.25, 1.2 * ceiling, 30.0)
                    .into_iter()
                    .map(|w| -w.clamp(-ceiling, ceiling))
                    .collect();
                let d = detect(&rates, 2);
                let c = d.ceiling().expect("clipped");
                assert_eq!((c.axis, c.positive), (2, false), "{rate} Hz");
                // The lowest flat-top sample: the ceiling or a sample just below it.
                let below = ceiling - c.ceiling_rads;
                assert!((0.0..=FLAT_SHARE * ceiling).contains(&below), "{c:?}");
                assert_eq!(c.peak_rads, ceiling);
                assert!(c.flat_tops >= 25, "{c:?}");
                assert!((c.range_rads() * AT_RANGE - c.ceiling_rads).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn one_clipped_stride_is_not_enough() {
        let mut rates = strides(200.0, 0.25, 9.0, 10.0);
        for w in &mut rates[..200] {
            *w = w.min(8.0);
        }
        assert!(rates.iter().any(|&w| w > 8.5), "the other strides go above");
        assert_eq!(detect(&rates, 0).ceiling(), None);
    }

    #[test]
    fn non_finite_samples_are_ignored() {
        let mut d = GyroCeilingDetector::new();
        d.push([f64::NAN, 0.0, 0.0]);
        d.push([f64::INFINITY, 0.0, 0.0]);
        assert_eq!(d.peak_rads(), 0.0);
        assert_eq!(d.ceiling(), None);
    }
}
