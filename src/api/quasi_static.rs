//! `POST /v1/quasi-static`: the Jones-Harris equilibrium, answered directly.

use super::direct::run_direct;
use super::extract::{as_object, from_value, parse_value, require_json};
use super::problem::{ApiResult, Problem};
use super::scene_input::resolve_scene;
use super::state::AppState;
use axum::body::Bytes;
use axum::extract::State;
use axum::http::{HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;

pub async fn solve(
    State(state): State<AppState>,
    headers: HeaderMap,
    body: Bytes,
) -> ApiResult<Response> {
    require_json(&headers)?;
    let mut body = as_object(parse_value(&body)?)?;
    let rpm: Option<f64> = match body.remove("shaft_rpm") {
        None => None,
        Some(v) => Some(from_value(v, "shaft_rpm")?),
    };
    let scene = resolve_scene(&mut body, &["shaft_rpm"])?;
    let rpm = rpm.unwrap_or(scene.operating.speed.steady_rpm);
    if !rpm.is_finite() || rpm <= 0.0 || rpm > 100_000.0 {
        return Err(Problem::field(
            "shaft_rpm",
            "must be in (0, 100000] rev/min",
        ));
    }
    let solved = run_direct(&state, "the quasi-static solver", move || {
        bearing_core::quasi_static::solve(&scene, rpm)
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
