//! Accelerometer clipping: which samples sat at the sensor's ceiling, and how much of
//! their specific force the filter does not know.
//!
//! A foot-mounted accelerometer of ±4…16 g clips at heel strike and, running, through
//! the swing: the axis reports its ceiling while the true specific force is above it,
//! and the velocity integrated over the clipped samples misses the part above (on the
//! UofT running trials clipped at ±4 g, 0.1–0.3 m of position even on the oracle
//! stance labels). How much is missing is not in the data (an impact is a spike, not
//! a parabola: extrapolating its flanks put the error up as often as down,
//! docs/lab/2026-12-06-foot-accel-clip.md), so a clipped sample is not repaired: its
//! velocity variance grows by what it may hide, [`UNKNOWN_SHARE`] × the ceiling per
//! clipped axis over the interval, and the next zero-velocity update corrects the
//! velocity and, through the correlation that growth builds, the position.
//!
//! The zero-velocity detector's gait intensity (the stride's peak ‖f‖, which sets the
//! adaptive SHOE's threshold) is capped by the clip too: a running foot's stances,
//! judged against a walking threshold, are missed for seconds. An impact is a spike, so
//! its peak is where its flanks meet: [`ClipRun`] extends the line through the two
//! samples before a clipped run and the line through the two after it, and gives the
//! detector the norm with the clipped axis at their crossing (at least the ceiling, at
//! most [`MAX_PEAK_SHARE`] × it) once the run is over.
//!
//! The ceiling comes from the data, per sensor axis and sign ([`AccelCeiling`]): an
//! axis's largest magnitude so far, reached again and again with nothing above it
//! ([`MIN_CLIP_HITS`] separate times within [`LEVEL_SHARE`]), is a ceiling. A smooth
//! maximum is reached once or a few times; a clip at every hard impact. Or from a
//! configured range ([`FootConfig::accel_range_mps2`](super::FootConfig::accel_range_mps2)):
//! a sample at 99 % of it or more is clipped. Causal, allocation-free, fixed state.

/// Smallest ceiling looked for, m/s² (1.5 g): below the narrowest range of a MEMS
/// accelerometer (±2 g) and above gravity, which an axis of a foot at rest reads
/// for seconds.
pub const MIN_ACCEL_CEILING_MPS2: f64 = 1.5 * 9.80665;
/// Samples within this share of an axis's largest magnitude are at its level (a
/// calibrated output of a saturated element wanders a little: the UofT
/// MicroStrain's clipped pitch rate by 0.6 %, `ceiling.rs`).
pub const LEVEL_SHARE: f64 = 0.006;
/// Separate runs at the level, with nothing above it, that make it a ceiling. A
/// smooth maximum recurs a few times at most (up to 6 runs within 0.6 % on the 42
/// UofT trials as recorded); a ±4 g clip of their running trials 10–100 times.
pub const MIN_CLIP_HITS: u32 = 10;
/// 1-σ of the specific force a clipped axis does not report, as a share of its
/// ceiling: the UofT running trials' impacts reach up to twice a ±4 g ceiling, and
/// the part above, anywhere from 0 to 1 × the ceiling, has σ = 1/√12 ≈ 0.3 (0.25, 0.5
/// and 1 measured: docs/lab/2026-12-06-foot-accel-clip.md).
pub const UNKNOWN_SHARE: f64 = 0.3;

/// The largest impact peak [`ClipRun`] gives, as a share of the ceiling (10 g for a
/// ±4 g sensor: above what a running foot's impacts reach; the flanks of a long clipped
/// run would otherwise meet far above any).
pub const MAX_PEAK_SHARE: f64 = 2.5;

/// A sample at this share of a configured range or more is at the range.
use super::clip::AT_RANGE;

/// One sensor axis, one sign: magnitudes on that side.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Side {
    /// The largest magnitude so far, m/s².
    pub peak: f64,
    /// Separate runs at the level of `peak` since it was last exceeded.
    pub hits: u32,
    /// The previous sample was at the level.
    pub at_level: bool,
}

