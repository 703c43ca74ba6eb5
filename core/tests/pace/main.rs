//! Pace tracking and step length: one test binary (the files of this folder are its modules).

mod pace_accel;
mod pace_accuracy;
mod pace_behaviour;
mod pace_crosscheck;
mod pace_pedometer;
mod steplength;
mod steplength_outage;
