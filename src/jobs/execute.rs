//! The blocking part of a job: decode its input, run the engine or the analysis, and
//! turn the result into what the store keeps.

use super::{analysis_job, postprocess};
use crate::store::{Artifact, Claimed, JobKind};
use bearing_sim::scene::Scene;
use bearing_sim::simulation::{simulate, RunControl, SimError};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;

/// Shared between the blocking run and its async heartbeat loop.
#[derive(Clone, Default)]
pub struct Control {
    pub cancel: Arc<AtomicBool>,
    /// f64 bits of the fraction done.
    pub progress: Arc<AtomicU64>,
}

impl Control {
    pub fn progress(&self) -> f64 {
        f64::from_bits(self.progress.load(Ordering::Relaxed))
    }
    pub fn set_progress(&self, f: f64) {
        self.progress.store(f.to_bits(), Ordering::Relaxed);
    }
}

pub struct JobOutput {
    pub result: serde_json::Value,
    pub stats: Option<serde_json::Value>,
    pub artifacts: Vec<Artifact>,
}

/// A job that did not succeed.
#[derive(Debug)]
pub struct JobFailure {
    /// `invalid`, `numerical`, `panic`, `cancelled`, `analysis`.
    pub kind: &'static str,
    pub message: String,
    pub stats: Option<serde_json::Value>,
}

impl JobFailure {
    pub fn new(kind: &'static str, message: impl Into<String>) -> Self {
        JobFailure {
            kind,
            message: message.into(),
            stats: None,
        }
    }
    pub fn is_cancel(&self) -> bool {
        self.kind == "cancelled"
    }
}

pub fn execute(job: &Claimed, ctl: &Control) -> Result<JobOutput, JobFailure> {
    match job.kind {
        JobKind::Simulation => run_simulation(&job.input, ctl),
        JobKind::Analysis => {
            analysis_job::execute(&job.input, job.input_blob.as_deref().unwrap_or(&[]), ctl)
        }
    }
}

fn run_simulation(input: &serde_json::Value, ctl: &Control) -> Result<JobOutput, JobFailure> {
    let scene: Scene = serde_json::from_value(input.clone())
        .map_err(|e| JobFailure::new("invalid", format!("stored scene does not parse: {e}")))?;
    let mut on_progress = |f: f64| ctl.set_progress(f);
    let run = simulate(
        &scene,
        RunControl {
            cancel: Some(&ctl.cancel),
            progress: Some(&mut on_progress),
        },
    );
    let result = match run {
        Ok(r) => r,
        Err(SimError::Cancelled { at }) => {
            return Err(JobFailure::new(
                "cancelled",
                format!("cancelled at t = {at} s"),
            ))
        }
        Err(e @ SimError::Invalid(_)) => return Err(JobFailure::new("invalid", e.to_string())),
        Err(e @ SimError::Numerical { .. }) => {
            return Err(JobFailure::new("numerical", e.to_string()))
        }
    };
    let stats = serde_json::to_value(&result.summary.stats).ok();
    // A NaN that slipped past the engine fails the job rather than poisoning stored results.
    for ch in &result.channels.channels {
        if let Some(k) = ch.data.iter().position(|x| !x.is_finite()) {
            return Err(JobFailure {
                kind: "numerical",
                message: format!("channel {} has a non-finite sample at index {k}", ch.name),
                stats,
            });
        }
    }
    let (summary, artifacts) = postprocess::summarize(&scene, &result);
    Ok(JobOutput {
        result: summary,
        stats,
        artifacts,
    })
}
