//! One call from a valid scene to a simulation result.
//!
//! This is the engine's public face: the CLI and the service call [`simulate`] and
//! nothing deeper.

use crate::dynamics::run::integrate;
use crate::dynamics::DynError;
use crate::model::Model;
use crate::quasi_static::{initial_state, solve_model, QsError};
use crate::scene::ValidScene;

pub use crate::dynamics::{
    BallSummary, Channel, Channels, RunControl, SimResult, SolverStats, Summary,
};

/// Why a run did not produce a result.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    /// No quasi-static equilibrium to start from at the initial speed.
    #[error("no initial state: {0}")]
    InitialState(#[from] QsError),
    /// The integration stopped: cancelled, step-size underflow or a non-finite state.
    #[error(transparent)]
    Dynamics(#[from] DynError),
}

impl SimError {
    pub fn is_cancelled(&self) -> bool {
        matches!(self, SimError::Dynamics(DynError::Cancelled { .. }))
    }
}

/// Run a scene to completion (or cancellation / failure): the quasi-static equilibrium at
/// the initial speed is the state at t = 0.
pub fn simulate(scene: &ValidScene, ctl: RunControl<'_>) -> Result<SimResult, SimError> {
    let model = Model::new(scene);
    let qs = solve_model(&model, model.shaft_speed(0.0))?;
    let y0 = initial_state(&model, &qs);
    Ok(integrate(&model, scene, y0, ctl)?)
}
