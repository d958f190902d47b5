//! Submitting simulations and reading their sampled channels.

use super::extract::{as_object, parse_value, require_json, QueryParams};
use super::jobs::{enqueue, succeeded};
use super::problem::{ApiResult, Problem};
use super::scene_input::resolve_scene;
use super::AppState;
use crate::store::blob::decode_f32le;
use crate::store::JobKind;
use axum::body::Bytes;
use axum::extract::{Path, RawQuery, State};
use axum::http::HeaderMap;
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde_json::{json, Value};

/// Default and largest number of points returned by `signals`.
const DEFAULT_POINTS: usize = 10_000;
const MAX_POINTS: usize = 1_000_000;

pub async fn submit(
    State(state): State<AppState>,
    headers: HeaderMap,
    body: Bytes,
) -> ApiResult<Response> {
    require_json(&headers)?;
    let mut body = as_object(parse_value(&body)?)?;
    let scene = resolve_scene(&mut body, &[])?;
    let input = serde_json::to_value(&scene).map_err(|e| Problem::internal(e.to_string()))?;
    enqueue(
        &state,
        &headers,
        JobKind::Simulation,
        scene.name.clone(),
        input,
        None,
    )
    .await
}

pub async fn signals(
    State(state): State<AppState>,
    Path(id): Path<String>,
    RawQuery(q): RawQuery,
) -> ApiResult<Response> {
    let q = QueryParams::parse(q.as_deref())?;
    let channel = q
        .str("channel")
        .ok_or_else(|| {
            Problem::bad_request(
                "query parameter 'channel' is required (see the result's channels list)",
            )
        })?
        .to_string();
    let from = q.f64("from")?;
    let to = q.f64("to")?;
    let max_points = q.get::<usize>("max_points")?.unwrap_or(DEFAULT_POINTS);
    if !(1..=MAX_POINTS).contains(&max_points) {
        return Err(Problem::bad_request(format!(
            "query parameter 'max_points' must be in 1..={MAX_POINTS}"
        )));
    }
    succeeded(&state, JobKind::Simulation, &id).await?;
    let Some(a) = state
        .store
        .get_artifact(&id, &format!("channel:{channel}"))
        .await?
    else {
        return Err(Problem::not_found(format!(
            "simulation {id} has no channel '{channel}'"
        )));
    };
    let fs = a
        .meta
        .get("sample_rate")
        .and_then(Value::as_f64)
        .unwrap_or(1.0);
    let t0 = a
        .meta
        .get("start_time")
        .and_then(Value::as_f64)
        .unwrap_or(0.0);
    let unit = a.meta.get("unit").cloned().unwrap_or(Value::Null);
    let data = decode_f32le(&a.data);
    let n = data.len();
    // Sample k is at t0 + k / fs; the window keeps samples with from <= t <= to.
    let first = from
        .map(|f| ((f - t0) * fs).ceil().max(0.0) as usize)
        .unwrap_or(0)
        .min(n);
    let last = to
        .map(|t| (((t - t0) * fs).floor() + 1.0).max(0.0) as usize)
        .unwrap_or(n)
        .min(n)
        .max(first);
    let len = last - first;
    let step = len.div_ceil(max_points).max(1);
    let values: Vec<f64> = data[first..last].iter().step_by(step).copied().collect();
    Ok(Json(json!({
        "id": id,
        "channel": channel,
        "unit": unit,
        "start_time": t0 + first as f64 / fs,
        "dt": step as f64 / fs,
        "decimation": step,
        "source_sample_rate": fs,
        "count": values.len(),
        "data": values,
    }))
    .into_response())
}
