//! `POST /v1/analyses`: the diagnosis pipeline on a measured signal, sent as JSON samples,
//! as a raw little-endian f32 body with query parameters, or as a recording file (`.mat`,
//! WAV, CSV, ...) with `filename=`/`format=` ([`super::recording_upload`]). Small signals are answered
//! directly (200); large ones, or `mode=async`, are queued as jobs (202).

use super::caller::Caller;
use super::direct::run_direct;
use super::extract::{as_object, content_type, from_value, parse_value, QueryParams};
use super::job_resource;
use super::openapi::params::{
    IdempotencyKey, IfNoneMatch, JobId, ListQuery, RawAnalysisQuery, RawSamples, SpectraQuery,
    WaitQuery,
};
use super::openapi::responses::{
    BadRequest, Conflict, Invalid, NotFound, QueueFull, RequestTimeout, TooLarge, Unavailable,
    UnsupportedMediaType,
};
use super::problem::{ApiResult, FieldProblem, Problem};
use super::recording_upload::{is_upload, read_upload, uploaded_signal};
use super::results::{self, AnalysisResult, SpectrumView};
use super::state::AppState;
use super::submission::enqueue;
use super::views::{JobPage, JobView};
use crate::jobs::{run_analysis, AnalysisInput};
use crate::store::blob::encode_f64le;
use crate::store::JobKind;
use axum::body::Bytes;
use axum::extract::{Path, RawQuery, State};
use axum::http::{HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use bearing_core::signal::analysis::{
    check_options, AnalysisError, AnalysisOptions, AnalysisReport, Spectrum,
};
use bearing_core::signal::frequencies::{
    kinematic_preset, kinematic_preset_names, KinematicGeometry,
};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

const KIND: JobKind = JobKind::Analysis;

/// The JSON form of a request: give `preset` or `geometry`, and `shaft_hz` or `shaft_rpm`.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(example = json!({"samples": [0.0, 0.1, -0.2, 0.05], "sample_rate": 12000, "preset": "cwru6205", "shaft_rpm": 1797}))]
pub struct AnalysisRequest {
    /// The signal, in any unit (spectra come out in it).
    samples: Vec<f64>,
    /// Hz.
    #[schema(exclusive_minimum = 0.0)]
    sample_rate: f64,
    /// A kinematic bearing preset (`cwru6205`, `h7005c`).
    #[serde(default)]
    preset: Option<String>,
    #[serde(default)]
    geometry: Option<KinematicGeometry>,
    /// Shaft frequency, Hz.
    #[serde(default)]
    #[schema(exclusive_minimum = 0.0)]
    shaft_hz: Option<f64>,
    /// Shaft speed, rev/min.
    #[serde(default)]
    #[schema(exclusive_minimum = 0.0)]
    shaft_rpm: Option<f64>,
    /// Missing options take their defaults.
    #[serde(default)]
    options: Option<AnalysisOptions>,
}

/// A small signal analysed directly.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct DirectAnalysis {
    pub state: DirectState,
    pub analysis: AnalysisReport,
    pub spectra: DirectSpectra,
}

/// A direct analysis has run when it is answered.
#[derive(Debug, Clone, Copy, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum DirectState {
    Succeeded,
}

/// What `200` answers to `POST /v1/analyses`: a direct analysis, or with a repeated
/// `Idempotency-Key` the job the first request queued.
#[derive(Serialize, ToSchema)]
#[serde(untagged)]
#[allow(dead_code, clippy::large_enum_variant)] // documents the two shapes of the answer
pub enum AnalysisOk {
    Direct(DirectAnalysis),
    Replay(JobView),
}

/// The envelope spectra of a direct analysis.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct DirectSpectra {
    pub raw: Spectrum,
    /// The max-kurtosis DTCWT component's.
    pub best_component: Option<Spectrum>,
}

