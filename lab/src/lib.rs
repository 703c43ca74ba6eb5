//! stridekit-lab: everything around the engines that is not shipped in the SDK —
//! evaluation against simulated and real recordings, the metrics, the trainers of
//! the shipped models, and the naive baselines the engines are compared with. Used by
//! the `stridekit` CLI, the tests and the benches.

pub mod odometry;
pub mod pace;
pub mod placement;
pub mod steplength;
