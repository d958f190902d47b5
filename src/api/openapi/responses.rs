//! Problem responses shared by the operations (RFC 9457, `application/problem+json`).
//! The types exist for the document: each names its status' description and its body,
//! a [`Problem`] (handlers return `Problem` itself).
#![allow(dead_code)]

use crate::api::problem::Problem;
use utoipa::ToResponse;

/// Malformed JSON or query parameter.
#[derive(ToResponse)]
#[response(
    content_type = "application/problem+json",
    example = json!({
        "type": "urn:bearing-sim:problem:bad-request",
        "title": "Bad request",
        "status": 400,
        "detail": "query parameter 'limit' = 'x': invalid digit found in string"
    })
)]
pub struct BadRequest(Problem);

/// No such job (of this kind) or resource.
#[derive(ToResponse)]
#[response(
    content_type = "application/problem+json",
    example = json!({
        "type": "urn:bearing-sim:problem:not-found",
        "title": "Not found",
        "status": 404,
        "detail": "no job with id 42"
    })
)]
pub struct NotFound(Problem);

/// Not possible in the job's current state (e.g. the result of a running job, deleting a
/// queued job, cancelling a finished one).
#[derive(ToResponse)]
#[response(
    content_type = "application/problem+json",
    example = json!({
        "type": "urn:bearing-sim:problem:invalid-state",
        "title": "Not possible in the job's current state",
        "status": 409,
        "detail": "job 019a4f7e-3c1b-7d2a-9f10-2b6c8e4d5a71 is running; results exist only for succeeded jobs",
        "job_state": "running"
    })
)]
pub struct Conflict(Problem);

/// Body larger than the configured limit.
#[derive(ToResponse)]
#[response(content_type = "application/problem+json")]
pub struct TooLarge(Problem);

/// Wrong Content-Type.
#[derive(ToResponse)]
#[response(content_type = "application/problem+json")]
pub struct UnsupportedMediaType(Problem);

/// Invalid content: every field problem with its path; also an Idempotency-Key reused with
/// a different request (type `urn:bearing-sim:problem:idempotency-key-reused`), and a
/// solver or analysis that cannot run on valid input.
#[derive(ToResponse)]
#[response(
    content_type = "application/problem+json",
    example = json!({
        "type": "urn:bearing-sim:problem:validation",
        "title": "Invalid request",
        "status": 422,
        "detail": "2 problems in the request; see errors",
        "errors": [
            {"path": "scene.bearing.ball_diameter", "message": "must be > 0 m"},
            {"path": "scene.solver.duration", "message": "must be > 0 s"}
        ]
    })
)]
pub struct Invalid(Problem);

/// The queue is full.
#[derive(ToResponse)]
#[response(
    content_type = "application/problem+json",
    headers(("Retry-After" = u64, description = "Seconds to wait before retrying."))
)]
pub struct QueueFull(Problem);

/// The request took longer than the configured request timeout.
#[derive(ToResponse)]
#[response(content_type = "application/problem+json")]
pub struct RequestTimeout(Problem);

/// Not ready (shutting down, or the database is not reachable).
#[derive(ToResponse)]
#[response(content_type = "application/problem+json")]
pub struct Unavailable(Problem);

/// This service requires an API token (`Authorization: Bearer <token>`), and none or an
/// unknown one was sent.
#[derive(ToResponse)]
#[response(
    content_type = "application/problem+json",
    example = json!({
        "type": "urn:bearing-sim:problem:unauthorized",
        "title": "Unauthorized",
        "status": 401,
        "detail": "this service requires a token: send Authorization: Bearer <token>"
    })
)]
pub struct Unauthorized(Problem);
