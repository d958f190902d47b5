//! One call from a valid scene to a simulation result.
//!
//! This is the engine's public face: the CLI and the service call [`simulate`] and
//! nothing deeper.

use crate::dynamics::run::integrate;
use crate::model::Model;
use crate::ode::error::SolveError;
use crate::quasi_static::{initial_state, solve_model, QsError};
use crate::scene::{FieldError, ValidScene, ValidationErrors};

pub use crate::dynamics::{BallSummary, Channel, Channels, SimResult, SolverStats, Summary};
pub use crate::ode::control::RunControl;

/// Why a run did not produce a result.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    /// No quasi-static equilibrium to start from at the initial speed.
    #[error("no initial state: {0}")]
    InitialState(#[from] QsError),
    /// The integration stopped: cancelled, step-size underflow or a non-finite state.
    #[error(transparent)]
    Dynamics(#[from] SolveError),
}

impl SimError {
    pub fn is_cancelled(&self) -> bool {
        matches!(self, SimError::Dynamics(SolveError::Cancelled { .. }))
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

/// Refuse up front a scene whose run could not start: the quasi-static equilibrium at the
/// initial speed must exist (it is the state at t = 0). The errors name the fields to
/// change: the loads when the tilt-locked ring has too little axial load for its radial
/// load, the moment when a free ring cannot carry it. Costs one quasi-static solve
/// (milliseconds).
pub fn check_start(scene: &ValidScene) -> Result<(), ValidationErrors> {
    let model = Model::new(scene);
    match solve_model(&model, model.shaft_speed(0.0)) {
        Ok(_) => Ok(()),
        Err(e) => Err(start_errors(&e)),
    }
}

fn start_errors(e: &QsError) -> ValidationErrors {
    let err = |path: &str, message: String| FieldError {
        path: path.into(),
        message,
    };
    let list = match e {
        QsError::NoEquilibrium {
            axial_load,
            radial_load,
            axial_load_needed: Some(needed),
            ..
        } => vec![
            err(
                "operating.axial_load",
                format!(
                    "{axial_load} N cannot hold the radial load of {radial_load} N with the inner ring's tilt locked: no quasi-static equilibrium exists at the initial speed; the axial load must be above about Fr tan(alpha0) = {needed:.1} N"
                ),
            ),
            err(
                "operating.radial_load",
                format!(
                    "{radial_load} N needs an axial load above about Fr tan(alpha0) = {needed:.1} N with the inner ring's tilt locked, and {axial_load} N is applied"
                ),
            ),
        ],
        QsError::NoEquilibrium {
            moment_reached: Some(_),
            ..
        } => vec![err("operating.applied_moment", e.to_string())],
        QsError::InvalidSpeed { .. } => vec![err("operating.speed.initial_rpm", e.to_string())],
        QsError::NoEquilibrium { .. } => vec![err("operating", e.to_string())],
        // a run's start never asks for the pocket cycle
        QsError::PocketCycle { .. } => vec![err("operating", e.to_string())],
    };
    ValidationErrors(list)
}
