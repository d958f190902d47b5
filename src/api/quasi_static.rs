//! `POST /v1/quasi-static`: the Jones-Harris equilibrium, answered directly.

use super::direct::run_direct;
use super::extract::{as_object, from_value, parse_bounded, require_json};
use super::openapi::responses::{
    BadRequest, Invalid, RequestTimeout, TooLarge, Unavailable, UnsupportedMediaType,
};
use super::problem::{ApiResult, Problem};
use super::scene_input::{resolve_scene, QuasiStaticRequest};
use super::state::AppState;
use axum::body::Bytes;
use axum::extract::State;
use axum::http::{HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use bearing_core::quasi_static::QuasiStaticSolution;
use std::sync::atomic::Ordering;

/// Quasi-static (Jones-Harris) equilibrium, answered directly
#[utoipa::path(
    post,
    path = "/v1/quasi-static",
    tag = "models",
    operation_id = "solveQuasiStatic",
    request_body(
        content = QuasiStaticRequest,
        examples(
            ("preset" = (value = json!({"preset": "h7005c", "shaft_rpm": 10000}))),
            ("with the pocket cycle" = (value = json!({"preset": "h7005c", "shaft_rpm": 10000, "pocket_cycle": true})))
        )
    ),
    responses(
        (status = 200, description = "The equilibrium.", body = QuasiStaticSolution),
        (status = 400, response = BadRequest),
        (status = 413, response = TooLarge),
        (status = 415, response = UnsupportedMediaType),
        (status = 422, response = Invalid),
        (status = 408, response = RequestTimeout),
        (status = 503, response = Unavailable),
    )
)]
pub async fn solve(
    State(state): State<AppState>,
    headers: HeaderMap,
    body: Bytes,
) -> ApiResult<Response> {
    require_json(&headers)?;
    let mut body = as_object(parse_bounded(&body)?)?;
    let rpm: Option<f64> = match body.remove("shaft_rpm") {
        None => None,
        Some(v) => Some(from_value(v, "shaft_rpm")?),
    };
    let with_cycle: bool = match body.remove("pocket_cycle") {
        None => false,
        Some(v) => from_value(v, "pocket_cycle")?,
    };
    let scene = resolve_scene(&mut body, &["shaft_rpm", "pocket_cycle"])?;
    let rpm = rpm.unwrap_or(scene.operating.speed.steady_rpm);
    if !rpm.is_finite() || rpm <= 0.0 || rpm > 100_000.0 {
        return Err(Problem::field(
            "shaft_rpm",
            "must be in (0, 100000] rev/min",
        ));
    }
    let solved = run_direct(&state, "the quasi-static solver", move |cancel| {
        // a few milliseconds of Newton iterations: not worth a check; the pocket cycle
        // asks between its trial cage speeds
        let mut solution = bearing_core::quasi_static::solve(&scene, rpm)?;
        if with_cycle {
            let stop = || cancel.load(Ordering::SeqCst);
            solution.pocket_cycle = Some(bearing_core::quasi_static::pocket_cycle_until(
                &scene, rpm, &stop,
            )?);
        }
        Ok::<_, bearing_core::quasi_static::QsError>(solution)
    })
    .await?;
    match solved {
        Ok(solution) => Ok((StatusCode::OK, Json(solution)).into_response()),
        Err(e) => Err(Problem::new(
            StatusCode::UNPROCESSABLE_ENTITY,
            Some("solver-failed"),
            "The solver found no solution",
            e.to_string(),
        )),
    }
}
