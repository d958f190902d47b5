//! RFC 9457 problem details: the one shape of every error response.

use crate::store::{JobState, StoreError};
use axum::body::Body;
use axum::http::{header, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use bearing_core::scene::{FieldError, ValidationErrors};
use serde::Serialize;
use utoipa::ToSchema;

pub const PROBLEM_JSON: &str = "application/problem+json";

/// One field problem: `path` is dotted from the request body's root (`scene.bearing.width`).
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct FieldProblem {
    pub path: String,
    pub message: String,
}

/// RFC 9457 problem details.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct Problem {
    /// `about:blank` for plain HTTP errors, `urn:bearing-sim:problem:<slug>` otherwise.
    #[serde(rename = "type")]
    pub type_: String,
    pub title: String,
    /// The HTTP status.
    pub status: u16,
    pub detail: String,
    /// Every field problem, with its path from the request body's root.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(required = false, nullable = false)]
    pub errors: Option<Vec<FieldProblem>>,
    /// The job's state, for a request not possible in it (409).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(required = false, nullable = false, value_type = JobState)]
    pub job_state: Option<String>,
    #[serde(skip)]
    pub retry_after: Option<u64>,
}

/// Problem types of this service; plain HTTP errors use `about:blank`.
fn type_uri(slug: &str) -> String {
    format!("urn:bearing-sim:problem:{slug}")
}

impl Problem {
    pub fn new(
        status: StatusCode,
        slug: Option<&str>,
        title: &str,
        detail: impl Into<String>,
    ) -> Problem {
        Problem {
            type_: slug.map(type_uri).unwrap_or_else(|| "about:blank".into()),
            title: title.into(),
            status: status.as_u16(),
            detail: detail.into(),
            errors: None,
            job_state: None,
            retry_after: None,
        }
    }

    /// A bare HTTP status (unknown route, wrong method, body too large, timeout ...).
    pub fn http(status: StatusCode, detail: impl Into<String>) -> Problem {
        Problem::new(
            status,
            None,
            status.canonical_reason().unwrap_or("Error"),
            detail,
        )
    }

    pub fn bad_request(detail: impl Into<String>) -> Problem {
        Problem::new(
            StatusCode::BAD_REQUEST,
            Some("bad-request"),
            "Bad request",
            detail,
        )
    }

    pub fn not_found(detail: impl Into<String>) -> Problem {
        Problem::new(
            StatusCode::NOT_FOUND,
            Some("not-found"),
            "Not found",
            detail,
        )
    }

    pub fn conflict(detail: impl Into<String>, state: Option<&str>) -> Problem {
        let mut p = Problem::new(
            StatusCode::CONFLICT,
            Some("invalid-state"),
            "Not possible in the job's current state",
            detail,
        );
        p.job_state = state.map(String::from);
        p
    }

    pub fn unsupported_media(detail: impl Into<String>) -> Problem {
        Problem::new(
            StatusCode::UNSUPPORTED_MEDIA_TYPE,
            Some("unsupported-media-type"),
            "Unsupported media type",
            detail,
        )
    }

    /// A 422 listing the problems, at most [`MAX_LISTED_PROBLEMS`] of them (the detail
    /// says how many there were), so a request with 100 000 bad items cannot make a
    /// megabyte answer.
    pub fn validation(mut errors: Vec<FieldProblem>) -> Problem {
        let total = errors.len();
        let detail = if total == 1 {
            format!("{}: {}", errors[0].path, errors[0].message)
        } else if total > MAX_LISTED_PROBLEMS {
            errors.truncate(MAX_LISTED_PROBLEMS);
            format!("{total} problems in the request; errors lists the first {MAX_LISTED_PROBLEMS}")
        } else {
            format!("{total} problems in the request; see errors")
        };
        let mut p = Problem::new(
            StatusCode::UNPROCESSABLE_ENTITY,
            Some("validation"),
            "Invalid request",
            detail,
        );
        p.errors = Some(errors);
        p
    }

    pub fn field(path: &str, message: impl Into<String>) -> Problem {
        Problem::validation(vec![FieldProblem {
            path: path.into(),
            message: message.into(),
        }])
    }

    /// Scene validation errors, their paths prefixed (e.g. with `scene.`).
    pub fn scene_invalid(prefix: &str, e: &ValidationErrors) -> Problem {
        Problem::validation(
            e.0.iter()
                .map(|f: &FieldError| FieldProblem {
                    path: join_path(prefix, &f.path),
                    message: f.message.clone(),
                })
                .collect(),
        )
    }

