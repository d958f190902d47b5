//! Who is calling: the `authenticate` middleware turns the bearer token into a
//! [`Caller`] (the tenant), and handlers take it as an extractor to scope what they show
//! and change.

use super::problem::Problem;
use super::state::AppState;
use axum::extract::{FromRequestParts, Request, State};
use axum::http::request::Parts;
use axum::http::{header, HeaderValue, Method, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use std::convert::Infallible;

/// The tenant of a request: the name of its token ('' without tokens), and whether it
/// may read everyone's jobs (a token-less GET with `--open-reads`).
#[derive(Debug, Clone, Default)]
pub struct Caller {
    tenant: String,
    reads_all: bool,
    share_key: String,
}

/// The address a request came from (set by the accept loop on every request).
#[derive(Debug, Clone, Copy)]
pub struct ClientAddr(pub std::net::IpAddr);

/// Who a request counts against for the shares of limited resources (large transfers):
/// its tenant when it names a configured token, otherwise its address. Tenants on one
/// host (behind one proxy) keep separate shares; anonymous clients share by address.
pub fn share_key(state: &AppState, req: &Request) -> String {
    let tenant = req
        .headers()
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(bearer_token)
        .and_then(|t| state.tokens.name_of(t));
    match (tenant, req.extensions().get::<ClientAddr>()) {
        (Some(name), _) => format!("tenant {name}"),
        (None, Some(ClientAddr(ip))) => format!("address {ip}"),
        (None, None) => "address unknown".into(),
    }
}

impl Caller {
    /// The owner recorded on what this caller creates.
    pub fn tenant(&self) -> &str {
        &self.tenant
    }

    /// May this caller see a resource owned by `owner`? (Others' resources answer 404,
    /// so their ids reveal nothing.)
    pub fn may_see(&self, owner: &str) -> bool {
        self.reads_all || owner == self.tenant
    }

    /// Whom this request counts against for shared limits ([`share_key`]).
    pub fn share_key(&self) -> &str {
        &self.share_key
    }

    /// The tenant to scope a listing to (None: everyone's).
    pub fn list_scope(&self) -> Option<String> {
        (!self.reads_all).then(|| self.tenant.clone())
    }
}

impl<S: Send + Sync> FromRequestParts<S> for Caller {
    type Rejection = Infallible;

    async fn from_request_parts(parts: &mut Parts, _: &S) -> Result<Self, Self::Rejection> {
        // set by `authenticate` on every /v1 route; absent only without tokens
        Ok(parts
            .extensions
            .get::<Caller>()
            .cloned()
            .unwrap_or_default())
    }
}

fn unauthorized(detail: &str) -> Response {
    let mut res = Problem::new(
        StatusCode::UNAUTHORIZED,
        Some("unauthorized"),
        "Unauthorized",
        detail,
    )
    .into_response();
    res.headers_mut().insert(
        header::WWW_AUTHENTICATE,
        HeaderValue::from_static("Bearer realm=\"bearing-sim\""),
    );
    res
}

/// The token of an `Authorization: Bearer <token>` value. The scheme is case-insensitive
/// (RFC 7235 section 2.1): `bearer` and `BEARER` name it too.
fn bearer_token(value: &str) -> Option<&str> {
    let (scheme, token) = value.trim_start().split_once(' ')?;
    scheme
        .eq_ignore_ascii_case("bearer")
        .then(|| token.trim())
        .filter(|t| !t.is_empty())
}

/// With tokens configured, every `/v1` request needs `Authorization: Bearer <token>`
/// (token-less GETs too, unless `--open-reads`); health, metrics, the OpenAPI document
/// and the web page stay open.
pub async fn authenticate(State(state): State<AppState>, mut req: Request, next: Next) -> Response {
    let share_key = share_key(&state, &req);
    if state.tokens.is_empty() || !req.uri().path().starts_with("/v1/") {
        req.extensions_mut().insert(Caller {
            share_key,
            ..Caller::default()
        });
        return next.run(req).await;
    }
    let caller = match req.headers().get(header::AUTHORIZATION) {
        Some(v) => {
            let token = v.to_str().ok().and_then(bearer_token);
            let Some(token) = token else {
                return unauthorized("the Authorization header must be 'Bearer <token>'");
            };
            match state.tokens.name_of(token) {
                Some(name) => Caller {
                    tenant: name.to_string(),
                    reads_all: false,
                    share_key,
                },
                None => return unauthorized("the token is not configured on this service"),
            }
        }
        None if state.config.open_reads && matches!(*req.method(), Method::GET | Method::HEAD) => {
            Caller {
                tenant: String::new(),
                reads_all: true,
                share_key,
            }
        }
        None => {
            return unauthorized(
                "this service requires a token: send Authorization: Bearer <token>",
            )
        }
    };
    req.extensions_mut().insert(caller);
    next.run(req).await
}

#[cfg(test)]
mod tests {
    use super::bearer_token;

    #[test]
    fn the_bearer_scheme_is_case_insensitive() {
        for v in ["Bearer bs_x", "bearer bs_x", "BEARER  bs_x "] {
            assert_eq!(bearer_token(v), Some("bs_x"), "{v}");
        }
        for v in ["Basic YTpi", "Bearer", "Bearer ", "Bearerbs_x"] {
            assert_eq!(bearer_token(v), None, "{v}");
        }
    }
}
