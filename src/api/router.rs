//! The router: every route of the table, with the middleware every route gets.

use super::state::AppState;
use super::{middleware, ops, routes};
use axum::extract::DefaultBodyLimit;
use axum::http::{header, HeaderName, HeaderValue, Method, StatusCode};
use axum::Router;
use std::time::Duration;
use tower_http::cors::{AllowOrigin, CorsLayer};
use tower_http::timeout::TimeoutLayer;
use tower_http::trace::TraceLayer;

pub fn router(state: AppState) -> Router {
    let cfg = state.config.clone();
    let timeout = cfg.request_deadline();
    let mut app = Router::new();
    for route in routes::table() {
        let handler = if route.long_poll {
            route.handler
        } else {
            route.handler.layer(TimeoutLayer::with_status_code(
                StatusCode::REQUEST_TIMEOUT,
                timeout,
            ))
        };
        app = app.route(route.path, handler);
    }
    // the lab's page (not part of the API document)
    let app = app
        .route("/", axum::routing::get(super::web::index))
        .route("/assets/{name}", axum::routing::get(super::web::asset));
    let mut app = app
        .fallback(ops::no_route)
        .layer(DefaultBodyLimit::max(cfg.max_body_bytes))
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            super::caller::authenticate,
        ))
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            middleware::answer_without_database,
        ))
        .layer(TraceLayer::new_for_http())
        .layer(axum::middleware::from_fn(
            middleware::problem_for_every_error,
        ))
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            middleware::bound_request_bodies,
        ))
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            middleware::record_latency,
        ))
        .with_state(state);
    if let Some(cors) = cors_layer(&cfg.cors_origins) {
        app = app.layer(cors);
    }
    app
}

/// CORS for the configured origins (checked when the configuration was parsed): `*`
/// anywhere in the list allows any origin (tower-http's list refuses a wildcard).
fn cors_layer(origins: &[String]) -> Option<CorsLayer> {
    let origins: Vec<&str> = origins
        .iter()
        .map(|o| o.trim())
        .filter(|o| !o.is_empty())
        .collect();
    if origins.is_empty() {
        return None;
    }
    let allow = if origins.contains(&"*") {
        AllowOrigin::any()
    } else {
        AllowOrigin::list(
            origins
                .iter()
                .filter_map(|o| HeaderValue::from_str(o).ok())
                .collect::<Vec<_>>(),
        )
    };
    Some(
        CorsLayer::new()
            .allow_origin(allow)
            .allow_methods([Method::GET, Method::POST, Method::DELETE, Method::OPTIONS])
            .allow_headers([
                header::CONTENT_TYPE,
                header::IF_NONE_MATCH,
                header::ACCEPT,
                header::AUTHORIZATION,
                HeaderName::from_static("idempotency-key"),
            ])
            .expose_headers([header::LOCATION, header::ETAG, header::RETRY_AFTER])
            .max_age(Duration::from_secs(600)),
    )
}
