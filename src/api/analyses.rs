//! `POST /v1/analyses`: the diagnosis pipeline on a measured signal, sent as JSON samples
//! or as a raw little-endian f32 body with query parameters. Small signals are answered
//! directly (200); large ones, or `mode=async`, are queued as jobs (202).

use super::direct::run_direct;
use super::extract::{as_object, content_type, from_value, parse_value, QueryParams};
use super::job_resource;
use super::problem::{ApiResult, FieldProblem, Problem};
use super::results;
use super::state::AppState;
use super::submission::enqueue;
use crate::jobs::{run_analysis, AnalysisInput};
use crate::store::blob::encode_f64le;
use crate::store::JobKind;
use axum::body::Bytes;
use axum::extract::{Path, RawQuery, State};
use axum::http::{HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use bearing_core::signal::analysis::AnalysisOptions;
use bearing_core::signal::frequencies::{
    kinematic_preset, kinematic_preset_names, KinematicGeometry,
};
use serde::Deserialize;
use serde_json::json;

const KIND: JobKind = JobKind::Analysis;

/// The JSON form of a request.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JsonRequest {
    samples: Vec<f64>,
    sample_rate: f64,
    #[serde(default)]
    preset: Option<String>,
    #[serde(default)]
    geometry: Option<KinematicGeometry>,
    #[serde(default)]
    shaft_hz: Option<f64>,
    #[serde(default)]
    shaft_rpm: Option<f64>,
    #[serde(default)]
    options: Option<AnalysisOptions>,
}

pub async fn submit(
    State(state): State<AppState>,
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
    let (input, samples) = if super::extract::is_json(&headers) {
        from_json(&body)?
    } else if ct == "application/octet-stream" {
        from_raw(&q, &body)?
    } else {
        return Err(Problem::unsupported_media(format!(
            "expected Content-Type application/json or application/octet-stream (raw f32 little-endian samples), got {}",
            if ct.is_empty() { "none" } else { &ct }
        )));
    };

    if mode == "async" || samples.len() > state.config.sync_analysis_samples {
        let value = serde_json::to_value(&input).map_err(|e| Problem::internal(e.to_string()))?;
        let label = format!("{} samples at {} Hz", samples.len(), input.sample_rate);
        return enqueue(
            &state,
            &headers,
            KIND,
            label,
            value,
            Some(encode_f64le(&samples)),
        )
        .await;
    }

    let run = run_direct(&state, "the analysis", move || {
        run_analysis(&input, &samples)
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
    let best = out.report.best_component.level;
    Ok(Json(json!({
        "state": "succeeded",
        "analysis": out.report,
        "spectra": {
            "raw": out.raw_spectrum,
            "best_component": best.checked_sub(1).and_then(|i| out.level_spectra.get(i)),
        },
    }))
    .into_response())
}

fn from_json(body: &[u8]) -> ApiResult<(AnalysisInput, Vec<f64>)> {
    let v = serde_json::Value::Object(as_object(parse_value(body)?)?);
    let r: JsonRequest = from_value(v, "")?;
    let geometry = geometry(r.preset.as_deref(), r.geometry, "preset")?;
    let shaft_hz = shaft_hz(r.shaft_hz, r.shaft_rpm)?;
    let input = AnalysisInput {
        sample_rate: r.sample_rate,
        geometry,
        shaft_hz,
        options: r.options.unwrap_or_default(),
    };
    check(&input, &r.samples)?;
    Ok((input, r.samples))
}

fn from_raw(q: &QueryParams, body: &[u8]) -> ApiResult<(AnalysisInput, Vec<f64>)> {
    if body.len() % 4 != 0 {
        return Err(Problem::field(
            "$",
            format!(
                "raw body length {} is not a multiple of 4 (f32 little-endian samples)",
                body.len()
            ),
        ));
    }
    let samples = crate::store::blob::decode_f32le(body);
    let sample_rate = q.f64("sample_rate")?.ok_or_else(|| {
        Problem::field(
            "sample_rate",
            "required with a raw body: the query parameter sample_rate (Hz)",
        )
    })?;
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
    let shaft_hz = shaft_hz(q.f64("shaft_hz")?, q.f64("shaft_rpm")?)?;
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
    let input = AnalysisInput {
        sample_rate,
        geometry,
        shaft_hz,
        options,
    };
    check(&input, &samples)?;
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

fn check(input: &AnalysisInput, samples: &[f64]) -> ApiResult<()> {
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
        Ok(())
    } else {
        Err(Problem::validation(errs))
    }
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
