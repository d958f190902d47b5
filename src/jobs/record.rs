//! What a job stores as its result, as types: written by the jobs, read back by the API
//! with `serde_json::from_value` (never by JSON pointer). `GET .../result` returns the
//! stored record with the job's `id` added.

use bearing_core::signal::analysis::{AnalysisOptions, AnalysisReport};
use bearing_core::simulation::{BallSummary, SolverStats};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

/// An analysis as stored: the report and the options it ran with.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct AnalysisRecord {
    #[serde(flatten)]
    pub report: AnalysisReport,
    /// The options the analysis ran with (harmonics searched, levels, filters, ...).
    pub options: AnalysisOptions,
    /// The simulated channel analysed (simulations only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub channel: Option<String>,
}

/// The result of an analysis job.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct AnalysisJobRecord {
    pub analysis: AnalysisRecord,
    /// Samples received.
    pub samples: usize,
}

/// The result of a simulation job: the run's summary, the channels recorded, and the
/// analysis of the outer-ring acceleration (or why there is none).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct SimulationRecord {
    pub scene_name: String,
    pub solver: SolverStats,
    /// Window of the averages and of the analysis, s.
    pub steady_window: [f64; 2],
    pub shaft_speed: SpeedRecord,
    pub cage: CageRecord,
    /// Mean force the balls exert on the inner ring (X, Y, Z), N.
    pub mean_inner_ring_reaction: [f64; 3],
    pub contact: ContactRecord,
    pub balls: Vec<BallSummary>,
    pub channels: Vec<ChannelInfo>,
    /// Hz.
    pub sample_rate: f64,
    /// s.
    pub start_time: f64,
    pub analysis: Option<AnalysisRecord>,
    pub analysis_error: Option<String>,
}

/// A mean speed with its unit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct SpeedRecord {
    #[serde(deserialize_with = "bearing_core::json_float::f64_or_nan")]
    #[schema(nullable)]
    pub mean: f64,
    /// `rad/s`.
    pub unit: String,
}

/// Cage speed over the steady window.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct CageRecord {
    /// rad/s.
    pub mean_speed: f64,
    /// Pure-rolling cage speed at the load-weighted contact angles, rad/s.
    pub epicyclic_speed: f64,
    /// 1 - mean / epicyclic, -.
    pub slip: f64,
    /// `rad/s`.
    pub unit: String,
}

/// Contact statistics over the balls (each averaged over the steady window).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct ContactRecord {
    pub inner_load: Option<MinMeanMax>,
    pub outer_load: Option<MinMeanMax>,
    pub inner_contact_angle: Option<MinMeanMax>,
    pub outer_contact_angle: Option<MinMeanMax>,
    pub units: ContactUnits,
}

/// Units of [`ContactRecord`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct ContactUnits {
    /// `N`.
    pub load: String,
    /// `rad`.
    pub angle: String,
}

/// Smallest, mean and largest value over the balls (NaN stored as null: a ball never
/// loaded has no contact angle).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct MinMeanMax {
    #[serde(deserialize_with = "bearing_core::json_float::f64_or_nan")]
    #[schema(nullable)]
    pub min: f64,
    #[serde(deserialize_with = "bearing_core::json_float::f64_or_nan")]
    #[schema(nullable)]
    pub mean: f64,
    #[serde(deserialize_with = "bearing_core::json_float::f64_or_nan")]
    #[schema(nullable)]
    pub max: f64,
}

impl MinMeanMax {
    /// `None` for no values. The mean is NaN if any value is; min and max skip NaNs.
    pub fn of(v: impl Iterator<Item = f64> + Clone) -> Option<MinMeanMax> {
        let n = v.clone().count();
        if n == 0 {
            return None;
        }
        Some(MinMeanMax {
            min: v.clone().fold(f64::INFINITY, f64::min),
            mean: v.clone().sum::<f64>() / n as f64,
            max: v.fold(f64::NEG_INFINITY, f64::max),
        })
    }
}

/// A recorded channel, without its samples (they are an artifact).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct ChannelInfo {
    pub name: String,
    pub unit: String,
    pub samples: usize,
}
