//! Orientation in the lab: the BROAD metric (errors against optical truth during
//! movement) and `eval orientation`.

pub mod eval;
pub mod metric;
