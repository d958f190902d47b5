//! Middleware: problem+json for errors produced outside handlers, latency metrics.

use super::database_watch::DatabaseWatch;
use super::problem::{Problem, PROBLEM_JSON};
use super::state::AppState;
use axum::extract::{MatchedPath, Request, State};
use axum::http::{header, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use std::time::Instant;

/// While the database does not answer, a request that needs it gets 503 with
/// `Retry-After` at once, and one in flight when it goes away gets it then (instead of
/// hanging on a connection that will not answer until the request timeout).
pub async fn answer_without_database(
    State(state): State<AppState>,
    req: Request,
    next: Next,
) -> Response {
    if !DatabaseWatch::needed_by(req.uri().path()) {
        return next.run(req).await;
    }
    if !state.database.is_up() {
        return DatabaseWatch::unavailable().into_response();
    }
    tokio::select! {
        res = next.run(req) => res,
        () = state.database.went_away() => DatabaseWatch::unavailable().into_response(),
    }
}

/// Rewrites any error response that is not problem+json yet (axum's extractor
/// rejections, 405, 408 from the timeout, 413 from the body limit) into one, keeping
/// its status and headers such as `Allow`.
pub async fn problem_for_every_error(req: Request, next: Next) -> Response {
    let res = next.run(req).await;
    let status = res.status();
    if !(status.is_client_error() || status.is_server_error()) {
        return res;
    }
    let is_problem = res
        .headers()
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.starts_with(PROBLEM_JSON));
    if is_problem {
        return res;
    }
    let (parts, body) = res.into_parts();
    let text = axum::body::to_bytes(body, 16 * 1024)
        .await
        .map(|b| String::from_utf8_lossy(&b).trim().to_string())
        .unwrap_or_default();
    let detail = match status {
        StatusCode::METHOD_NOT_ALLOWED => {
            "method not allowed on this resource (the Allow header lists the allowed ones)".into()
        }
        StatusCode::REQUEST_TIMEOUT => {
            "the request took longer than the configured request timeout".into()
        }
        StatusCode::PAYLOAD_TOO_LARGE => format!(
            "request body too large{}",
            if text.is_empty() {
                String::new()
            } else {
                format!(": {text}")
            }
        ),
        _ if !text.is_empty() => text,
        _ => status.canonical_reason().unwrap_or("error").to_string(),
    };
    let mut out = Problem::http(status, detail).into_response();
    for (k, v) in parts.headers.iter() {
        if k != header::CONTENT_TYPE && k != header::CONTENT_LENGTH {
            out.headers_mut().insert(k.clone(), v.clone());
        }
    }
    out
}

/// Answers 413 at once when the declared `Content-Length` is over the body limit,
/// before a byte of the body is read (the body limit alone only trips after reading up
/// to it, so a client declaring 400 MB and sending 16 bytes held the request until the
/// timeout answered 408); and makes a large body wait for a large-transfer permit.
pub async fn bound_request_bodies(
    State(state): State<AppState>,
    req: Request,
    next: Next,
) -> Response {
    let limit = state.config.max_body_bytes;
    let declared = req
        .headers()
        .get(header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim().parse::<u64>().ok());
    if let Some(n) = declared.filter(|&n| n > limit as u64) {
        let mut res = Problem::http(
            StatusCode::PAYLOAD_TOO_LARGE,
            format!(
                "the declared Content-Length of {n} bytes is over the limit of {limit} bytes (--max-body-bytes)"
            ),
        )
        .into_response();
        // the unread body makes the connection unusable for a next request
        res.headers_mut().insert(
            header::CONNECTION,
            header::HeaderValue::from_static("close"),
        );
        return res;
    }
    // A large body (or one of unknown length) waits for a large-transfer permit before a
    // byte of it is read, and holds it until the answer is made: the bodies held in memory
    // at once stay bounded by --max-large-transfers, not by the connection count.
    // The wait for the slot and the whole request after it fit in the request timeout
    // (the wait used to come before it: a stalled flood made uploads take 89 s).
    let chunked = declared.is_none() && req.headers().contains_key(header::TRANSFER_ENCODING);
    if declared.is_some_and(|n| n > LARGE_BODY) || chunked {
        let deadline = state.config.request_deadline();
        let client = super::caller::share_key(&state, &req);
        let answered = tokio::time::timeout(deadline, async {
            let _permit = match state.large_transfer(&client).await {
                Ok(p) => p,
                Err(problem) => return problem.into_response(),
            };
            next.run(req).await
        })
        .await;
        return answered.unwrap_or_else(|_| {
            Problem::http(
                StatusCode::REQUEST_TIMEOUT,
                "the request took longer than the configured request timeout".to_string(),
            )
            .into_response()
        });
    }
    next.run(req).await
}

/// A request body above this many bytes is a large transfer.
const LARGE_BODY: u64 = 1024 * 1024;

pub async fn record_latency(State(state): State<AppState>, req: Request, next: Next) -> Response {
    let route = req
        .extensions()
        .get::<MatchedPath>()
        .map(|p| p.as_str().to_string())
        .unwrap_or_else(|| "unmatched".into());
    let method = req.method().as_str().to_string();
    let start = Instant::now();
    let res = next.run(req).await;
    state.metrics.observe_http(
        &method,
        &route,
        res.status().as_u16(),
        start.elapsed().as_secs_f64(),
    );
    res
}