impl Side {
    /// One magnitude on this side (negative: the other side); returns whether it is
    /// clipped (the level is a ceiling and the sample is at it).
    #[inline]
    fn push(&mut self, x: f64) -> bool {
        if x < MIN_ACCEL_CEILING_MPS2 {
            self.at_level = false;
            return false;
        }
        if x > self.peak * (1.0 + LEVEL_SHARE) {
            // A new maximum: whatever was taken for a ceiling was not one.
            *self = Self {
                peak: x,
                hits: 1,
                at_level: true,
            };
            return false;
        }
        self.peak = self.peak.max(x);
        let at = x >= self.peak * (1.0 - LEVEL_SHARE);
        if at && !self.at_level {
            self.hits = self.hits.saturating_add(1);
        }
        self.at_level = at;
        at && self.hits >= MIN_CLIP_HITS
    }
}

/// Streaming accelerometer ceiling detector of one sensor (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct AccelCeiling {
    /// Per sensor axis: the positive and the negative side.
    pub sides: [[Side; 2]; 3],
}

impl AccelCeiling {
    /// One sample's specific force, sensor axes (finite: the door checked it), with
    /// the configured range if any; returns per sensor axis whether it is clipped.
    #[inline]
    pub(crate) fn push(&mut self, f: &[f64; 3], range_mps2: Option<f64>) -> [bool; 3] {
        let mut out = [false; 3];
        for ((sides, &x), o) in self.sides.iter_mut().zip(f).zip(out.iter_mut()) {
            let up = sides[0].push(x);
            let down = sides[1].push(-x);
            let clipped = match range_mps2 {
                Some(r) => x.abs() >= AT_RANGE * r,
                None => up || down,
            };
            *o = clipped;
        }
        out
    }

    /// The lowest ceiling found so far on any axis and sign, m/s² (the level's
    /// largest sample).
    pub(crate) fn lowest_mps2(&self) -> Option<f64> {
        self.ceilings().map(|(_, _, c)| c).min_by(f64::total_cmp)
    }

    /// Every (axis, positive side, ceiling m/s²) found so far.
    pub(crate) fn ceilings(&self) -> impl Iterator<Item = (usize, bool, f64)> + '_ {
        self.sides.iter().enumerate().flat_map(|(axis, s)| {
            s.iter()
                .enumerate()
                .filter(|(_, x)| x.hits >= MIN_CLIP_HITS && x.peak >= MIN_ACCEL_CEILING_MPS2)
                .map(move |(k, x)| (axis, k == 0, x.peak))
        })
    }
}

/// The accelerometer's ceiling over a whole recording, by the navigator's own rule
/// ([`AccelCeiling`]): a device's range is a constant, so a file replay runs it over
/// every sample first and reports what it finds. `range_mps2()` is the range that,
/// configured ([`FootConfig::accel_range_mps2`](super::FootConfig::accel_range_mps2)),
/// would not trust the first impacts either (measured worse on balance on clipped
/// copies, docs/lab/2026-12-06-foot-accel-clip.md round 2, so replays do not
/// configure it). Allocation-free, fixed state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AccelCeilingDetector {
    ceiling: AccelCeiling,
}

impl AccelCeilingDetector {
    pub fn new() -> Self {
        Self::default()
    }

    /// One sample's specific force, sensor axes, m/s² (a non-finite one, which the
    /// navigator refuses, is skipped).
    pub fn push(&mut self, accel_mps2: [f64; 3]) {
        if accel_mps2.iter().all(|x| x.is_finite()) {
            self.ceiling.push(&accel_mps2, None);
        }
    }

    /// The lowest ceiling found on any axis and sign, m/s² (the level's largest
    /// sample), or `None`: no sign of clipping.
    pub fn ceiling_mps2(&self) -> Option<f64> {
        self.ceiling.lowest_mps2()
    }

    /// The range to configure so that the navigator's clip threshold (99 % of the
    /// range) is where this rule takes a sample for clipped: the ceiling's level,
    /// [`LEVEL_SHARE`] below it.
    pub fn range_mps2(&self) -> Option<f64> {
        self.ceiling_mps2()
            .map(|c| c * (1.0 - LEVEL_SHARE) / AT_RANGE)
    }

    /// The largest magnitude on any axis, m/s² (0 when none reached
    /// [`MIN_ACCEL_CEILING_MPS2`]).
    pub fn peak_mps2(&self) -> f64 {
        self.ceiling
            .sides
            .iter()
            .flatten()
            .fold(0.0, |m, s| m.max(s.peak))
    }
}

