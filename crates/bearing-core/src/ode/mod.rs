//! A generic solver of initial value problems `dy/dt = f(t, y)`, kept apart from the
//! bearing (it imports nothing of the engine; `tests/checks/import_graph.rs` holds it to that).
//!
//! Three roles, as in diffsol:
//! - the problem ([`problem::OdeSystem`], and [`problem::JacobianSystem`] for a linearly
//!   implicit method) evaluates the derivative, may bound the step and may project the
//!   state after a step;
//! - a method ([`method::Method`]) proposes one step and its error: an explicit
//!   Runge-Kutta method given by its tableau ([`explicit_rk::ExplicitRk`] over
//!   [`tableau`]), the exponential RK4 around a linear part the problem names
//!   ([`etd_rk4::EtdRk4`]), the Rosenbrock-W method ([`rosenbrock::Rosenbrock`]), or the
//!   switch between an explicit one and it ([`auto_switch::AutoSwitch`]); every controlled method measures its error
//!   with the one [`error_norm::ErrorNorm`] and sizes its next step with the one
//!   [`controller::Controller`];
//! - the solver ([`solver::Solver`]) owns the state: accept and reject, landing on the end
//!   time, dense output of the last step ([`hermite`]).

/// Test problems whose Jacobian is differences of their own right-hand side (unit scales, the
/// whole state one block): `JacobianSystem` for a `Copy` problem of at most 8 components.
#[cfg(test)]
macro_rules! jacobian_by_differences {
    ($problem:ty) => {
        impl crate::ode::problem::JacobianSystem for $problem {
            fn jacobian(
                &mut self,
                t: f64,
                y: &[f64],
                f0: &[f64],
                _h: f64,
                jac: &mut crate::ode::block_jacobian::BlockJacobian,
            ) -> u64 {
                let mut problem = *self;
                let scale = [1.0; 8];
                jac.evaluate(t, y, f0, &scale[..y.len()], |t, y, dy| {
                    crate::ode::problem::OdeSystem::rhs(&mut problem, t, y, dy)
                });
                jac.cost_in_rhs() as u64
            }
        }
    };
}

pub mod auto_switch;
pub mod block_jacobian;
pub mod control;
pub mod controller;
pub mod error;
pub mod error_norm;
pub mod etd_rk4;
pub mod explicit_rk;
mod exponential_operators;
pub mod hermite;
pub mod method;
pub mod problem;
pub mod rosenbrock;
pub mod rosenbrock_tableau;
pub mod solver;
pub mod stats;
pub mod tableau;
