//! What the API shows of jobs (typed views), their ETags and timestamps.

use crate::store::{Job, JobError, JobKind, JobState};
use bearing_core::simulation::SolverStats;
use serde::Serialize;
use std::collections::BTreeMap;
use utoipa::ToSchema;

/// Collection path of a job kind.
pub fn collection(kind: JobKind) -> &'static str {
    match kind {
        JobKind::Simulation => "/v1/simulations",
        JobKind::Analysis => "/v1/analyses",
    }
}

pub fn job_location(job: &Job) -> String {
    format!("{}/{}", collection(job.kind), job.id)
}

/// Strong ETag: changes with every visible change of the job (the row version).
pub fn etag(job: &Job) -> String {
    format!("\"{}-{}\"", &job.id[..job.id.len().min(8)], job.version)
}

/// Does an `If-None-Match` header value match this ETag (`*`, or one of a list)?
pub fn etag_matches(if_none_match: &str, etag: &str) -> bool {
    if_none_match
        .split(',')
        .map(str::trim)
        .any(|t| t == "*" || t.trim_start_matches("W/") == etag)
}

/// A job as the API shows it.
#[derive(Debug, Clone, Serialize, ToSchema)]
#[schema(example = json!({
    "id": "019a4f7e-3c1b-7d2a-9f10-2b6c8e4d5a71",
    "kind": "simulation",
    "state": "running",
    "label": "H7005C (Table 1) compound inner+outer fault",
    "progress": 0.42,
    "attempt": 1,
    "cancel_requested": false,
    "created_at": "2026-01-01T12:00:00.000Z",
    "started_at": "2026-01-01T12:00:00.050Z",
    "finished_at": null,
    "updated_at": "2026-01-01T12:00:00.400Z",
    "stats": null,
    "error": null,
    "links": {
        "self": "/v1/simulations/019a4f7e-3c1b-7d2a-9f10-2b6c8e4d5a71",
        "cancel": "/v1/simulations/019a4f7e-3c1b-7d2a-9f10-2b6c8e4d5a71/cancel"
    }
}))]
pub struct JobView {
    /// Job id (a UUID).
    pub id: String,
    pub kind: JobKind,
    pub state: JobState,
    /// The scene's name, or a description of the analysed signal.
    pub label: String,
    /// Fraction of simulated time done, 0..=1.
    #[schema(minimum = 0.0, maximum = 1.0)]
    pub progress: f64,
    /// Times a worker claimed the job (a lost worker's job is retried).
    pub attempt: i64,
    pub cancel_requested: bool,
    /// RFC 3339, UTC.
    #[schema(format = DateTime)]
    pub created_at: String,
    #[schema(format = DateTime)]
    pub started_at: Option<String>,
    #[schema(format = DateTime)]
    pub finished_at: Option<String>,
    #[schema(format = DateTime)]
    pub updated_at: String,
    /// Solver statistics once a simulation's run ended.
    pub stats: Option<SolverStats>,
    pub error: Option<JobError>,
    /// `self`, `cancel`, and once succeeded `result`, `spectra` (and `signals`).
    pub links: BTreeMap<String, String>,
}

impl JobView {
    pub fn of(job: &Job) -> JobView {
        let base = job_location(job);
        let mut links = BTreeMap::new();
        links.insert("self".to_string(), base.clone());
        links.insert("cancel".to_string(), format!("{base}/cancel"));
        if job.state == JobState::Succeeded {
            links.insert("result".into(), format!("{base}/result"));
            links.insert("spectra".into(), format!("{base}/spectra"));
            if job.kind == JobKind::Simulation {
                links.insert("signals".into(), format!("{base}/signals"));
            }
        }
        JobView {
            id: job.id.clone(),
            kind: job.kind,
            state: job.state,
            label: job.label.clone(),
            progress: job.progress,
            attempt: job.attempt,
            cancel_requested: job.cancel_requested,
            created_at: rfc3339(job.created_at),
            started_at: job.started_at.map(rfc3339),
            finished_at: job.finished_at.map(rfc3339),
            updated_at: rfc3339(job.updated_at),
            // stored by the jobs layer from the engine's own type
            stats: job
                .stats
                .clone()
                .and_then(|v| serde_json::from_value(v).ok()),
            error: job.error.clone(),
            links,
        }
    }
}

/// One page of jobs, newest first.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct JobPage {
    pub items: Vec<JobView>,
    /// Cursor of the next (older) page; null on the last page.
    pub next_cursor: Option<String>,
    /// Link to the next page.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(required = false)]
    pub next: Option<String>,
}

/// A liveness or readiness answer.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct Status {
    /// `ok` (health) or `ready` (readiness).
    pub status: String,
}

/// Unix milliseconds as an RFC 3339 UTC timestamp with millisecond precision.
pub fn rfc3339(ms: i64) -> String {
    let secs = ms.div_euclid(1000);
    let milli = ms.rem_euclid(1000);
    let days = secs.div_euclid(86_400);
    let sod = secs.rem_euclid(86_400);
    let (y, m, d) = civil_from_days(days);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}.{milli:03}Z",
        sod / 3600,
        sod % 3600 / 60,
        sod % 60
    )
}

/// Proleptic Gregorian date of a day count since 1970-01-01 (H. Hinnant's algorithm).
fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + if m <= 2 { 1 } else { 0 };
    (y, m, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_timestamps() {
        assert_eq!(rfc3339(0), "1970-01-01T00:00:00.000Z");
        assert_eq!(rfc3339(951_782_400_123), "2000-02-29T00:00:00.123Z");
        assert_eq!(rfc3339(1_795_000_000_000), "2026-11-18T11:06:40.000Z");
    }

    #[test]
    fn if_none_match_lists() {
        assert!(etag_matches("\"a\", W/\"b\"", "\"b\""));
        assert!(etag_matches("*", "\"x\""));
        assert!(!etag_matches("\"a\"", "\"b\""));
    }
}
