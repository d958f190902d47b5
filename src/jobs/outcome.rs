//! How the blocking part of a job ends: what to store, or why it failed.

use crate::store::{Artifact, FailureKind};

/// A successful job's outputs, ready for the store.
pub struct JobOutput {
    /// The serialized record (`record::SimulationRecord` or `record::AnalysisJobRecord`).
    pub result: serde_json::Value,
    /// Solver statistics (simulations).
    pub stats: Option<serde_json::Value>,
    pub artifacts: Vec<Artifact>,
    /// The run's study scene key under this build (simulations), written over the
    /// submitter's (`store::Outcome::Succeeded`).
    pub scene_key: Option<String>,
}

/// A job that did not succeed.
#[derive(Debug)]
pub struct JobFailure {
    pub kind: FailureKind,
    pub message: String,
    pub stats: Option<serde_json::Value>,
}

impl JobFailure {
    pub fn new(kind: FailureKind, message: impl Into<String>) -> Self {
        JobFailure {
            kind,
            message: message.into(),
            stats: None,
        }
    }
    pub fn is_cancel(&self) -> bool {
        self.kind == FailureKind::Cancelled
    }
}

/// A record as the JSON the store keeps (records are plain data: serializing cannot fail
/// short of a bug, which fails the job rather than the process).
pub fn to_stored<T: serde::Serialize>(record: &T) -> Result<serde_json::Value, JobFailure> {
    serde_json::to_value(record).map_err(|e| {
        JobFailure::new(
            FailureKind::Internal,
            format!("result not serializable: {e}"),
        )
    })
}
