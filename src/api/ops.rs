//! Operational endpoints: health, readiness, metrics, the OpenAPI document, 404 fallback.

use super::problem::{ApiResult, Problem};
use super::state::AppState;
use crate::store::JobState;
use axum::extract::State;
use axum::http::{header, Uri};
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde_json::json;
use std::sync::atomic::Ordering;

pub const OPENAPI_YAML: &str = include_str!("../../openapi.yaml");

pub async fn healthz() -> Response {
    Json(json!({"status": "ok"})).into_response()
}

pub async fn readyz(State(state): State<AppState>) -> ApiResult<Response> {
    if !state.ready.load(Ordering::SeqCst) {
        return Err(Problem::unavailable("shutting down"));
    }
    state
        .store
        .ping()
        .await
        .map_err(|e| Problem::unavailable(format!("database not reachable: {e}")))?;
    Ok(Json(json!({"status": "ready"})).into_response())
}

pub async fn metrics(State(state): State<AppState>) -> ApiResult<Response> {
    let counts = state.store.counts().await?;
    let by_state: Vec<(&str, i64)> = JobState::ALL
        .iter()
        .map(|s| (s.as_str(), counts.get(*s)))
        .collect();
    let text = state.metrics.render(&by_state, state.config.worker_count());
    Ok((
        [(
            header::CONTENT_TYPE,
            "text/plain; version=0.0.4; charset=utf-8",
        )],
        text,
    )
        .into_response())
}

pub async fn openapi() -> Response {
    ([(header::CONTENT_TYPE, "application/yaml")], OPENAPI_YAML).into_response()
}

pub async fn no_route(uri: Uri) -> Problem {
    Problem::not_found(format!("no resource at {}", uri.path()))
}
