//! A generic solver of initial value problems `dy/dt = f(t, y)`, kept apart from the
//! bearing (it imports nothing of the engine; `tests/checks/import_graph.rs` holds it to that).
//!
//! Three roles, as in diffsol:
//! - the problem ([`problem::OdeSystem`], and [`problem::JacobianSystem`] for a linearly
//!   implicit method) evaluates the derivative, may bound the step and may project the
//!   state after a step;
//! - a method ([`method::Method`]) proposes one step and its error: an explicit
//!   Runge-Kutta method given by its tableau ([`explicit_rk::ExplicitRk`] over
//!   [`tableau`]), the Rosenbrock-W method ([`rosenbrock::Rosenbrock`]), or the switch
//!   between them ([`auto_switch::AutoSwitch`]); every controlled method measures its error
//!   with the one [`error_norm::ErrorNorm`] and sizes its next step with the one
//!   [`controller::Controller`];
//! - the solver ([`solver::Solver`]) owns the state: accept and reject, landing on the end
//!   time, dense output of the last step ([`hermite`]).

pub mod auto_switch;
pub mod block_jacobian;
pub mod control;
pub mod controller;
pub mod error;
pub mod error_norm;
pub mod explicit_rk;
pub mod hermite;
pub mod method;
pub mod problem;
pub mod rosenbrock;
pub mod rosenbrock_tableau;
pub mod solver;
pub mod stats;
pub mod tableau;