/// Analyse a measured signal
///
/// JSON samples, or a raw body of little-endian f32 samples
/// (`Content-Type: application/octet-stream`) described by query parameters. Signals up to
/// the configured size are answered directly (200); longer ones, or `mode=async`, are queued
/// as analysis jobs (202, poll `Location`).
#[utoipa::path(
    post,
    path = "/v1/analyses",
    tag = "analyses",
    operation_id = "submitAnalysis",
    params(IdempotencyKey, RawAnalysisQuery),
    request_body(content(
        (AnalysisRequest = "application/json"),
        (RawSamples = "application/octet-stream")
    )),
    responses(
        (status = 200, description = "Small signal, analysed directly; or an idempotent replay of a queued request (the job it created).", body = AnalysisOk),
        (status = 202, description = "Queued as an analysis job.", body = JobView, headers(
            ("Location" = String, description = "Path of the job."),
            ("ETag" = String, description = "Version of the job; send it back in If-None-Match.")
        ), links(
                ("getAnalysis" = (operation_id = "getAnalysis", parameters(("id" = "$response.body#/id")))),
                ("cancelAnalysis" = (operation_id = "cancelAnalysis", parameters(("id" = "$response.body#/id")))),
                ("getAnalysisResult" = (operation_id = "getAnalysisResult", parameters(("id" = "$response.body#/id")))),
                ("getAnalysisSpectra" = (operation_id = "getAnalysisSpectra", parameters(("id" = "$response.body#/id")))),
                ("deleteAnalysis" = (operation_id = "deleteAnalysis", parameters(("id" = "$response.body#/id"))))
            )),
        (status = 400, response = BadRequest),
        (status = 413, response = TooLarge),
        (status = 415, response = UnsupportedMediaType),
        (status = 422, response = Invalid),
        (status = 429, response = QueueFull),
        (status = 408, response = RequestTimeout),
        (status = 503, response = Unavailable),
    )
)]
pub async fn submit(
    State(state): State<AppState>,
    caller: Caller,
    headers: HeaderMap,
    RawQuery(q): RawQuery,
    body: Bytes,
) -> ApiResult<Response> {
    let q = QueryParams::parse(q.as_deref())?;
    let mode = q.str("mode").unwrap_or("auto");
    if mode != "auto" && mode != "async" {
        return Err(Problem::bad_request(format!(
            "query parameter 'mode' = '{mode}': expected auto or async"
        )));
    }
    let ct = content_type(&headers).unwrap_or_default();
    let mut file_name = None;
    let (input, samples) = if super::extract::is_json(&headers) {
        from_json(&body)?
    } else if ct == "application/octet-stream" && is_upload(&q) {
        let config = state.config.clone();
        let (q2, body2) = (q.clone(), body.clone());
        let (name, rec) = tokio::task::spawn_blocking(move || read_upload(&q2, &body2, &config))
            .await
            .map_err(|e| Problem::internal(format!("reading the file failed: {e}")))??;
        let signal = uploaded_signal(&q, name, &rec)?;
        file_name = Some(signal.name.clone());
        from_query(
            &q,
            signal.samples,
            Some((signal.sample_rate, signal.shaft_hz)),
        )?
    } else if ct == "application/octet-stream" {
        from_raw(&q, &body)?
    } else {
        return Err(Problem::unsupported_media(format!(
            "expected Content-Type application/json or application/octet-stream (raw f32 little-endian samples, or a recording file with filename= or format=), got {}",
            if ct.is_empty() { "none" } else { &ct }
        )));
    };

    let over =
        super::budget::over_analysis_budget(samples.len(), input.options.levels, &state.config);
    if !over.is_empty() {
        return Err(Problem::validation(over));
    }
    if mode == "async" || samples.len() > state.config.sync_analysis_samples {
        let value = serde_json::to_value(&input).map_err(|e| Problem::internal(e.to_string()))?;
        let label = file_name
            .unwrap_or_else(|| format!("{} samples at {} Hz", samples.len(), input.sample_rate));
        return enqueue(
            &state,
            &caller,
            &headers,
            KIND,
            label,
            value,
            Some(encode_f64le(&samples)),
        )
        .await;
    }

    let run = run_direct(&state, "the analysis", move |cancel| {
        run_analysis(&input, &samples, Some(cancel))
    })
    .await?;
    let out = run.map_err(|e| {
        Problem::new(
            StatusCode::UNPROCESSABLE_ENTITY,
            Some("analysis-failed"),
            "The signal cannot be analysed",
            e.to_string(),
        )
    })?;
    // the best level's spectrum, moved out rather than copied
    let best = out
        .report
        .best_component
        .level
        .checked_sub(1)
        .and_then(|i| out.level_spectra.into_iter().nth(i).flatten());
    Ok(Json(DirectAnalysis {
        state: DirectState::Succeeded,
        analysis: out.report,
        spectra: DirectSpectra {
            raw: out.raw_spectrum,
            best_component: best,
        },
    })
    .into_response())
}

fn from_json(body: &[u8]) -> ApiResult<(AnalysisInput, Vec<f64>)> {
    // Straight into the typed request: a JSON value tree of the samples costs ~6x the
    // body (96 MB for 3e6 samples). Only a request that does not parse takes the slow
    // path, which names the field at fault.
    let r: AnalysisRequest = match serde_json::from_slice(body) {
        Ok(r) => r,
        Err(_) => {
            let v = serde_json::Value::Object(as_object(parse_value(body)?)?);
            from_value(v, "")?
        }
    };
    let geometry = geometry(r.preset.as_deref(), r.geometry, "preset")?;
    let speed_field = speed_field(r.shaft_rpm.is_some());
    let shaft_hz = shaft_hz(r.shaft_hz, r.shaft_rpm)?;
    let input = AnalysisInput {
        sample_rate: r.sample_rate,
        geometry,
        shaft_hz,
        options: r.options.unwrap_or_default(),
    };
    check(&input, &r.samples, "options.", speed_field)?;
    Ok((input, r.samples))
}

