//! Quasi-static (Jones-Harris) equilibrium of the bearing at a given speed and load.
//!
//! It is the reference the dynamic model is checked against and the initial state of
//! every dynamic run.

use crate::scene::Scene;
use crate::simulation::SimError;
use serde::{Deserialize, Serialize};

/// Equilibrium of one ball.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct QsBall {
    /// Azimuth of the ball centre, rad.
    pub azimuth: f64,
    /// Inner-race normal contact load, N.
    pub inner_load: f64,
    /// Outer-race normal contact load, N.
    pub outer_load: f64,
    /// Inner contact angle, rad.
    pub inner_contact_angle: f64,
    /// Outer contact angle, rad.
    pub outer_contact_angle: f64,
    /// Centrifugal force on the ball, N.
    pub centrifugal_force: f64,
    /// Gyroscopic moment on the ball, N m.
    pub gyroscopic_moment: f64,
}

/// Quasi-static solution of a scene at one shaft speed.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct QuasiStaticSolution {
    /// Shaft (inner-ring) speed, rad/s.
    pub shaft_speed: f64,
    /// Inner-ring displacement relative to the outer ring (x axial, y, z), m.
    pub inner_ring_displacement: [f64; 3],
    /// Inner-ring tilt about Y and Z, rad (0 when locked).
    pub inner_ring_tilt: [f64; 2],
    /// Kinematic (pure-rolling, epicyclic) cage speed, rad/s.
    pub cage_speed: f64,
    /// Ball spin about its own axis, rad/s.
    pub ball_spin_speed: f64,
    /// Inner groove curvature factor used, -.
    pub inner_groove_curvature: f64,
    /// Outer groove curvature factor used, -.
    pub outer_groove_curvature: f64,
    /// Newton iterations taken.
    pub iterations: u32,
    /// Largest force residual at the solution, N.
    pub residual: f64,
    pub balls: Vec<QsBall>,
}

/// Solve the scene's bearing at `shaft_rpm` under its operating loads.
pub fn solve(scene: &Scene, shaft_rpm: f64) -> Result<QuasiStaticSolution, SimError> {
    scene.validate()?;
    let _ = shaft_rpm;
    Err(SimError::Numerical { time: 0.0, message: "quasi-static solver not yet implemented".into() })
}
