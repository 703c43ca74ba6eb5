//! Statistical constants the engines share: the χ² gates of innovation tests and the
//! per-axis σ of a fix's 68 % accuracy radius.

/// 99 % quantile of χ² with 2 degrees of freedom: a 2-D innovation beyond it is an
/// outlier.
pub const CHI2_99_2DOF: f64 = 9.21;
/// 99 % quantile of χ² with 1 degree of freedom.
pub const CHI2_99_1DOF: f64 = 6.63;
/// The 68 % radius of a circular 2-D Gaussian is 1.515 σ per axis: radius = σ × this.
pub const SIGMA_TO_RADIUS68: f64 = 1.515;
/// σ = radius × this (the inverse of [`SIGMA_TO_RADIUS68`]).
pub const RADIUS68_TO_SIGMA: f64 = 1.0 / SIGMA_TO_RADIUS68;
