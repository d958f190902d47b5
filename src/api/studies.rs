//! `/v1/studies`: parameter studies, each point a simulation job; their table and plots.

use super::caller::Caller;
use super::extract::{parse_bounded, require_json, QueryParams};
use super::job_resource::{long_poll, paging};
use super::openapi::params::{IfNoneMatch, PlotName, StudyId, StudyListQuery, WaitQuery};
use super::openapi::responses::{
    BadRequest, Conflict, Invalid, NotFound, QueueFull, TooLarge, Unavailable, UnsupportedMediaType,
};
use super::problem::{ApiResult, FieldProblem, Problem};
use super::state::AppState;
use super::study_views::{design_of, rows, study_etag, study_location, view, StudyPage, StudyView};
use crate::jobs::artifacts::spectrum_artifact_name;
use crate::store::blob::decode_f32le;
use crate::store::{
    ArtifactMeta, JobKind, NewJob, NewStudy, NewStudyPoint, StoreError, Study, INPUT_FORMAT,
};
use crate::studies::charts::{draw, plot_names, row_keys, PointSpectrum};
use crate::studies::scene_key;
use axum::body::Bytes;
use axum::extract::{Path, RawQuery, State};
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use bearing_core::study::{plan, to_csv, StudyRequest, StudyTable, StudyTableRow};

/// Queue a parameter study
///
/// A `base` scene (as for simulations: `scene`, or `preset` with `fault_case` and
/// `overrides`) and a `design`: a `grid` or `one_at_a_time` design over scene fields named
/// by JSON pointer, optionally repeated per fault case, or a `named` design shipped with
/// the service (`paper-trends`: Figures 23-28; `table2`: the paper's nine compound-fault
/// sizes; `sensitivity`: the trends' end points under lubricant variants), optionally
/// under lubricant `variants`. Every point is validated before anything is queued; a problem names the point
/// (`points[3].scene.operating.axial_load`). Each point runs as a simulation job; points
/// with identical scenes, in this study or in earlier ones still queued, running or
/// succeeded, share one job.
#[utoipa::path(
    post,
    path = "/v1/studies",
    tag = "studies",
    operation_id = "submitStudy",
    request_body(
        content = StudyRequest,
        examples(("table2" = (
            summary = "Table 2's nine compound-fault sizes, 50 ms each",
            value = json!({"base": {"preset": "h7005c", "overrides": {"solver": {"duration": 0.05}}}, "design": {"type": "named", "name": "table2"}})
        )), ("axial" = (
            summary = "Outer fault, three axial loads",
            value = json!({"base": {"preset": "h7005c", "fault_case": "outer", "overrides": {"solver": {"duration": 0.05}}}, "design": {"type": "one_at_a_time", "factors": [{"name": "axial_load", "pointer": "/operating/axial_load", "values": [200.0, 400.0, 800.0]}]}})
        )))
    ),
    responses(
        (status = 202, description = "Queued.", body = StudyView, headers(
            ("Location" = String, description = "Path of the study."),
            ("ETag" = String, description = "Version of the study; send it back in If-None-Match.")
        ), links(
            ("getStudy" = (operation_id = "getStudy", parameters(("id" = "$response.body#/id")))),
            ("getStudyTable" = (operation_id = "getStudyTable", parameters(("id" = "$response.body#/id")))),
            ("cancelStudy" = (operation_id = "cancelStudy", parameters(("id" = "$response.body#/id"))))
        )),
        (status = 400, response = BadRequest),
        (status = 413, response = TooLarge),
        (status = 415, response = UnsupportedMediaType),
        (status = 422, response = Invalid),
        (status = 429, response = QueueFull),
        (status = 503, response = Unavailable),
    )
)]
pub async fn submit(
    State(state): State<AppState>,
    caller: Caller,
    headers: HeaderMap,
    body: Bytes,
) -> ApiResult<Response> {
    require_json(&headers)?;
    super::submission::check_storage(&state).await?;
    let value = parse_bounded(&body)?;
    let req: StudyRequest = super::extract::from_value(value, "")?;
    let request_json = serde_json::to_value(&req).map_err(|e| Problem::internal(e.to_string()))?;
    // Expanding validates every point; each distinct scene must also have an equilibrium
    // at t = 0 (one quasi-static solve each), off the async threads.
    let config = state.config.clone();
    let plan = tokio::task::spawn_blocking(move || -> Result<_, Vec<FieldProblem>> {
        let plan = plan(&req).map_err(|ps| {
            ps.into_iter()
                .map(|p| FieldProblem {
                    path: p.path,
                    message: p.message,
                })
                .collect::<Vec<_>>()
        })?;
        let keys: Vec<String> = plan.points.iter().map(|p| scene_key(&p.scene)).collect();
        let mut seen = std::collections::HashSet::new();
        let mut problems = Vec::new();
        for (i, (p, key)) in plan.points.iter().zip(&keys).enumerate() {
            if !seen.insert(key) {
                continue;
            }
            problems.extend(super::budget::over_budget(
                &p.scene,
                &config,
                &format!("points[{i}].scene"),
            ));
            if let Err(e) = bearing_core::simulation::check_start(&p.scene) {
                problems.extend(e.0.into_iter().map(|f| FieldProblem {
                    path: super::problem::join_path(&format!("points[{i}].scene"), &f.path),
                    message: f.message,
                }));
            }
            if problems.len() > 50 {
                break;
            }
        }
        if problems.is_empty() {
            Ok((plan, keys))
        } else {
            Err(problems)
        }
    })
    .await
    .map_err(|e| Problem::internal(format!("study planning failed: {e}")))?
    .map_err(Problem::validation)?;

    let id = uuid::Uuid::now_v7().to_string();
    let (plan, keys) = plan;
    let n = plan.points.len();
    let mut points = Vec::with_capacity(n);
    for (i, (p, key)) in plan.points.iter().zip(keys).enumerate() {
        let input = serde_json::to_value(&p.scene).map_err(|e| Problem::internal(e.to_string()))?;
        points.push(NewStudyPoint {
            spec: serde_json::to_value(&p.spec).map_err(|e| Problem::internal(e.to_string()))?,
            job: NewJob {
                id: uuid::Uuid::now_v7().to_string(),
                tenant: caller.tenant().to_string(),
                kind: JobKind::Simulation,
                label: format!("{} [{} point {i}]", p.scene.name, plan.name),
                input,
                input_blob: None,
                idempotency_key: None,
                request_hash: key.clone(),
                input_format: INPUT_FORMAT,
            },
            scene_key: key,
        });
    }
    let created = state
        .store
        .create_study(
            NewStudy {
                id,
                tenant: caller.tenant().to_string(),
                label: plan.name.clone(),
                request: request_json,
                design: serde_json::to_value(&plan.design)
                    .map_err(|e| Problem::internal(e.to_string()))?,
                points,
            },
            state.config.max_queued,
        )
        .await?;
    state
        .metrics
        .study_created(n, created.queued, created.shared);
    if created.queued > 0 {
        state.wake.notify_waiters();
    }
    study_response(StatusCode::ACCEPTED, &created.study)
}

