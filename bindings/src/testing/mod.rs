//! Test helpers at the FFI (cargo feature `testing`, off by default; the test command
//! turns it on): simulated sessions with what Rust computes from them, so host tests
//! in Kotlin and Swift can prove that the FFI path gives the same numbers. Never part
//! of an app build (the Android AAR and the iOS XCFramework are built without it).

mod foot;
mod map;
mod pace;
mod phone;

pub use foot::{
    simulate_clipped_foot_run, simulate_foot_walk, ClippedFootRun, SimulatedFootWalk,
    MAX_SIM_FOOT_LAPS,
};
pub use map::{map_reference_replay, MapReplay};
pub use pace::{simulate_run, SimulatedRun, MAX_SIM_DURATION_S};
pub use phone::{pdr_reference_replay, simulate_phone_walk, PdrReplay, SimulatedPhoneWalk};
