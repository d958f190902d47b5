//! The job resource, shared by both job kinds (simulations and queued analyses): read
//! (with ETag and long poll), list, cancel, delete.

use super::caller::Caller;
use super::extract::QueryParams;
use super::problem::{ApiResult, Problem};
use super::state::AppState;
use super::views::{collection, etag, etag_matches, job_location, JobPage, JobView};
use crate::store::{Job, JobKind, JobState, ListFilter, StoreError};
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use std::time::{Duration, Instant};

/// Longest long poll (`wait`), s.
pub const MAX_WAIT: f64 = 60.0;

/// A job of the expected kind that the caller may see, or 404 (ids of the other kind,
/// and other tenants' jobs, are not visible here).
/// An unknown id and one the caller may not see get the same answer, so ids reveal nothing.
pub async fn load(state: &AppState, caller: &Caller, kind: JobKind, id: &str) -> ApiResult<Job> {
    let not_found = || Problem::not_found(format!("no {} with id {id}", kind.as_str()));
    let job = match state.store.get_job(id).await {
        Ok(job) => job,
        Err(StoreError::NotFound(_)) => return Err(not_found()),
        Err(e) => return Err(e.into()),
    };
    if job.kind != kind || !caller.may_see(&job.tenant) {
        return Err(not_found());
    }
    Ok(job)
}

pub fn job_response(status: StatusCode, job: &Job) -> Response {
    let mut res = (status, Json(JobView::of(job))).into_response();
    let h = res.headers_mut();
    if let Ok(v) = HeaderValue::from_str(&etag(job)) {
        h.insert(header::ETAG, v);
    }
    if let Ok(v) = HeaderValue::from_str(&job_location(job)) {
        h.insert(header::LOCATION, v);
    }
    h.insert(header::CACHE_CONTROL, HeaderValue::from_static("no-cache"));
    res
}

pub async fn get_job(
    state: AppState,
    caller: &Caller,
    kind: JobKind,
    id: String,
    headers: HeaderMap,
    q: Option<String>,
) -> ApiResult<Response> {
    long_poll(
        &headers,
        q.as_deref(),
        || load(&state, caller, kind, &id),
        etag,
        |job| job.state.is_finished(),
        |job| Ok(job_response(StatusCode::OK, job)),
    )
    .await
}

/// `GET` with `If-None-Match` and `wait` (s): answer at once when the resource changed
/// since the tag given; otherwise hold the unchanged answer until it changes, it finishes,
/// or `wait` passes, then 304. `*` names no version to wait past: answered at once.
pub async fn long_poll<T, Fut>(
    headers: &HeaderMap,
    q: Option<&str>,
    mut load: impl FnMut() -> Fut,
    tag: impl Fn(&T) -> String,
    finished: impl Fn(&T) -> bool,
    respond: impl Fn(&T) -> ApiResult<Response>,
) -> ApiResult<Response>
where
    Fut: std::future::Future<Output = ApiResult<T>>,
{
    let q = QueryParams::parse(q)?;
    let wait = q.f64("wait")?.unwrap_or(0.0);
    if !(0.0..=MAX_WAIT).contains(&wait) {
        return Err(Problem::bad_request(format!(
            "query parameter 'wait' must be in [0, {MAX_WAIT}] s"
        )));
    }
    let inm = headers
        .get(header::IF_NONE_MATCH)
        .and_then(|v| v.to_str().ok())
        .map(str::to_string);
    let deadline = Instant::now() + Duration::from_secs_f64(wait);
    loop {
        let item = load().await?;
        let current = tag(&item);
        if !inm.as_deref().is_some_and(|t| etag_matches(t, &current)) {
            return respond(&item);
        }
        let wildcard = inm.as_deref().is_some_and(|t| t.trim() == "*");
        if wildcard || finished(&item) || Instant::now() >= deadline {
            let mut res = StatusCode::NOT_MODIFIED.into_response();
            if let Ok(v) = HeaderValue::from_str(&current) {
                res.headers_mut().insert(header::ETAG, v);
            }
            return Ok(res);
        }
        tokio::time::sleep(Duration::from_millis(200)).await;
    }
}

pub async fn list(
    state: AppState,
    caller: &Caller,
    kind: JobKind,
    q: Option<String>,
) -> ApiResult<Response> {
    let q = QueryParams::parse(q.as_deref())?;
    let job_state = match q.str("state") {
        None => None,
        Some(s) => Some(JobState::parse(s).ok_or_else(|| {
            Problem::bad_request(format!("query parameter 'state' = '{s}': expected queued, running, succeeded, failed or cancelled"))
        })?),
    };
    let (limit, before) = paging(&q, 50, 500)?;
    let page = state
        .store
        .list_jobs(&ListFilter {
            tenant: caller.list_scope(),
            kind: Some(kind),
            state: job_state,
            before,
            limit,
        })
        .await?;
    let next_cursor = page.next.map(|n| n.to_string());
    let next = next_cursor.as_ref().map(|n| {
        let mut link = format!("{}?cursor={n}&limit={limit}", collection(kind));
        if let Some(s) = job_state {
            link.push_str(&format!("&state={s}"));
        }
        link
    });
    Ok(Json(JobPage {
        items: page.jobs.iter().map(JobView::of).collect(),
        next_cursor,
        next,
    })
    .into_response())
}

pub async fn cancel(
    state: AppState,
    caller: &Caller,
    kind: JobKind,
    id: String,
) -> ApiResult<Response> {
    load(&state, caller, kind, &id).await?;
    let job = state.store.request_cancel(&id).await?;
    Ok(job_response(StatusCode::ACCEPTED, &job))
}

pub async fn delete(
    state: AppState,
    caller: &Caller,
    kind: JobKind,
    id: String,
) -> ApiResult<Response> {
    load(&state, caller, kind, &id).await?;
    state.store.delete_job(&id).await?;
    Ok(StatusCode::NO_CONTENT.into_response())
}

/// `limit` (default `default`, at most `max`) and `cursor` (the `seq` to list below) of a
/// listing.
pub fn paging(q: &QueryParams, default: i64, max: i64) -> ApiResult<(i64, Option<i64>)> {
    let limit = q.get::<i64>("limit")?.unwrap_or(default);
    if !(1..=max).contains(&limit) {
        return Err(Problem::bad_request(format!(
            "query parameter 'limit' must be in 1..={max}"
        )));
    }
    let before = match q.str("cursor") {
        None => None,
        Some(c) => Some(c.parse::<i64>().ok().filter(|n| *n > 0).ok_or_else(|| {
            Problem::bad_request(format!(
                "query parameter 'cursor' = '{c}' is not a cursor from a previous page"
            ))
        })?),
    };
    Ok((limit, before))
}

/// The job, if it succeeded; 409 otherwise (with its state).
pub async fn succeeded(
    state: &AppState,
    caller: &Caller,
    kind: JobKind,
    id: &str,
) -> ApiResult<Job> {
    let job = load(state, caller, kind, id).await?;
    if job.state != JobState::Succeeded {
        let why = match &job.error {
            Some(e) => format!(
                "job {id} is {} ({}: {}); results exist only for succeeded jobs",
                job.state, e.kind, e.message
            ),
            None => format!(
                "job {id} is {}; results exist only for succeeded jobs",
                job.state
            ),
        };
        return Err(Problem::conflict(why, Some(job.state.as_str())));
    }
    Ok(job)
}
