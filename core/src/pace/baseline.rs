//! Baselines for evaluation (work in progress).