/// One sensor axis's clipped run in progress, for the impact's peak (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ClipRun {
    /// The previous two values on the axis, m/s² (newest first; NaN before them).
    pub prev: [f64; 2],
    /// Inside a run, or waiting for its second sample after.
    pub active: bool,
    /// The run's sign and ceiling (its largest magnitude), m/s².
    pub sign: f64,
    pub ceiling: f64,
    /// The magnitude of the sample before the run and its rise per sample.
    pub entry: f64,
    pub rise: f64,
    /// Clipped samples in the run.
    pub len: u32,
    /// The largest ‖f‖² over the run, (m/s²)².
    pub norm2: f64,
    /// The magnitude of the first sample after the run (NaN: still clipped).
    pub exit: f64,
}

impl Default for ClipRun {
    fn default() -> Self {
        Self {
            prev: [f64::NAN; 2],
            active: false,
            sign: 0.0,
            ceiling: 0.0,
            entry: f64::NAN,
            rise: f64::NAN,
            len: 0,
            norm2: 0.0,
            exit: f64::NAN,
        }
    }
}

impl ClipRun {
    /// The axis's value `x`, whether it is clipped and the sample's ‖f‖²; returns the
    /// impact's ‖f‖ estimate when a run ends (the second sample after it), m/s².
    #[inline]
    pub(crate) fn push(&mut self, x: f64, clipped: bool, norm2: f64) -> Option<f64> {
        let mut out = None;
        if self.active {
            if !self.exit.is_nan() {
                // The second sample after the run: the falling flank.
                if !clipped {
                    out = self.peak_norm(self.exit - self.sign * x);
                }
                self.active = false;
            } else if clipped && x.signum() == self.sign {
                self.len = self.len.saturating_add(1);
                self.ceiling = self.ceiling.max(x.abs());
                self.norm2 = self.norm2.max(norm2);
            } else if clipped {
                // Clipped on the other side at once: no flank to go by.
                self.active = false;
            } else {
                self.exit = self.sign * x;
            }
        }
        if clipped && !self.active {
            let sign = x.signum();
            let [p1, p2] = self.prev.map(|v| sign * v);
            *self = Self {
                prev: self.prev,
                active: true,
                sign,
                ceiling: x.abs(),
                entry: p1,
                rise: p1 - p2,
                len: 1,
                norm2,
                exit: f64::NAN,
            };
        }
        self.prev = [x, self.prev[0]];
        out
    }

