//! `/v1/simulations`: submit a scene, follow the job, read its result, signals and spectra.

use super::caller::Caller;
use super::extract::{as_object, parse_bounded, require_json, QueryParams};
use super::job_resource::{self, succeeded};
use super::openapi::params::{
    IdempotencyKey, IfNoneMatch, JobId, ListQuery, SignalsQuery, SpectraQuery, WaitQuery,
};
use super::openapi::responses::{
    BadRequest, Conflict, Invalid, NotFound, QueueFull, TooLarge, Unavailable, UnsupportedMediaType,
};
use super::problem::{ApiResult, Problem};
use super::results::{self, SimulationResult, SpectrumView};
use super::scene_input::resolve_scene;
use super::scene_input::SimulationRequest;
use super::state::AppState;
use super::submission::enqueue;
use super::views::{JobPage, JobView};
use crate::jobs::artifacts::channel_artifact_name;
use crate::store::blob::decode_f32le;
use crate::store::{ArtifactMeta, JobKind};
use axum::body::Bytes;
use axum::extract::{Path, RawQuery, State};
use axum::http::HeaderMap;
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde::Serialize;
use utoipa::ToSchema;

/// Default and largest number of points returned by `signals`.
const DEFAULT_POINTS: usize = 10_000;
const MAX_POINTS: usize = 200_000;

const KIND: JobKind = JobKind::Simulation;

/// A window of one sampled channel, decimated: point `k` is at `start_time + k dt`.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct SignalView {
    pub id: String,
    pub channel: String,
    /// SI unit of the samples, e.g. `m/s^2`.
    pub unit: String,
    /// Time of the first point, s.
    pub start_time: f64,
    /// Spacing of the points, s.
    pub dt: f64,
    /// Every k-th stored sample is returned.
    pub decimation: usize,
    /// Sample rate of the stored channel, Hz.
    pub source_sample_rate: f64,
    pub count: usize,
    pub data: Vec<f64>,
}

/// A stored channel's samples, decoded.
pub struct StoredChannel {
    pub data: Vec<f64>,
    /// Hz.
    pub sample_rate: f64,
    /// Time of sample 0, s.
    pub start_time: f64,
    pub unit: String,
}

/// Load a succeeded simulation's channel (404 if it has none of that name).
pub async fn load_channel(state: &AppState, id: &str, channel: &str) -> ApiResult<StoredChannel> {
    let Some(a) = state
        .store
        .get_artifact(id, &channel_artifact_name(channel))
        .await?
    else {
        return Err(Problem::not_found(format!(
            "simulation {id} has no channel '{channel}'"
        )));
    };
    let ArtifactMeta::Channel {
        sample_rate,
        start_time,
        unit,
        ..
    } = a.meta
    else {
        return Err(Problem::internal(format!(
            "artifact {} of simulation {id} is not a channel",
            a.name
        )));
    };
    Ok(StoredChannel {
        data: decode_f32le(&a.data),
        sample_rate,
        start_time,
        unit,
    })
}

/// Indices `first..last` of the samples with `from <= t <= to` (either bound optional) of a
/// channel whose sample `k` is at `t0 + k / fs`.
pub fn sample_window(
    t0: f64,
    fs: f64,
    n: usize,
    from: Option<f64>,
    to: Option<f64>,
) -> (usize, usize) {
    let first = from
        .map(|f| ((f - t0) * fs).ceil().max(0.0) as usize)
        .unwrap_or(0)
        .min(n);
    let last = to
        .map(|t| (((t - t0) * fs).floor() + 1.0).max(0.0) as usize)
        .unwrap_or(n)
        .min(n)
        .max(first);
    (first, last)
}