fn study_response(status: StatusCode, study: &Study) -> ApiResult<Response> {
    let v = view(study)?;
    let mut res = (status, Json(v)).into_response();
    let h = res.headers_mut();
    if let Ok(v) = HeaderValue::from_str(&study_etag(study)) {
        h.insert(header::ETAG, v);
    }
    if let Ok(v) = HeaderValue::from_str(&study_location(&study.id)) {
        h.insert(header::LOCATION, v);
    }
    h.insert(header::CACHE_CONTROL, HeaderValue::from_static("no-cache"));
    Ok(res)
}

/// State, progress and points of a study
///
/// Progress counts points and simulated time. Send the last `ETag` in `If-None-Match` for
/// a bodiless 304 while nothing changed; with `wait` (s) an unchanged study is held until
/// a point changes or `wait` passes (long poll).
#[utoipa::path(
    get,
    path = "/v1/studies/{id}",
    tag = "studies",
    operation_id = "getStudy",
    params(StudyId, IfNoneMatch, WaitQuery),
    responses(
        (status = 200, description = "The study.", body = StudyView, headers(
            ("ETag" = String, description = "Version of the study and its points."),
            ("Location" = String, description = "Path of the study.")
        )),
        (status = 304, description = "Unchanged since the ETag given.", headers(
            ("ETag" = String, description = "Version of the study.")
        )),
        (status = 400, response = BadRequest),
        (status = 404, response = NotFound),
    )
)]
pub async fn get(
    State(state): State<AppState>,
    caller: Caller,
    Path(id): Path<String>,
    headers: HeaderMap,
    RawQuery(q): RawQuery,
) -> ApiResult<Response> {
    long_poll(
        &headers,
        q.as_deref(),
        || load_study(&state, &caller, &id),
        study_etag,
        |st| super::study_views::study_state(st).is_finished(),
        |st| study_response(StatusCode::OK, st),
    )
    .await
}

