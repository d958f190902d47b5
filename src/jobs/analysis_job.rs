//! Analysis of a measured signal: run directly for small signals (by the handler on a
//! bounded blocking thread) or as a queued job for large ones.

use super::artifacts::spectrum_artifacts;
use super::control::Control;
use super::outcome::{to_stored, JobFailure, JobOutput};
use super::record::{AnalysisJobRecord, AnalysisRecord};
use crate::store::blob::decode_f64le;
use crate::store::FailureKind;
use bearing_core::signal::analysis::{
    analyze_with, AnalysisError, AnalysisOptions, AnalysisOutput, LevelSpectra,
};
use bearing_core::signal::frequencies::KinematicGeometry;
use serde::{Deserialize, Serialize};
use std::sync::atomic::AtomicBool;

/// A resolved analysis request (what a queued analysis job stores besides its samples).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct AnalysisInput {
    /// Hz.
    pub sample_rate: f64,
    pub geometry: KinematicGeometry,
    /// Hz.
    pub shaft_hz: f64,
    pub options: AnalysisOptions,
}

/// The analysis pipeline on `samples` as `input` describes them; it stops with
/// `AnalysisError::Cancelled` soon after `cancel` is set.
pub fn run_analysis(
    input: &AnalysisInput,
    samples: &[f64],
    cancel: Option<&AtomicBool>,
) -> Result<AnalysisOutput, AnalysisError> {
    analyze_with(
        samples,
        input.sample_rate,
        &input.geometry,
        input.shaft_hz,
        &input.options,
        cancel,
        LevelSpectra::All,
    )
}

pub fn execute(
    input: &serde_json::Value,
    blob: &[u8],
    ctl: &Control,
) -> Result<JobOutput, JobFailure> {
    let input: AnalysisInput = serde_json::from_value(input.clone()).map_err(|e| {
        JobFailure::new(
            FailureKind::Invalid,
            format!("stored analysis request does not parse: {e}"),
        )
    })?;
    if ctl.is_cancelled() {
        return Err(JobFailure::new(
            FailureKind::Cancelled,
            "cancelled before the analysis started",
        ));
    }
    let samples = decode_f64le(blob);
    let out = run_analysis(&input, &samples, Some(&ctl.cancel)).map_err(|e| match e {
        AnalysisError::Cancelled => {
            JobFailure::new(FailureKind::Cancelled, "cancelled during the analysis")
        }
        e => JobFailure::new(FailureKind::Analysis, e.to_string()),
    })?;
    ctl.set_progress(1.0);
    let artifacts = spectrum_artifacts(&out);
    let record = AnalysisJobRecord {
        analysis: AnalysisRecord {
            report: out.report,
            options: input.options,
            channel: None,
        },
        samples: samples.len(),
    };
    Ok(JobOutput {
        result: to_stored(&record)?,
        stats: None,
        artifacts,
        scene_key: None,
    })
}