    /// Where the rising flank (through `entry`, at `rise` per sample) meets the falling
    /// one (through `exit`, at `fall` per sample), as the run's ‖f‖; `None` when the
    /// flanks do not make a spike.
    fn peak_norm(&self, fall: f64) -> Option<f64> {
        let (c, rise) = (self.ceiling, self.rise);
        if !(rise > 0.0 && fall > 0.0 && self.entry.is_finite() && self.exit.is_finite()) {
            return None;
        }
        // Samples from the one before the run (0) to the first after it (len + 1).
        let span = f64::from(self.len) + 1.0;
        let x = ((self.exit + fall * span - self.entry) / (rise + fall)).clamp(0.0, span);
        let peak = (self.entry + rise * x).clamp(c, MAX_PEAK_SHARE * c);
        Some(((self.norm2 - c * c).max(0.0) + peak * peak).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Strides whose impact on x peaks at `peak` ± 15 % (uniform, seeded), sampled
    /// at 200 Hz: a spike of three samples per second.
    fn strides(peak: f64, n: usize) -> Vec<[f64; 3]> {
        let mut seed = 12345_u64;
        let mut p = peak;
        (0..n)
            .map(|k| {
                let ph = k % 200;
                if ph == 0 {
                    seed = seed
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
                    p = peak * (1.0 + 0.3 * (u - 0.5));
                }
                let x = match ph {
                    0 => 0.4 * p,
                    1 => p,
                    2 => 0.5 * p,
                    _ => 2.0,
                };
                [x, 0.3, -9.8]
            })
            .collect()
    }

    /// A minute of strides clipped at ±4 g, and the clip, m/s².
    fn clipped_strides() -> (f64, Vec<[f64; 3]>) {
        let lim = 4.0 * 9.80665;
        let samples = strides(60.0, 200 * 60)
            .into_iter()
            .map(|f| f.map(|x| x.clamp(-lim, lim)))
            .collect();
        (lim, samples)
    }

    fn run(samples: &[[f64; 3]], range: Option<f64>) -> (AccelCeiling, usize) {
        let mut c = AccelCeiling::default();
        let clipped = samples.iter().filter(|f| c.push(f, range)[0]).count();
        (c, clipped)
    }

    #[test]
    fn impacts_below_any_ceiling_are_not_clipped() {
        let (c, clipped) = run(&strides(60.0, 200 * 60), None);
        assert_eq!(clipped, 0);
        assert_eq!(c.ceilings().count(), 0);
    }

    #[test]
    fn a_clipped_axis_is_found_at_its_ceiling() {
        let (lim, samples) = clipped_strides();
        let (c, clipped) = run(&samples, None);
        // Every impact from the tenth on is clipped.
        assert_eq!(clipped, 60 - (MIN_CLIP_HITS as usize - 1));
        let found: Vec<_> = c.ceilings().collect();
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!((found[0].0, found[0].1), (0, true));
        assert!((found[0].2 - lim).abs() <= LEVEL_SHARE * lim);
        // Gravity on z, for a minute, is no ceiling.
        assert!(found.iter().all(|f| f.0 != 2));
    }

    /// The pre-scan's range makes the navigator's range rule take the same samples for
    /// clipped as the streaming rule once it is sure: the level, from the first impact.
    #[test]
    fn the_pre_scan_range_takes_the_level_for_clipped() {
        let (lim, samples) = clipped_strides();
        let mut d = AccelCeilingDetector::new();
        d.push([f64::NAN, 0.0, 0.0]);
        samples.iter().for_each(|f| d.push(*f));
        assert_eq!(d.ceiling_mps2(), Some(lim));
        assert_eq!(d.peak_mps2(), lim);
        let range = d.range_mps2().unwrap();
        assert!((AT_RANGE * range - lim * (1.0 - LEVEL_SHARE)).abs() < 1e-9);
        let (_, clipped) = run(&samples, Some(range));
        assert_eq!(clipped, 60, "every impact, the first nine too");
        let mut plain = AccelCeilingDetector::new();
        strides(60.0, 200 * 60).iter().for_each(|f| plain.push(*f));
        assert_eq!((plain.ceiling_mps2(), plain.range_mps2()), (None, None));
        assert!(plain.peak_mps2() > lim);
    }

    #[test]
    fn a_configured_range_decides_at_once() {
        let (_, clipped) = run(&strides(60.0, 200 * 10), Some(50.0));
        assert_eq!(clipped, 10, "every impact above 49.5 m/s²");
    }

    /// A triangular spike clipped at `c`: its peak comes back where the flanks meet,
    /// the other axes' part of the norm kept.
    #[test]
    fn a_clipped_spike_gets_its_peak_from_its_flanks() {
        let c = 40.0;
        // Up 20 per sample to 90, down 15 per sample; y carries 3 m/s².
        let xs: [f64; 11] = [
            10.0, 30.0, 50.0, 70.0, 90.0, 75.0, 60.0, 45.0, 30.0, 15.0, 0.0,
        ];
        let mut run = ClipRun::default();
        let mut out = Vec::new();
        for &x in &xs {
            let xc: f64 = x.min(c);
            let norm2 = xc * xc + 9.0;
            out.extend(run.push(xc, xc >= c, norm2));
        }
        assert_eq!(out.len(), 1, "one estimate, when the run is over");
        // Rising line 30 + 20·k, falling 30 + 15·(span − k): they meet at 90 m/s²,
        // the clamp at 2.5 × 40 = 100 does not bite.
        assert!(
            (out[0] - (90.0_f64 * 90.0 + 9.0).sqrt()).abs() < 1e-9,
            "{out:?}"
        );
        // The same spike on the negative side.
        let mut run = ClipRun::default();
        let neg: Vec<f64> = xs
            .iter()
            .filter_map(|&x| {
                let xc = -(x.min(c));
                run.push(xc, xc <= -c, xc * xc + 9.0)
            })
            .collect();
        assert_eq!(neg, out);
    }

    #[test]
    fn a_run_without_a_rising_flank_gives_nothing() {
        let mut run = ClipRun::default();
        let est: Vec<f64> = [40.0, 40.0, 30.0, 10.0]
            .iter()
            .filter_map(|&x| run.push(x, x >= 40.0, x * x))
            .collect();
        assert!(est.is_empty(), "{est:?}");
    }
}
