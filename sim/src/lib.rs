//! Deterministic, seeded simulators. Same seed, same output, on every platform.

pub mod foot;
pub mod phone;
pub mod rng;
pub mod run;

pub use foot::{simulate_foot, FootGait, FootScenario, FootTruth, SimulatedFoot, TrueStride};
pub use phone::{simulate_phone, PhoneActivity, PhonePlacement, PhoneScenario, SimulatedPhone};
pub use rng::Rng;
pub use run::{simulate_run, RunScenario, SimulatedRun, StepReport, TruthSample, Zone, ZoneKind};