/// Most points a page of studies shows: about 1 MB of JSON (a point's view is about 0.5
/// KiB). Without it, 100 studies of 500 points made a 25 MB page.
pub const MAX_LISTED_POINTS: usize = 2000;

/// List studies, newest first
#[utoipa::path(
    get,
    path = "/v1/studies",
    tag = "studies",
    operation_id = "listStudies",
    params(StudyListQuery),
    responses(
        (status = 200, description = "One page.", body = StudyPage),
        (status = 400, response = BadRequest),
    )
)]
pub async fn list(
    State(state): State<AppState>,
    caller: Caller,
    RawQuery(q): RawQuery,
) -> ApiResult<Response> {
    let q = QueryParams::parse(q.as_deref())?;
    let (limit, before) = paging(&q, 20, 100)?;
    let scope = caller.list_scope();
    let page = state
        .store
        .list_studies(scope.as_deref(), before, limit)
        .await?;
    // A page ends early once it holds MAX_LISTED_POINTS points (a study has up to 500):
    // its cursor continues after the last study shown.
    let mut points = 0;
    let mut next = page.next;
    let mut items = Vec::new();
    for (i, study) in page.studies.iter().enumerate() {
        points += study.points.len();
        if i > 0 && points > MAX_LISTED_POINTS {
            next = Some(page.studies[i - 1].seq);
            break;
        }
        items.push(view(study)?);
    }
    Ok(Json(StudyPage {
        items,
        next_cursor: next.map(|n| n.to_string()),
    })
    .into_response())
}

/// Cancel a study's unfinished points
///
/// Queued points are cancelled at once, running ones within a second. A point another
/// study shares keeps running for it.
#[utoipa::path(
    post,
    path = "/v1/studies/{id}/cancel",
    tag = "studies",
    operation_id = "cancelStudy",
    params(StudyId),
    responses(
        (status = 202, description = "Cancelled, or cancel requested for running points.", body = StudyView),
        (status = 404, response = NotFound),
        (status = 409, response = Conflict),
    )
)]
pub async fn cancel(
    State(state): State<AppState>,
    caller: Caller,
    Path(id): Path<String>,
) -> ApiResult<Response> {
    load_study(&state, &caller, &id).await?;
    let study = state.store.cancel_study(&id).await?;
    study_response(StatusCode::ACCEPTED, &study)
}

/// Delete a finished study and the points no other study shares
#[utoipa::path(
    delete,
    path = "/v1/studies/{id}",
    tag = "studies",
    operation_id = "deleteStudy",
    params(StudyId),
    responses(
        (status = 204, description = "Deleted."),
        (status = 404, response = NotFound),
        (status = 409, response = Conflict),
    )
)]
pub async fn delete(
    State(state): State<AppState>,
    caller: Caller,
    Path(id): Path<String>,
) -> ApiResult<Response> {
    load_study(&state, &caller, &id).await?;
    state.store.delete_study(&id).await?;
    Ok(StatusCode::NO_CONTENT.into_response())
}

