//! Operational endpoints: health, readiness, metrics, the OpenAPI document, 404 fallback.

use super::openapi::responses::Unavailable;
use super::problem::{ApiResult, Problem, DATABASE_RETRY_AFTER};
use super::state::AppState;
use super::views::Status;
use crate::store::JobState;
use axum::extract::State;
use axum::http::{header, Uri};
use axum::response::{IntoResponse, Response};
use axum::Json;
use std::sync::atomic::Ordering;

/// Liveness
#[utoipa::path(
    get,
    path = "/healthz",
    tag = "operations",
    operation_id = "healthz",
    responses((status = 200, description = "The process serves requests.", body = Status))
)]
pub async fn healthz() -> Response {
    Json(Status {
        status: "ok".into(),
    })
    .into_response()
}

/// Longest wait of `/readyz` for the database's answer.
const READY_PING_TIMEOUT: std::time::Duration = std::time::Duration::from_millis(1500);

/// Readiness (database reachable, not shutting down)
#[utoipa::path(
    get,
    path = "/readyz",
    tag = "operations",
    operation_id = "readyz",
    responses(
        (status = 200, description = "Ready.", body = Status),
        (status = 503, response = Unavailable),
    )
)]
pub async fn readyz(State(state): State<AppState>) -> ApiResult<Response> {
    if !state.ready.load(Ordering::SeqCst) {
        return Err(Problem::unavailable("shutting down"));
    }
    // the watch answers at once while the database is known to be away; a ping of its
    // own is bounded too, for the moments before the watch sees it
    let ping = tokio::time::timeout(READY_PING_TIMEOUT, state.store.ping()).await;
    let why = match ping {
        Ok(Ok(())) => None,
        Ok(Err(e)) => Some(format!("database not reachable: {e}")),
        Err(_) => Some(format!(
            "the database did not answer within {READY_PING_TIMEOUT:?}"
        )),
    };
    if let Some(why) = why {
        let mut p = Problem::unavailable(why);
        p.retry_after = Some(DATABASE_RETRY_AFTER);
        return Err(p);
    }
    Ok(Json(Status {
        status: "ready".into(),
    })
    .into_response())
}

/// Prometheus metrics (queue depth, jobs by state, job durations, HTTP latencies)
#[utoipa::path(
    get,
    path = "/metrics",
    tag = "operations",
    operation_id = "metrics",
    responses((status = 200, description = "Prometheus text exposition format 0.0.4.", body = String, content_type = "text/plain"))
)]
pub async fn metrics(State(state): State<AppState>) -> ApiResult<Response> {
    let counts = state.store.counts().await?;
    let by_state: Vec<(&str, i64)> = JobState::ALL
        .iter()
        .map(|s| (s.as_str(), counts.get(*s)))
        .collect();
    let stored = state.store.stored_bytes().await?;
    let text = state
        .metrics
        .render(&by_state, stored, state.config.worker.worker_count());
    Ok((
        [(
            header::CONTENT_TYPE,
            "text/plain; version=0.0.4; charset=utf-8",
        )],
        text,
    )
        .into_response())
}

/// This document
#[utoipa::path(
    get,
    path = "/openapi.yaml",
    tag = "operations",
    operation_id = "openapi",
    responses((status = 200, description = "OpenAPI 3.1 document.", body = Object, content_type = "application/yaml"))
)]
pub async fn openapi(State(state): State<AppState>) -> Response {
    (
        [(header::CONTENT_TYPE, "application/yaml")],
        state.openapi_yaml,
    )
        .into_response()
}

pub async fn no_route(uri: Uri) -> Problem {
    Problem::not_found(format!("no resource at {}", uri.path()))
}
