//! Why an integration stopped before the end time.

/// A solver run that did not reach its end time.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// Stopped on request.
    #[error("cancelled at t = {at} s")]
    Cancelled {
        /// Simulated time reached, s.
        at: f64,
    },
    /// The step controller asked for a step below the smallest it allows.
    #[error("numerical failure at t = {time} s: step size underflow: h = {step:.3e} s below {min_step:.1e} s (error norm {error_norm:.3e})")]
    StepUnderflow {
        /// Simulated time, s.
        time: f64,
        /// Step asked for, s.
        step: f64,
        /// Smallest step allowed, s.
        min_step: f64,
        /// Scaled error norm of the rejected step, -.
        error_norm: f64,
    },
    /// A state component or derivative became NaN or infinite.
    #[error("numerical failure at t = {time} s: non-finite state or derivative (component {component} of {len}) after a step of {step:.3e} s")]
    NonFinite {
        /// Simulated time, s.
        time: f64,
        /// Index of the first non-finite component in the state vector.
        component: usize,
        /// Length of the state vector.
        len: usize,
        /// Step that produced it, s.
        step: f64,
    },
}
