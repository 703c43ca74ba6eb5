//! Foot-mounted inertial navigation: one test binary (the files of this folder are its modules).

mod foot;
mod foot_adversarial;
mod foot_perturbed;
