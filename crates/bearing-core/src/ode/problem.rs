//! The problem a solver integrates: a first-order system `dy/dt = f(t, y)`, and what a
//! linearly implicit method also needs of it.

use super::block_jacobian::BlockJacobian;

/// A first-order system `dy/dt = f(t, y)`.
pub trait OdeSystem {
    fn dim(&self) -> usize;
    /// `f(t, y)` into `dy`.
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]);
    /// The derivative at a step's end point, which becomes the next step's first stage;
    /// a system may record per-evaluation diagnostics here.
    fn rhs_at_step_end(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        self.rhs(t, y, dy)
    }
    /// Update, after an accepted step and right after [`OdeSystem::rhs_at_step_end`] at
    /// `(t, y)`, the components the derivative does not advance because an algebraic
    /// equation fixes them. The derivative already evaluated at `y` is kept.
    fn project(&mut self, _t: f64, _y: &mut [f64]) {}
    /// Largest step the problem allows from `(t, y)`, s (e.g. to end steps on the points
    /// where `f` is not smooth); `None` for no limit.
    fn step_limit(&self, _t: f64, _y: &[f64]) -> Option<f64> {
        None
    }
}

/// A system that can also fill a block-diagonal Jacobian approximation.
pub trait JacobianSystem: OdeSystem {
    /// Fill `jac` at `(t, y)` with `f0 = f(t, y)`, for steps of about `h` (s; a problem may
    /// leave out what an explicit step of that size resolves); returns what that cost, in
    /// right-hand side evaluations (for the statistics).
    fn jacobian(&mut self, t: f64, y: &[f64], f0: &[f64], h: f64, jac: &mut BlockJacobian) -> u64;
    /// Accepted steps one Jacobian may serve (a W-method keeps its order with any
    /// approximation; a cheap partial Jacobian is best kept fresh).
    fn jacobian_max_age(&self) -> u32 {
        20
    }
}