/// The study's table: one row per point
///
/// Factor values; theoretical BPFO and BPFI (eq. 37 at the nominal and at the loaded
/// contact angle) and from the cage speed; the lines identified in the raw and in the best
/// DTCWT component's envelope spectra with their errors, prominence and detection flags;
/// the cage's speed, slip and whirl; the run time. Rows of unfinished or failed points
/// have a null `result` (and an `error`). `Accept: text/csv` gives the same as CSV.
#[utoipa::path(
    get,
    path = "/v1/studies/{id}/table",
    tag = "studies",
    operation_id = "getStudyTable",
    params(StudyId),
    responses(
        (status = 200, description = "The table.", content(
            (StudyTable = "application/json"),
            (String = "text/csv")
        )),
        (status = 404, response = NotFound),
    )
)]
pub async fn table(
    State(state): State<AppState>,
    caller: Caller,
    Path(id): Path<String>,
    headers: HeaderMap,
) -> ApiResult<Response> {
    let study = load_study(&state, &caller, &id).await?;
    let design = design_of(&study)?;
    let table = StudyTable {
        id: study.id.clone(),
        name: study.label.clone(),
        factors: design.factors.iter().map(|f| f.name.clone()).collect(),
        rows: rows(&study)?,
    };
    let csv = headers
        .get(header::ACCEPT)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|a| a.contains("text/csv"));
    if csv {
        let mut res = to_csv(&table).into_response();
        res.headers_mut().insert(
            header::CONTENT_TYPE,
            HeaderValue::from_static("text/csv; charset=utf-8"),
        );
        return Ok(res);
    }
    Ok(Json(table).into_response())
}

/// One of the study's plots, as SVG
///
/// `{factor}-{fault case}.svg` for each factor line (theoretical and identified frequency
/// on the left axis, error in % on the right, as in Figures 23-28), and `spectra.svg`: the
/// best DTCWT component's envelope spectrum of every succeeded point with BPFO and BPFI
/// markers (as in Figure 17). The study's `links` list the names.
#[utoipa::path(
    get,
    path = "/v1/studies/{id}/plots/{name}",
    tag = "studies",
    operation_id = "getStudyPlot",
    params(StudyId, PlotName),
    responses(
        (status = 200, description = "The chart.", content_type = "image/svg+xml", body = String),
        (status = 404, response = NotFound),
        (status = 409, response = Conflict),
    )
)]
pub async fn plot(
    State(state): State<AppState>,
    caller: Caller,
    Path((id, name)): Path<(String, String)>,
) -> ApiResult<Response> {
    let study = load_study(&state, &caller, &id).await?;
    let design = design_of(&study)?;
    let rows = rows(&study)?;
    // the best components' spectra of the succeeded points, read before drawing
    let mut spectra = std::collections::HashMap::new();
    if name == crate::studies::charts::SPECTRA_PLOT {
        for (p, r) in study.points.iter().zip(&rows) {
            let Some(res) = &r.result else { continue };
            let level = res.bpfo.best_level;
            if let Some(a) = state
                .store
                .get_artifact(&p.job.id, &spectrum_artifact_name(Some(level)))
                .await?
            {
                if let ArtifactMeta::Spectrum { df, .. } = a.meta {
                    let amplitude = decode_f32le(&a.data);
                    spectra.insert(
                        r.index,
                        PointSpectrum {
                            df,
                            amplitude,
                            level,
                        },
                    );
                }
            }
        }
    }
    let mut lookup = |r: &StudyTableRow| spectra.remove(&r.index);
    let svg = match draw(&study.label, &design, &rows, &name, &mut lookup) {
        None => {
            return Err(Problem::not_found(format!(
                "study {id} has no plot '{name}'; it has {}",
                plot_names(&design, row_keys(&rows)).join(", ")
            )))
        }
        Some(Err(e)) => {
            use super::study_views::StudyState;
            // the problem's job_state takes the job states' names, which a study's share
            let state = match super::study_views::study_state(&study) {
                StudyState::Queued => "queued",
                StudyState::Running => "running",
                StudyState::Succeeded => "succeeded",
                StudyState::Failed => "failed",
                StudyState::Cancelled => "cancelled",
            };
            return Err(Problem::conflict(format!("study {id}: {e}"), Some(state)));
        }
        Some(Ok(svg)) => svg,
    };
    Ok(svg_response(svg))
}

pub fn svg_response(svg: String) -> Response {
    let mut res = svg.into_response();
    res.headers_mut().insert(
        header::CONTENT_TYPE,
        HeaderValue::from_static("image/svg+xml"),
    );
    res
}

/// The study, if the caller may see it; 404 otherwise (as for an unknown id).
async fn load_study(state: &AppState, caller: &Caller, id: &str) -> ApiResult<Study> {
    let study = state.store.get_study(id).await?;
    if !caller.may_see(&study.tenant) {
        return Err(StoreError::StudyNotFound(id.to_string()).into());
    }
    Ok(study)
}
