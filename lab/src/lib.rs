//! stridekit-lab: everything around the engines that is not shipped in the SDK —
//! evaluation against simulated and real recordings, the metrics, the trainers of
//! the shipped models, and the naive baselines the engines are compared with. Used by
//! the `stridekit` CLI, the tests and the benches.

pub mod activity;
pub mod demo;
pub mod foot;
pub mod odometry;
pub mod orientation;
pub mod pace;
pub mod pace_device;
pub mod pace_eval;
pub mod pdr;
pub mod perturb;
pub mod placement;
pub mod placement_eval;
pub mod placement_mlp;
pub mod progress;
pub mod rejected;
pub mod replay;
pub mod report;
pub mod soak;
pub mod stats;
pub mod steplength;
pub mod steplength_eval;
pub mod steps_eval;
pub mod table;
