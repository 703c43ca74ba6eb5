//! Learned phone odometry in the lab: the naive double-integration baselines, the
//! trajectory metrics (ATE / RTE), fitting the regressors, and the evaluation on
//! simulated walks.

pub mod baseline;
pub mod commands;
pub mod evaluate;
pub mod metrics;
pub mod train;

pub use baseline::{NaiveMode, NaiveOdometry};

use stridekit_core::odometry::OdometryModel;

/// The simulator-trained model (`lab/models/odometry_sim_v1.txt`): shipped until
/// 2026-12-06, now the lab's model for every placement on the simulator and the fixed
/// frame reference of the training on real walks (`pdr::odometry`), so that a model
/// trained today does not depend on the one shipped.
pub fn simulator_model() -> OdometryModel {
    OdometryModel::parse(include_str!("../../models/odometry_sim_v1.txt"))
        .expect("lab/models/odometry_sim_v1.txt parses")
}
