//! Equations of motion and their integration: state layout, constants built from a
//! scene, the right-hand side, Runge-Kutta integrators and uniform output sampling.

pub mod integrator;
pub mod model;
pub mod rhs;
pub mod run;
pub mod state;
