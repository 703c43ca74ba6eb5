//! Learned phone odometry in the lab: the naive double-integration baselines, the
//! trajectory metrics (ATE / RTE), fitting the regressors, and the evaluation on
//! simulated walks.

pub mod baseline;
pub mod commands;
pub mod evaluate;
pub mod metrics;
pub mod train;

pub use baseline::{NaiveMode, NaiveOdometry};
