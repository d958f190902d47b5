//! Handlers shared by both job kinds (simulations and queued analyses): read, list,
//! cancel, delete, result and spectra.

use super::extract::QueryParams;
use super::problem::{ApiResult, Problem};
use super::views::{etag, etag_matches, job_json, job_location};
use super::AppState;
use crate::store::blob::decode_f32le;
use crate::store::{Job, JobKind, JobState, ListFilter};
use axum::extract::{Path, RawQuery, State};
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde_json::{json, Value};
use std::time::{Duration, Instant};

/// Longest long poll (`wait`), s.
const MAX_WAIT: f64 = 60.0;

/// A job of the expected kind, or 404 (ids of the other kind are not visible here).
pub async fn load(state: &AppState, kind: JobKind, id: &str) -> ApiResult<Job> {
    let job = state.store.get_job(id).await?;
    if job.kind != kind {
        return Err(Problem::not_found(format!(
            "no {} with id {id}",
            kind.as_str()
        )));
    }
    Ok(job)
}

pub fn job_response(status: StatusCode, job: &Job) -> Response {
    let mut res = (status, Json(job_json(job))).into_response();
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

fn not_modified(job: &Job) -> Response {
    let mut res = StatusCode::NOT_MODIFIED.into_response();
    if let Ok(v) = HeaderValue::from_str(&etag(job)) {
        res.headers_mut().insert(header::ETAG, v);
    }
    res
}

async fn get_job(
    state: AppState,
    kind: JobKind,
    id: String,
    headers: HeaderMap,
    q: Option<String>,
) -> ApiResult<Response> {
    let q = QueryParams::parse(q.as_deref())?;
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
        let job = load(&state, kind, &id).await?;
        let unchanged = inm.as_deref().is_some_and(|t| etag_matches(t, &etag(&job)));
        if !unchanged {
            return Ok(job_response(StatusCode::OK, &job));
        }
        // Long poll: with `wait`, hold an unchanged answer until the job changes. `*` names
        // no version to wait past, so it is answered at once.
        let wildcard = inm.as_deref().is_some_and(|t| t.trim() == "*");
        if wildcard || job.state.is_finished() || Instant::now() >= deadline {
            return Ok(not_modified(&job));
        }
        tokio::time::sleep(Duration::from_millis(200)).await;
    }
}

async fn list(state: AppState, kind: JobKind, q: Option<String>) -> ApiResult<Response> {
    let q = QueryParams::parse(q.as_deref())?;
    let job_state = match q.str("state") {
        None => None,
        Some(s) => Some(JobState::parse(s).ok_or_else(|| {
            Problem::bad_request(format!("query parameter 'state' = '{s}': expected queued, running, succeeded, failed or cancelled"))
        })?),
    };
    let limit = q.get::<i64>("limit")?.unwrap_or(50);
    if !(1..=500).contains(&limit) {
        return Err(Problem::bad_request(
            "query parameter 'limit' must be in 1..=500",
        ));
    }
    let before = match q.str("cursor") {
        None => None,
        Some(c) => Some(c.parse::<i64>().ok().filter(|n| *n > 0).ok_or_else(|| {
            Problem::bad_request(format!(
                "query parameter 'cursor' = '{c}' is not a cursor from a previous page"
            ))
        })?),
    };
    let page = state
        .store
        .list_jobs(&ListFilter {
            kind: Some(kind),
            state: job_state,
            before,
            limit,
        })
        .await?;
    let items: Vec<Value> = page.jobs.iter().map(job_json).collect();
    let next = page.next.map(|n| n.to_string());
    let mut body = json!({ "items": items, "next_cursor": next });
    if let Some(n) = &next {
        let mut link = format!(
            "{}?cursor={n}&limit={limit}",
            super::views::collection(kind)
        );
        if let Some(s) = job_state {
            link.push_str(&format!("&state={s}"));
        }
        body["next"] = json!(link);
    }
    Ok(Json(body).into_response())
}

async fn cancel(state: AppState, kind: JobKind, id: String) -> ApiResult<Response> {
    load(&state, kind, &id).await?;
    let job = state.store.request_cancel(&id).await?;
    Ok(job_response(StatusCode::ACCEPTED, &job))
}

async fn delete(state: AppState, kind: JobKind, id: String) -> ApiResult<Response> {
    load(&state, kind, &id).await?;
    state.store.delete_job(&id).await?;
    Ok(StatusCode::NO_CONTENT.into_response())
}