/// Queue a simulation
///
/// Either `{"scene": {...}}` or `{"preset": "h7005c", "fault_case": "compound",
/// "overrides": {...}}` where `overrides` is a JSON merge patch (RFC 7396) applied to the
/// preset scene (a lubricant model named anew, e.g. `{"lubricant": {"traction": {"model":
/// "abcd"}}}` for the paper's curve, replaces the preset's whole rather than merging into
/// it). With an
/// `Idempotency-Key`, repeating the same request returns the original job (200); the same
/// key with a different request is a 422.
#[utoipa::path(
    post,
    path = "/v1/simulations",
    tag = "simulations",
    operation_id = "submitSimulation",
    params(IdempotencyKey),
    request_body(
        content = SimulationRequest,
        examples(("preset" = (
            summary = "H7005C with both defects, 20 ms",
            value = json!({"preset": "h7005c", "fault_case": "compound", "overrides": {"solver": {"duration": 0.02}}})
        )))
    ),
    responses(
        (status = 202, description = "Queued.", body = JobView, headers(
            ("Location" = String, description = "Path of the job."),
            ("ETag" = String, description = "Version of the job; send it back in If-None-Match.")
        ), links(
                ("getSimulation" = (operation_id = "getSimulation", parameters(("id" = "$response.body#/id")))),
                ("cancelSimulation" = (operation_id = "cancelSimulation", parameters(("id" = "$response.body#/id")))),
                ("getSimulationResult" = (operation_id = "getSimulationResult", parameters(("id" = "$response.body#/id")))),
                ("getSimulationSpectra" = (operation_id = "getSimulationSpectra", parameters(("id" = "$response.body#/id")))),
                ("getSimulationSignals" = (operation_id = "getSimulationSignals", parameters(("id" = "$response.body#/id")))),
                ("deleteSimulation" = (operation_id = "deleteSimulation", parameters(("id" = "$response.body#/id"))))
            )),
        (status = 200, description = "Idempotent replay; the job created by the first request.", body = JobView, headers(
            ("Location" = String, description = "Path of the job."),
            ("ETag" = String, description = "Version of the job; send it back in If-None-Match.")
        )),
        (status = 400, response = BadRequest),
        (status = 413, response = TooLarge),
        (status = 415, response = UnsupportedMediaType),
        (status = 422, response = Invalid),
        (status = 429, response = QueueFull),
        (status = 503, response = Unavailable),
    )
)]
pub async fn submit(
    State(state): State<AppState>,
    caller: Caller,
    headers: HeaderMap,
    body: Bytes,
) -> ApiResult<Response> {
    require_json(&headers)?;
    let mut body = as_object(parse_bounded(&body)?)?;
    let scene = resolve_scene(&mut body, &[])?;
    let over = super::budget::over_budget(&scene, &state.config, "scene");
    if !over.is_empty() {
        return Err(Problem::validation(over));
    }
    // Refuse now what could never start (no equilibrium at t = 0), rather than fail the job
    // later: one quasi-static solve, off the async threads.
    let scene = tokio::task::spawn_blocking(move || {
        bearing_core::simulation::check_start(&scene).map(|()| scene)
    })
    .await
    .map_err(|e| Problem::internal(format!("start check failed: {e}")))?
    .map_err(|e| Problem::scene_invalid("scene", &e))?;
    let input = serde_json::to_value(&scene).map_err(|e| Problem::internal(e.to_string()))?;
    enqueue(
        &state,
        &caller,
        &headers,
        KIND,
        scene.name.clone(),
        input,
        None,
    )
    .await
}

/// One sampled channel, windowed and decimated
#[utoipa::path(
    get,
    path = "/v1/simulations/{id}/signals",
    tag = "simulations",
    operation_id = "getSimulationSignals",
    params(JobId, SignalsQuery),
    responses(
        (status = 200, description = "The samples.", body = SignalView),
        (status = 400, response = BadRequest),
        (status = 404, response = NotFound),
        (status = 409, response = Conflict),
        (status = 422, response = Invalid),
    )
)]
pub async fn signals(
    State(state): State<AppState>,
    caller: Caller,
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
    if let (Some(a), Some(b)) = (from, to) {
        if a > b {
            // an empty window is never what was meant: say so rather than answer nothing
            return Err(Problem::field(
                "to",
                format!("must not be before from ({b} s < {a} s)"),
            ));
        }
    }
    let max_points = q.get::<usize>("max_points")?.unwrap_or(DEFAULT_POINTS);
    if !(1..=MAX_POINTS).contains(&max_points) {
        return Err(Problem::bad_request(format!(
            "query parameter 'max_points' must be in 1..={MAX_POINTS}"
        )));
    }
    succeeded(&state, &caller, KIND, &id).await?;
    // a channel is up to 20 MB in memory while it is decimated: a few at a time
    let _permit = state.large_transfer(caller.share_key()).await?;
    let StoredChannel {
        data,
        sample_rate: fs,
        start_time: t0,
        unit,
    } = load_channel(&state, &id, &channel).await?;
    let (first, last) = sample_window(t0, fs, data.len(), from, to);
    let len = last - first;
    let step = len.div_ceil(max_points).max(1);
    let values: Vec<f64> = data[first..last].iter().step_by(step).copied().collect();
    Ok(Json(SignalView {
        id,
        channel,
        unit,
        start_time: t0 + first as f64 / fs,
        dt: step as f64 / fs,
        decimation: step,
        source_sample_rate: fs,
        count: values.len(),
        data: values,
    })
    .into_response())
}

