//! What every engine promises: no allocation per sample, typed refusals that change nothing, robust restores: one test binary (the files of this folder are its modules).

// The counting allocator (installed for this whole binary; counting is per thread).
#[path = "../common/mod.rs"]
mod common;

mod alloc;
mod foot_alloc;
mod map_alloc;
mod pdr_alloc;
mod robustness;
mod stepdetect_alloc;
mod time_units;
