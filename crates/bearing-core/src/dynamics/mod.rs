//! Equations of motion and their integration: the right-hand side, Runge-Kutta
//! integrators, the stepping loop, uniform output sampling, steady-window averages and
//! the result types. A run starts from a state vector it is given.

pub mod auto_switch;
pub mod averages;
pub mod ball_equilibrium;
pub mod block_jacobian;
pub mod control;
pub mod error;
pub mod error_scale;
pub mod integrator;
pub mod output;
pub mod recorder;
pub mod rhs;
pub mod rosenbrock;
pub mod run;
pub mod solver;
pub mod step_bound;
pub mod system;
pub mod window;

pub use control::RunControl;
pub use error::DynError;
pub use output::{
    BallSummary, CageMotion, CageState, Channel, Channels, SimResult, SolverStats, Summary,
};
