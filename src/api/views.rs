//! What the API shows of jobs (typed views), their ETags and timestamps.

use crate::store::{Job, JobError, JobKind, JobState};
use bearing_core::scene::MAX_NAME_CHARS;
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

/// Longest error message a job view shows, in characters. Messages are the service's own
/// (a solver failure, a limit), well under it; the bound keeps a listing's size bounded.
pub const MAX_ERROR_CHARS: usize = 2000;

/// `text` cut to `max` characters, with an ellipsis when cut. Inputs are bounded before
/// they are stored; this bounds what was stored before the bounds existed too.
pub fn bounded_text(text: &str, max: usize) -> String {
    match text.char_indices().nth(max) {
        None => text.to_string(),
        Some((end, _)) => {
            let cut = text[..end]
                .char_indices()
                .nth(max - 1)
                .map_or(0, |(i, _)| i);
            format!("{}\u{2026}", &text[..cut])
        }
    }
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
            label: bounded_text(&job.label, MAX_NAME_CHARS),
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
            error: job.error.as_ref().map(|e| JobError {
                kind: e.kind,
                message: bounded_text(&e.message, MAX_ERROR_CHARS),
            }),
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

    /// Largest job view, bytes of JSON: a label of [`MAX_NAME_CHARS`] and an error of
    /// [`MAX_ERROR_CHARS`] characters, each up to 6 bytes once escaped (`\u001f`), and 1.5 KiB
    /// of ids, times, statistics and links. A listing of `limit` jobs is at most `limit` times
    /// this (14 736 bytes; 500 of them are 7.0 MiB, where a typical view is 0.7 KiB).
    const MAX_JOB_VIEW_BYTES: usize = 6 * (MAX_NAME_CHARS + MAX_ERROR_CHARS) + 1536;

    #[test]
    fn formats_timestamps() {
        assert_eq!(rfc3339(0), "1970-01-01T00:00:00.000Z");
        assert_eq!(rfc3339(951_782_400_123), "2000-02-29T00:00:00.123Z");
        assert_eq!(rfc3339(1_795_000_000_000), "2026-11-18T11:06:40.000Z");
    }

    #[test]
    fn the_largest_job_view_is_within_its_bound() {
        // the worst a stored row can hold: names and messages far over their bounds, of
        // characters JSON escapes to six bytes, and the largest statistics
        let stats = SolverStats {
            accepted_steps: u64::MAX,
            rejected_steps: u64::MAX,
            rhs_evaluations: u64::MAX,
            min_step: -f64::MIN_POSITIVE,
            max_step: -f64::MAX,
            wall_time: -f64::MAX,
        };
        let job = Job {
            seq: i64::MAX,
            id: "019a4f7e-3c1b-7d2a-9f10-2b6c8e4d5a71".into(),
            tenant: "t".repeat(10_000),
            kind: JobKind::Simulation,
            state: JobState::Succeeded,
            label: "\u{1}".repeat(1 << 20),
            progress: -f64::MAX,
            attempt: i64::MIN,
            cancel_requested: true,
            version: i64::MIN,
            created_at: 4_102_444_800_000,
            started_at: Some(4_102_444_800_000),
            finished_at: Some(4_102_444_800_000),
            updated_at: 4_102_444_800_000,
            error: Some(JobError {
                kind: crate::store::FailureKind::LeaseExpired,
                message: "\u{1}".repeat(1 << 20),
            }),
            stats: Some(serde_json::to_value(&stats).unwrap()),
            result: None,
        };
        let view = JobView::of(&job);
        assert_eq!(view.label.chars().count(), MAX_NAME_CHARS);
        assert!(view.label.ends_with('\u{2026}'));
        let bytes = serde_json::to_vec(&view).unwrap().len();
        assert!(
            bytes <= MAX_JOB_VIEW_BYTES,
            "{bytes} > {MAX_JOB_VIEW_BYTES}"
        );
        assert_eq!(bounded_text("short", MAX_NAME_CHARS), "short");
    }

    #[test]
    fn if_none_match_lists() {
        assert!(etag_matches("\"a\", W/\"b\"", "\"b\""));
        assert!(etag_matches("*", "\"x\""));
        assert!(!etag_matches("\"a\"", "\"b\""));
    }
}
