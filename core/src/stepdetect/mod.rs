//! Step detection on the acceleration magnitude of a phone carried anywhere (in progress).

mod event;
pub use event::StepEvent;
