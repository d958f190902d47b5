//! `/v1/simulations`: submit a scene, follow the job, read its result, signals and spectra.

use super::extract::{as_object, parse_value, require_json, QueryParams};
use super::job_resource::{self, succeeded};
use super::problem::{ApiResult, Problem};
use super::results;
use super::scene_input::resolve_scene;
use super::state::AppState;
use super::submission::enqueue;
use crate::jobs::artifacts::channel_artifact_name;
use crate::store::blob::decode_f32le;
use crate::store::{ArtifactMeta, JobKind};
use axum::body::Bytes;
use axum::extract::{Path, RawQuery, State};
use axum::http::HeaderMap;
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde_json::json;

/// Default and largest number of points returned by `signals`.
const DEFAULT_POINTS: usize = 10_000;
const MAX_POINTS: usize = 1_000_000;

const KIND: JobKind = JobKind::Simulation;

pub async fn submit(
    State(state): State<AppState>,
    headers: HeaderMap,
    body: Bytes,
) -> ApiResult<Response> {
    require_json(&headers)?;
    let mut body = as_object(parse_value(&body)?)?;
    let scene = resolve_scene(&mut body, &[])?;
    let input = serde_json::to_value(&scene).map_err(|e| Problem::internal(e.to_string()))?;
    enqueue(&state, &headers, KIND, scene.name.clone(), input, None).await
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
    succeeded(&state, KIND, &id).await?;
    let Some(a) = state
        .store
        .get_artifact(&id, &channel_artifact_name(&channel))
        .await?
    else {
        return Err(Problem::not_found(format!(
            "simulation {id} has no channel '{channel}'"
        )));
    };
    let ArtifactMeta::Channel {
        sample_rate: fs,
        start_time: t0,
        unit,
        ..
    } = a.meta
    else {
        return Err(Problem::internal(format!(
            "artifact {} of simulation {id} is not a channel",
            a.name
        )));
    };
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

pub async fn get(
    State(s): State<AppState>,
    Path(id): Path<String>,
    headers: HeaderMap,
    RawQuery(q): RawQuery,
) -> ApiResult<Response> {
    job_resource::get_job(s, KIND, id, headers, q).await
}

pub async fn list(State(s): State<AppState>, RawQuery(q): RawQuery) -> ApiResult<Response> {
    job_resource::list(s, KIND, q).await
}

pub async fn cancel(State(s): State<AppState>, Path(id): Path<String>) -> ApiResult<Response> {
    job_resource::cancel(s, KIND, id).await
}

pub async fn delete(State(s): State<AppState>, Path(id): Path<String>) -> ApiResult<Response> {
    job_resource::delete(s, KIND, id).await
}

pub async fn result(State(s): State<AppState>, Path(id): Path<String>) -> ApiResult<Response> {
    results::result(s, KIND, id).await
}

pub async fn spectra(
    State(s): State<AppState>,
    Path(id): Path<String>,
    RawQuery(q): RawQuery,
) -> ApiResult<Response> {
    results::spectra(s, KIND, id, q).await
}