    pub fn internal(detail: impl Into<String>) -> Problem {
        Problem::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            Some("internal"),
            "Internal error",
            detail,
        )
    }

    pub fn unavailable(detail: impl Into<String>) -> Problem {
        Problem::new(
            StatusCode::SERVICE_UNAVAILABLE,
            Some("unavailable"),
            "Service unavailable",
            detail,
        )
    }

    /// 429 for a queue (or a tenant's share of it) that is full, retried after 5 s.
    fn queue_full(slug: &'static str, title: &'static str, detail: String) -> Problem {
        let mut p = Problem::new(StatusCode::TOO_MANY_REQUESTS, Some(slug), title, detail);
        p.retry_after = Some(5);
        p
    }

    /// 503 while the database cannot be reached: a client should retry (the pool
    /// reconnects by itself once the database is back).
    pub fn database_unreachable(e: &StoreError) -> Problem {
        let mut p = Problem::unavailable(format!(
            "the database is not reachable ({e}); retry shortly"
        ));
        p.retry_after = Some(DATABASE_RETRY_AFTER);
        p
    }

    pub fn status(&self) -> StatusCode {
        StatusCode::from_u16(self.status).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR)
    }
}

/// Most problems a 422 lists.
pub const MAX_LISTED_PROBLEMS: usize = 100;

pub fn join_path(prefix: &str, path: &str) -> String {
    // serde_path_to_error says "." and the scene's serde errors "$" for the root.
    let path = if path == "$" || path == "." { "" } else { path };
    match (prefix.is_empty(), path.is_empty()) {
        (true, true) => "$".into(),
        (true, false) => path.into(),
        (false, true) => prefix.into(),
        (false, false) if path.starts_with('[') => format!("{prefix}{path}"),
        (false, false) => format!("{prefix}.{path}"),
    }
}

impl IntoResponse for Problem {
    fn into_response(self) -> Response {
        let status = self.status();
        let retry = self.retry_after;
        let body = serde_json::to_vec(&self).unwrap_or_default();
        let mut res = Response::new(Body::from(body));
        *res.status_mut() = status;
        res.headers_mut()
            .insert(header::CONTENT_TYPE, HeaderValue::from_static(PROBLEM_JSON));
        if let Some(s) = retry {
            res.headers_mut()
                .insert(header::RETRY_AFTER, HeaderValue::from(s));
        }
        res
    }
}

impl From<StoreError> for Problem {
    fn from(e: StoreError) -> Problem {
        match e {
            StoreError::NotFound(id) => Problem::not_found(format!("no job with id {id}")),
            StoreError::StudyNotFound(id) => Problem::not_found(format!("no study with id {id}")),
            StoreError::StudyConflict { id, message } => {
                Problem::conflict(format!("study {id}: {message}"), None)
            }
            StoreError::Conflict { id, state, message } => Problem::conflict(
                format!("job {id} is {state}: {message}"),
                Some(state.as_str()),
            ),
            StoreError::QueueFull(n) => Problem::queue_full(
                "queue-full",
                "Queue full",
                format!("{n} jobs are waiting; retry later"),
            ),
            StoreError::TenantQueueFull(n) => Problem::queue_full(
                "tenant-queue-full",
                "Queue share full",
                format!("your token has {n} jobs queued, its share of the queue (--tenant-max-queued); retry when some have started"),
            ),
            StoreError::IdempotencyMismatch(id) => Problem::new(
                StatusCode::UNPROCESSABLE_ENTITY,
                Some("idempotency-key-reused"),
                "Idempotency-Key reused",
                format!("this Idempotency-Key was used for a different request (job {id})"),
            ),
            e @ StoreError::LeaseLost => Problem::internal(e.to_string()),
            e if e.is_unreachable() => {
                tracing::warn!(error = %e, "database unreachable");
                Problem::database_unreachable(&e)
            }
            e @ (StoreError::Db(_) | StoreError::Migrate(_) | StoreError::Url(_)) => {
                tracing::error!(error = %e, "store error");
                Problem::internal("database error")
            }
        }
    }
}

pub type ApiResult<T> = Result<T, Problem>;

/// `Retry-After` (s) of a 503 for an unreachable database: about a restart's time.
pub const DATABASE_RETRY_AFTER: u64 = 2;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_problem_list_is_cut_and_says_so() {
        let many = (0..100_000)
            .map(|i| FieldProblem {
                path: format!("faults[{i}].width"),
                message: "must be > 0 m".into(),
            })
            .collect();
        let p = Problem::validation(many);
        assert_eq!(p.errors.as_ref().unwrap().len(), MAX_LISTED_PROBLEMS);
        assert!(
            p.detail.contains("100000 problems") && p.detail.contains("first 100"),
            "{}",
            p.detail
        );
    }
}