/// State, progress, timestamps, solver statistics and error of a simulation
///
/// Send the last `ETag` in `If-None-Match` to get a bodiless 304 while nothing changed.
/// With `wait` (s), an unchanged job is held until it changes or `wait` passes (long poll;
/// exempt from the request timeout; `If-None-Match: *` is answered at once).
#[utoipa::path(
    get,
    path = "/v1/simulations/{id}",
    tag = "simulations",
    operation_id = "getSimulation",
    params(JobId, IfNoneMatch, WaitQuery),
    responses(
        (status = 200, description = "The job.", body = JobView, headers(
            ("ETag" = String, description = "Version of the job; send it back in If-None-Match."),
            ("Location" = String, description = "Path of the job.")
        )),
        (status = 304, description = "Unchanged since the ETag given.", headers(
            ("ETag" = String, description = "Version of the job.")
        )),
        (status = 400, response = BadRequest),
        (status = 404, response = NotFound),
    )
)]
pub async fn get(
    State(s): State<AppState>,
    caller: Caller,
    Path(id): Path<String>,
    headers: HeaderMap,
    RawQuery(q): RawQuery,
) -> ApiResult<Response> {
    job_resource::get_job(s, &caller, KIND, id, headers, q).await
}

/// List simulations, newest first
#[utoipa::path(
    get,
    path = "/v1/simulations",
    tag = "simulations",
    operation_id = "listSimulations",
    params(ListQuery),
    responses(
        (status = 200, description = "One page.", body = JobPage),
        (status = 400, response = BadRequest),
    )
)]
pub async fn list(
    State(s): State<AppState>,
    caller: Caller,
    RawQuery(q): RawQuery,
) -> ApiResult<Response> {
    job_resource::list(s, &caller, KIND, q).await
}

/// Cancel a queued (at once) or running (within a second) simulation
#[utoipa::path(
    post,
    path = "/v1/simulations/{id}/cancel",
    tag = "simulations",
    operation_id = "cancelSimulation",
    params(JobId),
    responses(
        (status = 202, description = "Cancelled (queued job) or cancel requested (running job).", body = JobView, headers(
            ("ETag" = String, description = "Version of the job."),
            ("Location" = String, description = "Path of the job.")
        )),
        (status = 404, response = NotFound),
        (status = 409, response = Conflict),
    )
)]
pub async fn cancel(
    State(s): State<AppState>,
    caller: Caller,
    Path(id): Path<String>,
) -> ApiResult<Response> {
    job_resource::cancel(s, &caller, KIND, id).await
}

/// Delete a finished simulation and its outputs
#[utoipa::path(
    delete,
    path = "/v1/simulations/{id}",
    tag = "simulations",
    operation_id = "deleteSimulation",
    params(JobId),
    responses(
        (status = 204, description = "Deleted."),
        (status = 404, response = NotFound),
        (status = 409, response = Conflict),
    )
)]
pub async fn delete(
    State(s): State<AppState>,
    caller: Caller,
    Path(id): Path<String>,
) -> ApiResult<Response> {
    job_resource::delete(s, &caller, KIND, id).await
}

/// Result summary of a succeeded simulation
///
/// Cage speed and slip, contact statistics, channels recorded, and the analysis of the
/// outer-ring acceleration (theory, identifications, per-level kurtosis).
#[utoipa::path(
    get,
    path = "/v1/simulations/{id}/result",
    tag = "simulations",
    operation_id = "getSimulationResult",
    params(JobId),
    responses(
        (status = 200, description = "The summary.", body = SimulationResult),
        (status = 404, response = NotFound),
        (status = 409, response = Conflict),
    )
)]
pub async fn result(
    State(s): State<AppState>,
    caller: Caller,
    Path(id): Path<String>,
) -> ApiResult<Response> {
    results::result(s, &caller, KIND, id).await
}

/// Envelope spectrum with characteristic-frequency markers and identified peaks
#[utoipa::path(
    get,
    path = "/v1/simulations/{id}/spectra",
    tag = "simulations",
    operation_id = "getSimulationSpectra",
    params(JobId, SpectraQuery),
    responses(
        (status = 200, description = "The spectrum; with `Accept: text/csv`, its bins as `frequency_hz,amplitude` rows.", content(
            (SpectrumView = "application/json"),
            (String = "text/csv")
        )),
        (status = 400, response = BadRequest),
        (status = 404, response = NotFound),
        (status = 409, response = Conflict),
        (status = 422, response = Invalid),
    )
)]
pub async fn spectra(
    State(s): State<AppState>,
    caller: Caller,
    Path(id): Path<String>,
    RawQuery(q): RawQuery,
    headers: HeaderMap,
) -> ApiResult<Response> {
    results::spectra(s, &caller, KIND, id, q, &headers).await
}
