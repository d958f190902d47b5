//! Cancellation and progress hooks of a run.

use std::sync::atomic::AtomicBool;

/// Cancellation and progress hooks, checked between integrator steps.
#[derive(Default)]
pub struct RunControl<'a> {
    /// Set to `true` (from any thread) to stop the run at the next step.
    pub cancel: Option<&'a AtomicBool>,
    /// Called with the fraction of simulated time done (0..=1), at most ~100 times a second.
    pub progress: Option<&'a mut dyn FnMut(f64)>,
}
