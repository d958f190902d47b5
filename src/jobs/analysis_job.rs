//! Analysis of a measured signal: run directly for small signals (by the handler on a
//! bounded blocking thread) or as a queued job for large ones.

use super::execute::{Control, JobFailure, JobOutput};
use crate::store::blob::{decode_f64le, encode_f32le};
use crate::store::Artifact;
use bearing_sim::signal::analysis::{analyze, AnalysisOptions, AnalysisOutput, AnalysisReport};
use bearing_sim::signal::frequencies::KinematicGeometry;
use serde::{Deserialize, Serialize};
use serde_json::json;
use std::sync::atomic::Ordering;

/// A resolved analysis request (what a queued analysis job stores besides its samples).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct AnalysisInput {
    pub sample_rate: f64,
    pub geometry: KinematicGeometry,
    pub shaft_hz: f64,
    pub options: AnalysisOptions,
}

pub struct AnalysisRun {
    pub output: AnalysisOutput,
}

pub fn run_analysis(input: &AnalysisInput, samples: &[f64]) -> Result<AnalysisRun, String> {
    analyze(
        samples,
        input.sample_rate,
        &input.geometry,
        input.shaft_hz,
        &input.options,
    )
    .map(|output| AnalysisRun { output })
    .map_err(|e| e.to_string())
}

pub fn execute(
    input: &serde_json::Value,
    blob: &[u8],
    ctl: &Control,
) -> Result<JobOutput, JobFailure> {
    let input: AnalysisInput = serde_json::from_value(input.clone()).map_err(|e| {
        JobFailure::new(
            "invalid",
            format!("stored analysis request does not parse: {e}"),
        )
    })?;
    if ctl.cancel.load(Ordering::SeqCst) {
        return Err(JobFailure::new(
            "cancelled",
            "cancelled before the analysis started",
        ));
    }
    let samples = decode_f64le(blob);
    let run = run_analysis(&input, &samples).map_err(|m| JobFailure::new("analysis", m))?;
    ctl.set_progress(1.0);
    Ok(JobOutput {
        result: json!({ "analysis": analysis_json(&run.output.report), "samples": samples.len() }),
        stats: None,
        artifacts: spectrum_artifacts(&run.output),
    })
}

pub fn analysis_json(report: &AnalysisReport) -> serde_json::Value {
    serde_json::to_value(report).unwrap_or(serde_json::Value::Null)
}

/// Raw envelope spectrum and one per DTCWT level, as f32 blobs with their bin width.
pub fn spectrum_artifacts(out: &AnalysisOutput) -> Vec<Artifact> {
    let mut v = vec![Artifact {
        name: "spectrum:raw".into(),
        meta: json!({"df": out.raw_spectrum.df, "bins": out.raw_spectrum.amplitude.len()}),
        data: encode_f32le(&out.raw_spectrum.amplitude),
    }];
    for (i, s) in out.level_spectra.iter().enumerate() {
        v.push(Artifact {
            name: format!("spectrum:level:{}", i + 1),
            meta: json!({"df": s.df, "bins": s.amplitude.len()}),
            data: encode_f32le(&s.amplitude),
        });
    }
    v
}
