//! Small signal-processing building blocks shared by the engines. None allocates
//! after construction.

mod gap;
mod ring;
pub(crate) use gap::is_gap;
pub use ring::Ring;

/// Gain of a first-order low-pass over a step of `x` time constants: 1 − e^(−x), exact
/// discretisation for any sample spacing. Below x = 1 a Padé (2,2) form of e^(−x) is used
/// (relative error < 2e-4, no `exp` call on the per-sample path).
#[inline]
pub(crate) fn ema_gain(x: f64) -> f64 {
    if x < 1.0 {
        let (p, q) = (1.0 + x * x / 12.0, 0.5 * x);
        1.0 - (p - q) / (p + q)
    } else {
        1.0 - (-x).exp()
    }
}
