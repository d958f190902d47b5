//! One call from a validated scene to a simulation result.
//!
//! This is the engine's public face: the CLI and the service call [`simulate`] and
//! nothing deeper.

use crate::scene::{Scene, ValidationErrors};
use serde::{Deserialize, Serialize};
use std::sync::atomic::AtomicBool;

/// Cancellation and progress hooks, checked between integrator steps.
#[derive(Default)]
pub struct RunControl<'a> {
    /// Set to `true` (from any thread) to stop the run at the next step.
    pub cancel: Option<&'a AtomicBool>,
    /// Called with the fraction of simulated time done (0..=1), at most ~100 times a second.
    pub progress: Option<&'a mut dyn FnMut(f64)>,
}

/// Why a run did not produce a result.
#[derive(Debug, Clone, thiserror::Error, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SimError {
    #[error("invalid scene: {0}")]
    Invalid(#[from] ValidationErrors),
    #[error("cancelled at t = {at} s")]
    Cancelled { at: f64 },
    /// Non-finite state, step-size underflow or a failed quasi-static start.
    #[error("numerical failure at t = {time} s: {message}")]
    Numerical { time: f64, message: String },
}

impl<'de> Deserialize<'de> for ValidationErrors {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        struct Fe {
            path: String,
            message: String,
        }
        let v: Vec<Fe> = Vec::deserialize(d)?;
        Ok(ValidationErrors(
            v.into_iter()
                .map(|f| crate::scene::FieldError {
                    path: f.path,
                    message: f.message,
                })
                .collect(),
        ))
    }
}

/// Integrator statistics.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SolverStats {
    pub accepted_steps: u64,
    pub rejected_steps: u64,
    pub rhs_evaluations: u64,
    /// Smallest accepted step, s.
    pub min_step: f64,
    /// Largest accepted step, s.
    pub max_step: f64,
    /// Wall-clock time of the integration, s.
    pub wall_time: f64,
}

/// Time-averaged state of one ball over the steady window.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct BallSummary {
    /// Mean inner-race contact load, N.
    pub inner_load: f64,
    /// Mean outer-race contact load, N.
    pub outer_load: f64,
    /// Mean inner contact angle, rad.
    pub inner_contact_angle: f64,
    /// Mean outer contact angle, rad.
    pub outer_contact_angle: f64,
}

/// Scalar results of a run.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub stats: SolverStats,
    /// Time window used for the averages (after the speed ramp and its transient), s.
    pub steady_window: [f64; 2],
    /// Mean inner-ring (shaft) speed over the window, rad/s.
    pub mean_shaft_speed: f64,
    /// Mean cage angular speed, rad/s.
    pub mean_cage_speed: f64,
    /// Pure-rolling (epicyclic) cage speed at the mean shaft speed, rad/s.
    pub epicyclic_cage_speed: f64,
    /// Cage slip, 1 - mean / epicyclic, -.
    pub cage_slip: f64,
    /// Mean force the balls exert on the inner ring (X, Y, Z), N; balances the applied load.
    pub mean_inner_ring_reaction: [f64; 3],
    /// Per ball, averaged over the window (each ball orbits through the whole bearing).
    pub balls: Vec<BallSummary>,
    /// Load distribution: averages over whichever ball sits within half a ball spacing of
    /// azimuth `2 pi k / Z` (k = 0..Z), comparable with the quasi-static ball k.
    pub load_zone: Vec<BallSummary>,
}

/// One uniformly sampled channel.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Channel {
    /// e.g. `outer_ring_accel_y`.
    pub name: String,
    /// SI unit of the samples, e.g. `m/s^2`.
    pub unit: String,
    pub data: Vec<f64>,
}

/// Uniformly sampled channels; sample `k` is at `start_time + k / sample_rate`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Channels {
    /// Hz.
    pub sample_rate: f64,
    /// s.
    pub start_time: f64,
    pub channels: Vec<Channel>,
}

impl Channels {
    pub fn get(&self, name: &str) -> Option<&Channel> {
        self.channels.iter().find(|c| c.name == name)
    }
}

/// What a run produces.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimResult {
    pub summary: Summary,
    pub channels: Channels,
}

impl SimResult {
    /// RMS of `channel` below `fmax` (Hz) over the summary's steady window, in the channel's
    /// unit; `None` for a channel the run did not record.
    pub fn steady_band_rms(&self, channel: &str, fmax: f64) -> Option<f64> {
        let fs = self.channels.sample_rate;
        let data = &self.channels.get(channel)?.data;
        let w0 = ((self.summary.steady_window[0] - self.channels.start_time) * fs) as usize;
        Some(crate::signal::spectrum::band_rms(
            &data[w0.min(data.len())..],
            fs,
            fmax,
        ))
    }
}

/// Run a scene to completion (or cancellation / failure).
pub fn simulate(scene: &Scene, ctl: RunControl<'_>) -> Result<SimResult, SimError> {
    scene.validate()?;
    let model = crate::dynamics::model::Model::new(scene);
    let qs = crate::quasi_static::solve_model(&model, model.shaft_speed(0.0))?;
    crate::dynamics::run::integrate(&model, scene, &qs, ctl)
}
