//! The bearing's equations of motion and what a run makes of them: the right-hand side,
//! the bearing as a problem for the generic solver of [`crate::ode`] (its error scales,
//! step bound and Jacobian), the run loop, uniform output sampling, steady-window
//! averages and the result types. A run starts from a state vector it is given.

pub mod averages;
pub mod ball_equilibrium;
pub mod error_scale;
pub mod output;
pub mod recorder;
pub mod rhs;
pub mod run;
pub mod step_bound;
pub mod system;
pub mod window;

pub use output::{
    BallSummary, CageMotion, CageState, Channel, Channels, SimResult, SolverStats, Summary,
};
