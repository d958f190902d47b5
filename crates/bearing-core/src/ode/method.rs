//! What a one-step method offers the solver.

use super::controller::StepEnd;
use super::problem::OdeSystem;
use super::stats::StepStats;

/// A one-step method under the solver's control.
pub trait Method<S: OdeSystem> {
    /// Attempt one step from `(t, y)` with `f0 = f(t, y)` to `t_end = t + h` (exactly the
    /// end time on the last step). Leaves the proposal for [`Method::y_new`] and returns
    /// the scaled error norm: accept when <= 1; 0 for a method without error control.
    #[allow(clippy::too_many_arguments)]
    fn attempt(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64],
        f0: &[f64],
        h: f64,
        t_end: f64,
        stats: &mut StepStats,
    ) -> f64;
    /// The proposed state of the last attempt.
    fn y_new(&self) -> &[f64];
    /// `f(t + h, y_new)` when the attempt evaluated it (first same as last), through
    /// [`OdeSystem::rhs_at_step_end`].
    fn f_new(&self) -> Option<&[f64]> {
        None
    }
    /// Factor for the next step after an accepted one, which ended as `end` says.
    fn accept_factor(&mut self, err: f64, end: StepEnd) -> f64;
    /// Factor for the retry after a rejected one.
    fn reject_factor(&mut self, err: f64) -> f64;
    /// Called before each attempt's step is chosen, at its start `(t, y)` with
    /// `f0 = f(t, y)` (a retry calls it again at the same point): a method that linearises
    /// the problem does it here, so that [`Method::step_limit`] describes the step about to
    /// be chosen; the right-hand sides it spends go to `stats`.
    fn begin_attempt(
        &mut self,
        _sys: &mut S,
        _t: f64,
        _y: &[f64],
        _f0: &[f64],
        _stats: &mut StepStats,
    ) {
    }
    /// After an accepted step (before the next begins): overwrite in `out`, the cubic
    /// Hermite interpolant at fraction `s` of `step`, the components the method
    /// interpolates better itself; false if it has none.
    fn refine_dense(&self, _step: &LastStep<'_>, _s: f64, _out: &mut [f64]) -> bool {
        false
    }
    /// Largest step the method itself can take accurately from here, s (`None`: no limit).
    fn step_limit(&self) -> Option<f64> {
        None
    }
    /// False for a fixed-step method: every step is the initial step.
    fn controlled(&self) -> bool {
        true
    }
}

/// One accepted step as the output sampling and a method's dense output read it.
pub struct LastStep<'a> {
    /// Start, s, and size, s.
    pub t: f64,
    pub h: f64,
    pub y0: &'a [f64],
    pub f0: &'a [f64],
    pub y1: &'a [f64],
    pub f1: &'a [f64],
}
