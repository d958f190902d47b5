//! `POST /v1/recordings/inspect`: the channels of a recording file, as `bearing-sim
//! inspect` lists them, so a client (the page) can offer a channel before it uploads the
//! file for analysis.

use super::extract::QueryParams;
use super::openapi::params::InspectQuery;
use super::openapi::responses::{BadRequest, Invalid, TooLarge};
use super::problem::{ApiResult, Problem};
use super::recording_upload::read_upload;
use super::state::AppState;
use axum::body::Bytes;
use axum::extract::{RawQuery, State};
use axum::Json;
use bearing_core::signal::recording::Listing;

/// Preview points a listing may carry per channel.
const MAX_PREVIEW_POINTS: usize = 10_000;

/// List a recording's channels
///
/// The body is the file (MATLAB v5 .mat, WAV, CSV/TSV, raw f32le or a JSON array); its
/// format comes from `format`, or from the extension of `filename`. Answers each channel's
/// name, index, length, unit and duration, the sample rate and shaft speed where the file
/// carries them, and what is not a channel, with the reason; with `preview=N`, up to N
/// samples of each channel (every k-th) to plot it.
#[utoipa::path(
    post,
    path = "/v1/recordings/inspect",
    tag = "analyses",
    operation_id = "inspectRecording",
    params(InspectQuery),
    request_body(content = Vec<u8>, content_type = "application/octet-stream", description = "The recording file."),
    responses(
        (status = 200, description = "The file's channels.", body = Listing),
        (status = 400, response = BadRequest),
        (status = 413, response = TooLarge),
        (status = 422, response = Invalid),
    )
)]
pub async fn inspect(
    State(state): State<AppState>,
    RawQuery(q): RawQuery,
    body: Bytes,
) -> ApiResult<Json<Listing>> {
    let q = QueryParams::parse(q.as_deref())?;
    let points = q.get::<usize>("preview")?.unwrap_or(0);
    if points > MAX_PREVIEW_POINTS {
        return Err(Problem::field(
            "preview",
            format!("at most {MAX_PREVIEW_POINTS} points (got {points})"),
        ));
    }
    let config = state.config.clone();
    // parsing a large file is CPU work: off the async threads
    let (_, rec) = tokio::task::spawn_blocking(move || read_upload(&q, &body, &config))
        .await
        .map_err(|e| Problem::internal(format!("reading the file failed: {e}")))??;
    Ok(Json(rec.listing_with_preview(points)))
}
