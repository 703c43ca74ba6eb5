//! What every engine's batch entry point reports about the samples it refused.

/// A sample a batch push refused: its position in the batch (from 0) and why. The
/// other samples were processed as if pushed one by one; the refused one changed
/// nothing. Every engine's rejection type is this one with its own error
/// (`pace::Rejection`, `foot::FootRejection`, ...).
#[derive(Clone, Debug, PartialEq)]
pub struct Rejected<E> {
    pub index: usize,
    pub error: E,
}
