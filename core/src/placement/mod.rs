//! Phone placement classifier: where the phone is carried (in the hand, in a trouser
//! pocket, in a bag, in a neck pouch, on an armband, in a swinging hand), from the
//! accelerometer alone, at any sampling rate and phone orientation.
//!
//! - `class`: the [`Placement`] classes and their mapping from the Oxford Step
//!   Counter positions and the simulator's placements;
//! - `resample`: rate-independent 20-ms bin means;
//! - `features`: 23 window features (5.12 s windows every 1.28 s);
//! - `stream`: [`FeatureStream`], door checks + bins + window ring;
//! - `model`: [`PlacementModel`], multinomial logistic regression and its
//!   versioned text file (`core/models/placement_lr_v1.txt` ships, [`PlacementModel::shipped`]);
//! - `train`: class-balanced training of the model;
//! - `classifier`: [`PlacementClassifier`], the streaming engine apps use.
//!
//! Accuracy (leave-one-user-out on the Oxford traces) and limits: docs/odometry.md.

mod class;
mod classifier;
mod error;
mod features;
mod model;
mod resample;
mod stream;

pub use crate::stepdetect::AccelSample;
pub use class::{Placement, CLASSES};
/// Pieces the placement trainer (`stridekit-lab`) builds on.
pub use classifier::DEFAULT_SMOOTHING;
pub use classifier::{PlacementClassifier, PlacementEstimate, PlacementRejection};
pub use error::PlacementError;
pub use features::{window_features, FeatureTables};
pub use features::{Features, FEATURES, FEATURE_NAMES, WINDOW};
pub use model::PlacementModel;
pub use resample::BinAverager;
pub use stream::{trace_features, FeatureStream, HOP};
