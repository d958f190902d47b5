//! `GET /v1/simulations/{id}/recording?format=wav|csv|mat`: a finished run as a measured
//! recording, its channels with the shaft angle (`shaft_angle`, rad) and a
//! once-per-revolution tachometer (`tachometer`), so it can be analysed, shared or
//! plotted with a lab's own tools, or uploaded back as a measured signal.

use super::caller::Caller;
use super::extract::QueryParams;
use super::job_resource::succeeded;
use super::openapi::params::{JobId, RecordingExportQuery};
use super::openapi::responses::{BadRequest, Conflict, NotFound};
use super::problem::{ApiResult, Problem};
use super::results::record;
use super::simulations::load_channel;
use super::state::AppState;
use crate::jobs::artifacts::SHAFT_ANGLE_ARTIFACT;
use crate::jobs::record::SimulationRecord;
use crate::store::blob::decode_f32le;
use crate::store::JobKind;
use axum::extract::{Path, RawQuery, State};
use axum::http::header;
use axum::response::{IntoResponse, Response};
use bearing_core::run_recording::export_with_angle;
use bearing_core::signal::recording::{ExportChannel, ExportFormat};

/// A finished run as a recording file
///
/// Every channel the run recorded, then its shaft angle and tachometer pulses, as a
/// 32-bit float WAV (channels in the result's order, then `shaft_angle` and
/// `tachometer`; WAV keeps no names), a CSV with a `time [s]` column and a named header,
/// or a level-5 MAT-file with one variable per channel and `fs` (Hz).
#[utoipa::path(
    get,
    path = "/v1/simulations/{id}/recording",
    tag = "simulations",
    operation_id = "getSimulationRecording",
    params(JobId, RecordingExportQuery),
    responses(
        (status = 200, description = "The recording file.", content(
            (Vec<u8> = "audio/wav"),
            (String = "text/csv"),
            (Vec<u8> = "application/x-matlab-data")
        )),
        (status = 400, response = BadRequest),
        (status = 404, response = NotFound),
        (status = 409, response = Conflict),
    )
)]
pub async fn recording(
    State(state): State<AppState>,
    caller: Caller,
    Path(id): Path<String>,
    RawQuery(q): RawQuery,
) -> ApiResult<Response> {
    let q = QueryParams::parse(q.as_deref())?;
    let format: ExportFormat = q.get("format")?.ok_or_else(|| {
        Problem::bad_request("query parameter 'format' is required: wav, csv or mat")
    })?;
    let job = succeeded(&state, &caller, JobKind::Simulation, &id).await?;
    let rec: SimulationRecord = record(&job)?;
    // every channel in memory at once: a few such exports at a time
    let _permit = state.large_transfer(caller.share_key()).await?;
    let mut data = Vec::with_capacity(rec.channels.len());
    for c in &rec.channels {
        data.push(load_channel(&state, &id, &c.name).await?.data);
    }
    let angle = state
        .store
        .get_artifact(&id, SHAFT_ANGLE_ARTIFACT)
        .await?
        .ok_or_else(|| {
            Problem::not_found(format!(
                "simulation {id} was run before runs kept their shaft angle; run it again to export it"
            ))
        })?;
    let radians = decode_f32le(&angle.data);
    let sample_rate = rec.sample_rate;
    let bytes = tokio::task::spawn_blocking(move || {
        let channels: Vec<ExportChannel> = rec
            .channels
            .iter()
            .zip(&data)
            .map(|(c, d)| ExportChannel {
                name: &c.name,
                unit: Some(&c.unit),
                samples: d,
            })
            .collect();
        export_with_angle(&channels, &radians, sample_rate, format)
    })
    .await
    .map_err(|e| Problem::internal(format!("export failed: {e}")))?
    .map_err(Problem::internal)?;
    let file = format!("attachment; filename=\"{id}.{}\"", format.extension());
    Ok((
        [
            (header::CONTENT_TYPE, format.media_type().to_string()),
            (header::CONTENT_DISPOSITION, file),
        ],
        bytes,
    )
        .into_response())
}
