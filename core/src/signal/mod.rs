//! Small signal-processing building blocks shared by the engines. None allocates
//! after construction.

mod ring;
pub use ring::Ring;
