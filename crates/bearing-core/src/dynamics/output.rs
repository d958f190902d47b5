//! What a run produces: solver statistics, steady-window averages and sampled channels.

use serde::{Deserialize, Serialize};

/// Integrator statistics.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
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
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct BallSummary {
    /// Mean inner-race contact load, N.
    #[serde(deserialize_with = "crate::json_float::f64_or_nan")]
    #[cfg_attr(feature = "openapi", schema(nullable))]
    pub inner_load: f64,
    /// Mean outer-race contact load, N.
    #[serde(deserialize_with = "crate::json_float::f64_or_nan")]
    #[cfg_attr(feature = "openapi", schema(nullable))]
    pub outer_load: f64,
    /// Mean inner contact angle, rad.
    #[serde(deserialize_with = "crate::json_float::f64_or_nan")]
    #[cfg_attr(feature = "openapi", schema(nullable))]
    pub inner_contact_angle: f64,
    /// Mean outer contact angle, rad.
    #[serde(deserialize_with = "crate::json_float::f64_or_nan")]
    #[cfg_attr(feature = "openapi", schema(nullable))]
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
    /// Mean cage spin speed over the window (each step's cubic through the speed and its
    /// rate at both ends, integrated), rad/s.
    pub mean_cage_speed: f64,
    /// Pure-rolling (epicyclic) cage speed of the loaded balls at the mean shaft speed:
    /// rolling kinematics with outer-race control at `loaded_contact_angles`, rad/s.
    pub epicyclic_cage_speed: f64,
    /// Cage slip against the loaded balls' pure rolling, `1 - mean / epicyclic`, -
    /// (negative when the cage runs faster than the loaded balls would roll it).
    pub cage_slip: f64,
    /// Inner and outer contact angles of the load zone, each azimuth weighted by its mean
    /// contact load on that race, rad.
    pub loaded_contact_angles: [f64; 2],
    /// Mean force the balls exert on the inner ring (X, Y, Z), N; balances the applied load.
    pub mean_inner_ring_reaction: [f64; 3],
    /// Per ball, averaged over the window (each ball orbits through the whole bearing).
    pub balls: Vec<BallSummary>,
    /// Load distribution: averages over whichever ball sits within half a ball spacing of
    /// azimuth `2 pi k / Z` (k = 0..Z), comparable with the quasi-static ball k.
    pub load_zone: Vec<BallSummary>,
    /// How the cage centre moved relative to its guiding ring over the window.
    #[serde(default)]
    pub cage_motion: CageMotion,
}

/// The cage centre's motion relative to its guiding ring (the outer ring for a ball-guided
/// cage) over the steady window.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct CageMotion {
    /// Quiet, or whirling (the centre orbits).
    pub state: CageState,
    /// Mean eccentricity over the land's radial clearance, - (0 centred, 1 touching).
    pub mean_eccentricity: f64,
    /// Largest eccentricity ratio, -.
    pub max_eccentricity: f64,
    /// Mean angular speed of the centre's orbit, rad/s (positive with the shaft).
    pub whirl_speed: f64,
}

/// Whether the cage runs quietly or whirls.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum CageState {
    /// The centre stays near one position: it does not complete a tenth of an orbit per
    /// cage revolution.
    #[default]
    Quiet,
    /// The centre orbits at more than a tenth of the cage speed (half-speed whirl is the
    /// usual form) with an eccentricity ratio above 0.1.
    Whirling,
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
    /// Samples of `channel` inside the summary's steady window; `None` for a channel the
    /// run did not record.
    pub fn steady_samples(&self, channel: &str) -> Option<&[f64]> {
        let fs = self.channels.sample_rate;
        let data = &self.channels.get(channel)?.data;
        let w0 = ((self.summary.steady_window[0] - self.channels.start_time) * fs) as usize;
        Some(&data[w0.min(data.len())..])
    }
}
