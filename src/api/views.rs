//! JSON views of jobs, their ETags and timestamps.

use crate::store::{Job, JobKind};
use serde_json::{json, Value};

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

pub fn job_json(job: &Job) -> Value {
    let base = job_location(job);
    let mut links = json!({ "self": base, "cancel": format!("{base}/cancel") });
    if job.state == crate::store::JobState::Succeeded {
        links["result"] = json!(format!("{base}/result"));
        links["spectra"] = json!(format!("{base}/spectra"));
        if job.kind == JobKind::Simulation {
            links["signals"] = json!(format!("{base}/signals"));
        }
    }
    json!({
        "id": job.id,
        "kind": job.kind,
        "state": job.state,
        "label": job.label,
        "progress": job.progress,
        "attempt": job.attempt,
        "cancel_requested": job.cancel_requested,
        "created_at": rfc3339(job.created_at),
        "started_at": job.started_at.map(rfc3339),
        "finished_at": job.finished_at.map(rfc3339),
        "updated_at": rfc3339(job.updated_at),
        "stats": job.stats,
        "error": job.error,
        "links": links,
    })
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