fn from_raw(q: &QueryParams, body: &[u8]) -> ApiResult<(AnalysisInput, Vec<f64>)> {
    if !body.len().is_multiple_of(4) {
        return Err(Problem::field(
            "$",
            format!(
                "raw body length {} is not a multiple of 4 (f32 little-endian samples)",
                body.len()
            ),
        ));
    }
    from_query(q, crate::store::blob::decode_f32le(body), None)
}

/// The analysis the query parameters describe, of `samples`; `known` is the sample rate
/// and shaft frequency (Hz) an uploaded file gave, which the query then does not.
fn from_query(
    q: &QueryParams,
    samples: Vec<f64>,
    known: Option<(f64, f64)>,
) -> ApiResult<(AnalysisInput, Vec<f64>)> {
    let sample_rate = match known {
        Some((fs, _)) => fs,
        None => q.f64("sample_rate")?.ok_or_else(|| {
            Problem::field(
                "sample_rate",
                "required with a raw body: the query parameter sample_rate (Hz)",
            )
        })?,
    };
    let explicit = match (
        q.get::<usize>("ball_count")?,
        q.f64("ball_diameter")?,
        q.f64("pitch_diameter")?,
        q.f64("contact_angle")?,
    ) {
        (None, None, None, None) => None,
        (Some(ball_count), Some(ball_diameter), Some(pitch_diameter), Some(contact_angle)) => {
            Some(KinematicGeometry {
                ball_count,
                ball_diameter,
                pitch_diameter,
                contact_angle,
            })
        }
        _ => return Err(Problem::field(
            "ball_count",
            "give all of ball_count, ball_diameter, pitch_diameter and contact_angle, or a preset",
        )),
    };
    let geometry = geometry(q.str("preset"), explicit, "preset")?;
    let speed_field = speed_field(q.str("shaft_rpm").is_some());
    let shaft_hz = match known {
        Some((_, hz)) => hz,
        None => shaft_hz(q.f64("shaft_hz")?, q.f64("shaft_rpm")?)?,
    };
    let mut options = AnalysisOptions::default();
    if let Some(l) = q.get::<usize>("levels")? {
        options.levels = l;
    }
    if let Some(h) = q.get::<usize>("harmonics")? {
        options.harmonics = h;
    }
    if let Some(p) = q.f64("search_band_pct")? {
        options.search_band_pct = p;
    }
    match (q.f64("window_from")?, q.f64("window_to")?) {
        (None, None) => {}
        (Some(a), Some(b)) => options.window = Some([a, b]),
        _ => {
            return Err(Problem::field(
                "window_from",
                "give both window_from and window_to (s)",
            ))
        }
    }
    match (q.f64("band_low")?, q.f64("band_high")?) {
        (None, None) => {}
        (Some(a), Some(b)) => options.band = Some([a, b]),
        _ => {
            return Err(Problem::field(
                "band_low",
                "give both band_low and band_high (Hz)",
            ))
        }
    }
    if let Some(b) = q.str("biort") {
        options.biort = b.to_string();
    }
    if let Some(s) = q.str("qshift") {
        options.qshift = s.to_string();
    }
    options.kurtogram_levels = q.get::<usize>("kurtogram_levels")?;
    if let Some(p) = q.f64("false_alarm_rate")? {
        options.false_alarm_rate = p;
    }
    if let Some(h) = q.get::<usize>("verdict_harmonics")? {
        options.verdict_harmonics = h;
    }
    let input = AnalysisInput {
        sample_rate,
        geometry,
        shaft_hz,
        options,
    };
    check(&input, &samples, "", speed_field)?;
    Ok((input, samples))
}

fn geometry(
    preset: Option<&str>,
    explicit: Option<KinematicGeometry>,
    path: &str,
) -> ApiResult<KinematicGeometry> {
    match (preset, explicit) {
        (Some(_), Some(_)) => Err(Problem::field(
            path,
            "give either a preset or a geometry, not both",
        )),
        (None, None) => Err(Problem::field(
            path,
            format!(
                "required: a bearing preset ({}) or a geometry",
                kinematic_preset_names().join(", ")
            ),
        )),
        (Some(p), None) => kinematic_preset(&p.to_ascii_lowercase()).ok_or_else(|| {
            Problem::field(
                path,
                format!(
                    "unknown preset '{p}'; presets: {}",
                    kinematic_preset_names().join(", ")
                ),
            )
        }),
        (None, Some(g)) => g
            .validate()
            .map(|()| g)
            .map_err(|(field, message)| Problem::field(&format!("geometry.{field}"), message)),
    }
}

