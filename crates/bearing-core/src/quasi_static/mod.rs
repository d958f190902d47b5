//! Quasi-static (Jones-Harris) equilibrium of the bearing at a given speed and load.
//!
//! It is the reference the dynamic model is checked against and the initial state of
//! every dynamic run.

mod cage_balance;
mod error;
mod initial_state;
mod pocket_cycle;
mod solver;

pub use cage_balance::{cage_balance, CageBalance};
pub use error::QsError;
pub use initial_state::initial_state;
pub use pocket_cycle::{PocketCycle, PocketCycleSettings};
pub use solver::{pocket_cycle, pocket_cycle_until, pocket_cycle_with};
pub use solver::{solve, solve_model, QsBall, QsState, QuasiStaticSolution};
