//! What a job stores as its result, as types: written by the jobs, read back by the API
//! with `serde_json::from_value` (never by JSON pointer). `GET .../result` returns the
//! stored record with the job's `id` added.

use bearing_core::signal::analysis::{AnalysisOptions, AnalysisReport};
use bearing_core::simulation::{BallSummary, SolverStats};
use bearing_core::simulation_analysis::FrequencyComparison;
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

/// An analysis as stored: the report and the options it ran with.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct AnalysisRecord {
    #[serde(flatten)]
    pub report: AnalysisReport,
    /// The options the analysis ran with (harmonics searched, levels, filters, ...).
    /// Records stored before this field existed read back with the defaults, which is
    /// what every simulation job and option-less analysis ran with.
    #[serde(default)]
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
    /// The engine build that computed this record: `bearing_core::ENGINE_DIGEST`, 16 hex
    /// digits over the engine's sources, locked dependencies, compiler, target and compiler
    /// flags. Empty in records stored before it existed.
    #[serde(default)]
    pub engine: String,
    pub solver: SolverStats,
    /// Window of the averages and of the analysis, s.
    pub steady_window: [f64; 2],
    pub shaft_speed: SpeedRecord,
    pub cage: CageRecord,
    /// BPFO, BPFI and FTF from eq. 37 at the nominal angle, from the loaded balls' pure
    /// rolling, and from the run's cage speed (absent in records stored before it existed).
    #[serde(default)]
    pub frequencies: Option<FrequencyComparison>,
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

/// Cage speed over the steady window (null only for a degenerate run).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct CageRecord {
    /// rad/s.
    #[serde(deserialize_with = "bearing_core::json_float::f64_or_nan")]
    #[schema(nullable)]
    pub mean_speed: f64,
    /// Pure-rolling cage speed at the load-weighted contact angles, rad/s.
    #[serde(deserialize_with = "bearing_core::json_float::f64_or_nan")]
    #[schema(nullable)]
    pub epicyclic_speed: f64,
    /// 1 - mean / epicyclic, -: negative when the cage runs faster than the loaded balls
    /// would roll it.
    #[serde(deserialize_with = "bearing_core::json_float::f64_or_nan")]
    #[schema(nullable)]
    pub slip: f64,
    /// What `epicyclic_speed` and `slip` mean (absent in records stored before it existed).
    #[serde(default)]
    pub slip_definition: Option<String>,
    /// The cage centre's motion on its land: quiet or whirling, eccentricity ratio and
    /// whirl speed (absent in records stored before it existed).
    #[serde(default)]
    pub motion: Option<bearing_core::dynamics::CageMotion>,
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

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn an_analysis_stored_before_options_were_recorded_reads_back() {
        // the shape written by the service before analysis records kept their options
        let mut report = serde_json::to_value(AnalysisRecord {
            report: sample_report(),
            options: AnalysisOptions::default(),
            channel: None,
        })
        .unwrap();
        report.as_object_mut().unwrap().remove("options");
        let old = json!({"analysis": report, "samples": 4096});
        let r: AnalysisJobRecord = serde_json::from_value(old).unwrap();
        assert_eq!(r.analysis.options, AnalysisOptions::default());
    }

    fn sample_report() -> AnalysisReport {
        let g = bearing_core::signal::kinematic_preset("cwru6205").unwrap();
        let x: Vec<f64> = (0..4096)
            .map(|i| ((i * 37 % 101) as f64 - 50.0) / 50.0)
            .collect();
        bearing_core::signal::analyze(&x, 12_000.0, &g, 30.0, &AnalysisOptions::default())
            .unwrap()
            .report
    }
}