fn shaft_hz(hz: Option<f64>, rpm: Option<f64>) -> ApiResult<f64> {
    let f = match (hz, rpm) {
        (Some(_), Some(_)) => {
            return Err(Problem::field(
                "shaft_hz",
                "give either shaft_hz or shaft_rpm, not both",
            ))
        }
        (None, None) => {
            return Err(Problem::field(
                "shaft_hz",
                "required: shaft_hz (Hz) or shaft_rpm (rev/min)",
            ))
        }
        (Some(h), None) => h,
        (None, Some(r)) => r / 60.0,
    };
    if !(f.is_finite() && f > 0.0) {
        return Err(Problem::field(
            if hz.is_some() {
                "shaft_hz"
            } else {
                "shaft_rpm"
            },
            "must be a finite number > 0",
        ));
    }
    Ok(f)
}

/// The field a shaft speed was given in.
fn speed_field(rpm_given: bool) -> &'static str {
    if rpm_given {
        "shaft_rpm"
    } else {
        "shaft_hz"
    }
}

/// Check the request before anything runs or is queued; `options_prefix` is where the
/// options sit in the request (`options.` in a JSON body, nothing for query parameters),
/// `speed_field` the field of the shaft speed.
fn check(
    input: &AnalysisInput,
    samples: &[f64],
    options_prefix: &str,
    speed_field: &str,
) -> ApiResult<()> {
    let mut errs = vec![];
    if !(input.sample_rate.is_finite() && input.sample_rate > 0.0) {
        errs.push(FieldProblem {
            path: "sample_rate".into(),
            message: "must be a finite number > 0 Hz".into(),
        });
    }
    if samples.len() < 16 {
        errs.push(FieldProblem {
            path: "samples".into(),
            message: format!("need at least 16 samples, got {}", samples.len()),
        });
    }
    if let Some(k) = samples.iter().position(|x| !x.is_finite()) {
        errs.push(FieldProblem {
            path: format!("samples[{k}]"),
            message: "must be finite".into(),
        });
    }
    if errs.is_empty() {
        errs = super::analysis_sense::senseless(input, samples, speed_field);
    }
    // the options as the analysis itself checks them, so a queued job cannot be accepted
    // and fail later where the direct path answers 422
    if errs.is_empty() {
        let problem = check_options(&input.options, input.sample_rate, samples.len()).err();
        if let Some(e) = problem {
            errs.push(match e {
                AnalysisError::Invalid { field, message } => FieldProblem {
                    path: format!("{options_prefix}{field}"),
                    message,
                },
                AnalysisError::TooShort { n, levels, need } => FieldProblem {
                    path: "samples".into(),
                    message: format!(
                        "{n} samples is too short for {levels} levels (need >= {need})"
                    ),
                },
                AnalysisError::NonFinite { index } => FieldProblem {
                    path: format!("samples[{index}]"),
                    message: "must be finite".into(),
                },
                AnalysisError::Cancelled => FieldProblem {
                    path: "$".into(),
                    message: "the check was cancelled".into(),
                },
            });
        }
    }
    if errs.is_empty() {
        Ok(())
    } else {
        Err(Problem::validation(errs))
    }
}

/// State of a queued analysis
///
/// ETag, `If-None-Match` and the `wait` long poll work as for simulations.
#[utoipa::path(
    get,
    path = "/v1/analyses/{id}",
    tag = "analyses",
    operation_id = "getAnalysis",
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

/// List queued analysis jobs, newest first
#[utoipa::path(
    get,
    path = "/v1/analyses",
    tag = "analyses",
    operation_id = "listAnalyses",
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

/// Cancel a queued or running analysis
#[utoipa::path(
    post,
    path = "/v1/analyses/{id}/cancel",
    tag = "analyses",
    operation_id = "cancelAnalysis",
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

/// Delete a finished analysis job
#[utoipa::path(
    delete,
    path = "/v1/analyses/{id}",
    tag = "analyses",
    operation_id = "deleteAnalysis",
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

/// Report of a succeeded analysis job
#[utoipa::path(
    get,
    path = "/v1/analyses/{id}/result",
    tag = "analyses",
    operation_id = "getAnalysisResult",
    params(JobId),
    responses(
        (status = 200, description = "The report.", body = AnalysisResult),
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

/// Envelope spectrum of a succeeded analysis job
#[utoipa::path(
    get,
    path = "/v1/analyses/{id}/spectra",
    tag = "analyses",
    operation_id = "getAnalysisSpectra",
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