/// The job, if it succeeded; 409 otherwise (with its state).
pub async fn succeeded(state: &AppState, kind: JobKind, id: &str) -> ApiResult<Job> {
    let job = load(state, kind, id).await?;
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

async fn result(state: AppState, kind: JobKind, id: String) -> ApiResult<Response> {
    let job = succeeded(&state, kind, &id).await?;
    let mut body = job.result.clone().unwrap_or(Value::Null);
    if let Value::Object(m) = &mut body {
        m.insert("id".into(), json!(job.id));
        if job.stats.is_some() {
            m.entry("solver")
                .or_insert(job.stats.clone().unwrap_or(Value::Null));
        }
    }
    let mut res = Json(body).into_response();
    if let Ok(v) = HeaderValue::from_str(&etag(&job)) {
        res.headers_mut().insert(header::ETAG, v);
    }
    Ok(res)
}

async fn spectra(
    state: AppState,
    kind: JobKind,
    id: String,
    q: Option<String>,
) -> ApiResult<Response> {
    let q = QueryParams::parse(q.as_deref())?;
    let level = q.get::<usize>("level")?;
    if let Some(l) = level {
        if !(1..=bearing_sim::signal::analysis::MAX_LEVELS).contains(&l) {
            return Err(Problem::bad_request(format!(
                "query parameter 'level' must be in 1..={}",
                bearing_sim::signal::analysis::MAX_LEVELS
            )));
        }
    }
    // `level` alone implies kind=level; with another kind it is ignored.
    let which = q
        .str("kind")
        .unwrap_or(if level.is_some() { "level" } else { "raw" })
        .to_string();
    let level = if which == "level" { level } else { None };
    let fmax = q.f64("fmax")?;
    if let Some(f) = fmax {
        if f <= 0.0 {
            return Err(Problem::bad_request(
                "query parameter 'fmax' must be > 0 Hz",
            ));
        }
    }
    if !["raw", "best_component", "level"].contains(&which.as_str()) {
        return Err(Problem::bad_request(format!(
            "query parameter 'kind' = '{which}': expected raw, best_component or level"
        )));
    }
    if which == "level" && level.is_none() {
        return Err(Problem::field(
            "level",
            "required with kind=level (1 = finest)",
        ));
    }
    let job = succeeded(&state, kind, &id).await?;
    let analysis = job
        .result
        .as_ref()
        .and_then(|r| r.get("analysis"))
        .filter(|a| !a.is_null())
        .cloned();
    let Some(analysis) = analysis else {
        let why = job
            .result
            .as_ref()
            .and_then(|r| r.get("analysis_error"))
            .and_then(|v| v.as_str())
            .unwrap_or("no analysis was stored");
        return Err(Problem::conflict(
            format!("job {id} has no spectra: {why}"),
            Some(job.state.as_str()),
        ));
    };
    let best_level = analysis
        .pointer("/best_component/level")
        .and_then(Value::as_u64)
        .map(|l| l as usize);
    let (artifact, lvl, peaks) = match which.as_str() {
        "raw" => (
            "spectrum:raw".to_string(),
            None,
            analysis.get("raw").cloned(),
        ),
        "best_component" => {
            let l = best_level
                .ok_or_else(|| Problem::internal("stored analysis lacks best_component.level"))?;
            (
                format!("spectrum:level:{l}"),
                Some(l),
                analysis.pointer("/best_component/identifications").cloned(),
            )
        }
        _ => {
            let l = level.unwrap_or(0);
            let peaks = ["best_component", "runner_up_component"]
                .iter()
                .filter_map(|c| analysis.get(*c))
                .find(|c| c.get("level").and_then(Value::as_u64) == Some(l as u64))
                .and_then(|c| c.get("identifications").cloned());
            (format!("spectrum:level:{l}"), Some(l), peaks)
        }
    };
    let Some(a) = state.store.get_artifact(&id, &artifact).await? else {
        return Err(Problem::not_found(format!(
            "job {id} has no spectrum {which}{}",
            lvl.map(|l| format!(" for level {l}")).unwrap_or_default()
        )));
    };
    let df = a.meta.get("df").and_then(Value::as_f64).unwrap_or(0.0);
    let mut amplitude = decode_f32le(&a.data);
    if let Some(f) = fmax {
        if df > 0.0 {
            amplitude.truncate(((f / df).floor() as usize + 1).min(amplitude.len()));
        }
    }
    let f_top = df * amplitude.len().saturating_sub(1) as f64;
    let harmonics = analysis
        .pointer("/options/harmonics")
        .and_then(Value::as_u64)
        .unwrap_or(3)
        .max(1);
    let markers = markers(analysis.get("theory"), harmonics, f_top);
    let peaks: Vec<Value> = peaks
        .and_then(|p| p.as_array().cloned())
        .unwrap_or_default()
        .into_iter()
        .filter(|p| {
            p.get("identified_hz")
                .and_then(Value::as_f64)
                .is_some_and(|f| f <= f_top)
        })
        .collect();
    Ok(Json(json!({
        "id": id,
        "kind": which,
        "level": lvl,
        "df": df,
        "fmax": f_top,
        "amplitude": amplitude,
        "markers": markers,
        "peaks": peaks,
    }))
    .into_response())
}

/// Theoretical characteristic frequencies and their harmonics up to `f_top`.
fn markers(theory: Option<&Value>, harmonics: u64, f_top: f64) -> Vec<Value> {
    let Some(Value::Object(t)) = theory else {
        return vec![];
    };
    let mut out = vec![];
    for (name, f) in t {
        let Some(f) = f.as_f64().filter(|f| *f > 0.0) else {
            continue;
        };
        let name = name.trim_end_matches("_hz");
        for h in 1..=harmonics {
            let fh = f * h as f64;
            if fh <= f_top {
                out.push(json!({ "name": name, "harmonic": h, "frequency": fh }));
            }
        }
    }
    out
}

macro_rules! kind_handlers {
    ($kind:expr, $get:ident, $list:ident, $cancel:ident, $delete:ident, $result:ident, $spectra:ident) => {
        pub async fn $get(
            State(s): State<AppState>,
            Path(id): Path<String>,
            headers: HeaderMap,
            RawQuery(q): RawQuery,
        ) -> ApiResult<Response> {
            get_job(s, $kind, id, headers, q).await
        }
        pub async fn $list(
            State(s): State<AppState>,
            RawQuery(q): RawQuery,
        ) -> ApiResult<Response> {
            list(s, $kind, q).await
        }
        pub async fn $cancel(
            State(s): State<AppState>,
            Path(id): Path<String>,
        ) -> ApiResult<Response> {
            cancel(s, $kind, id).await
        }
        pub async fn $delete(
            State(s): State<AppState>,
            Path(id): Path<String>,
        ) -> ApiResult<Response> {
            delete(s, $kind, id).await
        }
        pub async fn $result(
            State(s): State<AppState>,
            Path(id): Path<String>,
        ) -> ApiResult<Response> {
            result(s, $kind, id).await
        }
        pub async fn $spectra(
            State(s): State<AppState>,
            Path(id): Path<String>,
            RawQuery(q): RawQuery,
        ) -> ApiResult<Response> {
            spectra(s, $kind, id, q).await
        }
    };
}

kind_handlers!(
    JobKind::Simulation,
    get_simulation,
    list_simulations,
    cancel_simulation,
    delete_simulation,
    simulation_result,
    simulation_spectra
);
kind_handlers!(
    JobKind::Analysis,
    get_analysis,
    list_analyses,
    cancel_analysis,
    delete_analysis,
    analysis_result,
    analysis_spectra
);

/// Queue a job, honouring `Idempotency-Key`: 202 for a new job, 200 with the original
/// job for a replay of the same request, 422 for the same key with a different request.
pub async fn enqueue(
    state: &AppState,
    headers: &HeaderMap,
    kind: JobKind,
    label: String,
    input: Value,
    blob: Option<Vec<u8>>,
) -> ApiResult<Response> {
    let key = match headers.get("idempotency-key") {
        None => None,
        Some(v) => {
            // 1-255 printable ASCII characters, not starting or ending with a space.
            let b = v.as_bytes();
            let ok = (1..=255).contains(&b.len())
                && b.iter().all(|c| (0x20..=0x7e).contains(c))
                && b[0] != b' '
                && b[b.len() - 1] != b' ';
            if !ok {
                return Err(Problem::bad_request("Idempotency-Key must be 1-255 printable ASCII characters, without leading or trailing spaces"));
            }
            Some(String::from_utf8_lossy(b).into_owned())
        }
    };
    let mut hasher = Fnv1a::default();
    hasher.write(input.to_string().as_bytes());
    if let Some(b) = &blob {
        hasher.write(b);
    }
    let new = crate::store::NewJob {
        id: uuid::Uuid::now_v7().to_string(),
        kind,
        label,
        input,
        input_blob: blob,
        // Keys are scoped by kind so the two collections do not collide.
        idempotency_key: key.map(|k| format!("{}:{k}", kind.as_str())),
        request_hash: format!("{:016x}", hasher.0),
    };
    let created = state.store.create_job(new, state.config.max_queued).await?;
    if created.created {
        state.wake.notify_waiters();
        Ok(job_response(StatusCode::ACCEPTED, &created.job))
    } else {
        Ok(job_response(StatusCode::OK, &created.job))
    }
}

/// FNV-1a, 64 bit: a stable fingerprint of a request (not a security boundary).
struct Fnv1a(u64);

impl Default for Fnv1a {
    fn default() -> Self {
        Fnv1a(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv1a {
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 ^= *b as u64;
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }
}
