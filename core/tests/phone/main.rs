//! Phone sensing: steps, orientation, dead reckoning, placement, odometry: one test binary (the files of this folder are its modules).

// The counting allocator (installed for this whole binary; counting is per thread).
#[path = "../common/mod.rs"]
mod common;

mod adversarial_phone;
mod ahrs;
mod imu_merge;
mod map;
mod odometry;
mod pdr;
mod pdr_accuracy;
mod pdr_crosscheck;
mod pdr_diag;
mod pdr_gaps;
mod pdr_heading;
mod placement;
mod sim_phone;
mod stepdetect;
mod stepdetect_oxford;
