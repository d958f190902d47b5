//! Studies: a study and its points stored, and shared points queued once, in one
//! transaction; read, listed, cancelled and deleted with the points no other study holds.

use super::backend::Backend;
use super::jobs::{CANCELLABLE, CANCEL_SET};
use super::rows::*;
use super::statement::{BindParam, RowsAffected};
use crate::store::contract::StoreError;
use crate::store::model::*;
use sqlx::Pool;

pub(super) async fn create<B: Backend>(
    pool: &Pool<B>,
    study: NewStudy,
    max_queued: i64,
) -> Result<StudyCreated, StoreError> {
    let now = now_ms();
    let mut tx = B::begin_locked(pool).await?;
    sqlx::query(
        "INSERT INTO studies (id, tenant, label, request, design, created_at, updated_at) \
         VALUES ($1, $2, $3, $4, $5, $6, $6)",
    )
    .param(&study.id)
    .param(&study.tenant)
    .param(&study.label)
    .param(study.request.to_string())
    .param(study.design.to_string())
    .param(now)
    .execute(B::on(&mut *tx))
    .await?;
    let waiting = sqlx::query("SELECT COUNT(*) AS n FROM jobs WHERE state = 'queued'")
        .fetch_one(B::on(&mut *tx))
        .await?
        .int("n")?;
    let mut by_key: std::collections::HashMap<String, String> = Default::default();
    let (mut queued, mut shared) = (0usize, 0usize);
    for (idx, p) in study.points.iter().enumerate() {
        let job_id = if let Some(id) = by_key.get(&p.scene_key) {
            shared += 1;
            id.clone()
        } else {
            let existing = sqlx::query(
                "SELECT id FROM jobs WHERE scene_key = $1 AND tenant = $2 AND kind = 'simulation' \
                 AND state IN ('queued', 'running', 'succeeded') AND NOT cancel_requested \
                 ORDER BY seq DESC LIMIT 1",
            )
            .param(&p.scene_key)
            .param(&study.tenant)
            .fetch_optional(B::on(&mut *tx))
            .await?
            .map(|r| r.text("id"))
            .transpose()?;
            let id = match existing {
                Some(id) => {
                    shared += 1;
                    id
                }
                None => {
                    let j = &p.job;
                    sqlx::query(
                        "INSERT INTO jobs (id, tenant, kind, state, input, request_hash, label, scene_key, created_at, updated_at, input_format) \
                         VALUES ($1, $2, $3, 'queued', $4, $5, $6, $7, $8, $8, $9)",
                    )
                    .param(&j.id)
                    .param(&study.tenant)
                    .param(j.kind.as_str())
                    .param(j.input.to_string())
                    .param(&j.request_hash)
                    .param(&j.label)
                    .param(&p.scene_key)
                    .param(now)
                    .param(j.input_format)
                    .execute(B::on(&mut *tx))
                    .await?;
                    queued += 1;
                    j.id.clone()
                }
            };
            by_key.insert(p.scene_key.clone(), id.clone());
            id
        };
        sqlx::query(
            "INSERT INTO study_points (study_id, idx, job_id, spec) VALUES ($1, $2, $3, $4)",
        )
        .param(&study.id)
        .param(idx as i64)
        .param(&job_id)
        .param(p.spec.to_string())
        .execute(B::on(&mut *tx))
        .await?;
    }
    if queued > 0 && waiting + queued as i64 > max_queued {
        tx.rollback().await?;
        return Err(StoreError::QueueFull(waiting));
    }
    tx.commit().await?;
    Ok(StudyCreated {
        study: get(pool, &study.id).await?,
        queued,
        shared,
    })
}

pub(super) async fn get<B: Backend>(pool: &Pool<B>, id: &str) -> Result<Study, StoreError> {
    let row = sqlx::query(&format!(
        "SELECT {STUDY_COLUMNS} FROM studies WHERE id = $1"
    ))
    .param(id)
    .fetch_optional(B::on_pool(pool))
    .await?
    .ok_or_else(|| StoreError::StudyNotFound(id.to_string()))?;
    let mut study = study_from_row(&row)?;
    study.points = points(pool, id).await?;
    Ok(study)
}

async fn points<B: Backend>(pool: &Pool<B>, id: &str) -> Result<Vec<StudyPointRow>, StoreError> {
    let rows = sqlx::query(&format!(
        "SELECT sp.idx AS idx, sp.spec AS spec, \
             EXISTS (SELECT 1 FROM study_points o WHERE o.job_id = sp.job_id AND o.study_id <> sp.study_id) AS others, \
             {} \
         FROM study_points sp JOIN jobs ON jobs.id = sp.job_id WHERE sp.study_id = $1 ORDER BY sp.idx",
        job_columns_of_join()
    ))
    .param(id)
    .fetch_all(B::on_pool(pool))
    .await?;
    rows.iter().map(|r| study_point_from_row(id, r)).collect()
}

pub(super) async fn list<B: Backend>(
    pool: &Pool<B>,
    tenant: Option<&str>,
    before: Option<i64>,
    limit: i64,
) -> Result<StudyPage, StoreError> {
    let limit = limit.clamp(1, 500);
    // The casts type the NULL tests (PostgreSQL cannot infer a bare `$1 IS NULL`).
    let rows = sqlx::query(&format!(
        "SELECT {STUDY_COLUMNS} FROM studies WHERE (CAST($1 AS BIGINT) IS NULL OR seq < $1) \
         AND (CAST($3 AS TEXT) IS NULL OR tenant = $3) ORDER BY seq DESC LIMIT $2"
    ))
    .param(before)
    .param(limit + 1)
    .param(tenant)
    .fetch_all(B::on_pool(pool))
    .await?;
    let mut studies = Vec::with_capacity(rows.len());
    for r in rows.iter().take(limit as usize) {
        let mut st = study_from_row(r)?;
        st.points = points(pool, &st.id).await?;
        studies.push(st);
    }
    let next = if rows.len() as i64 > limit {
        studies.last().map(|s| s.seq)
    } else {
        None
    };
    Ok(StudyPage { studies, next })
}

pub(super) async fn cancel<B: Backend>(pool: &Pool<B>, id: &str) -> Result<Study, StoreError> {
    let now = now_ms();
    let mut tx = B::begin_locked(pool).await?;
    let n = sqlx::query(
        "UPDATE studies SET cancel_requested = TRUE, version = version + 1, updated_at = $2 WHERE id = $1",
    )
    .param(id)
    .param(now)
    .execute(B::on(&mut *tx))
    .await?
    .rows_affected();
    if n == 0 {
        return Err(StoreError::StudyNotFound(id.to_string()));
    }
    let unfinished = sqlx::query(
        "SELECT COUNT(*) AS n FROM study_points sp JOIN jobs j ON j.id = sp.job_id \
         WHERE sp.study_id = $1 AND j.state IN ('queued', 'running')",
    )
    .param(id)
    .fetch_one(B::on(&mut *tx))
    .await?
    .int("n")?;
    if unfinished == 0 {
        tx.rollback().await?;
        return Err(StoreError::StudyConflict {
            id: id.to_string(),
            message: "every point has finished; nothing to cancel".into(),
        });
    }
    // Points another study (not itself cancelled) still wants keep running for it.
    let ours = "id IN (SELECT job_id FROM study_points WHERE study_id = $1) \
         AND NOT EXISTS (SELECT 1 FROM study_points o JOIN studies s ON s.id = o.study_id \
             WHERE o.job_id = jobs.id AND o.study_id <> $1 AND NOT s.cancel_requested)";
    // One statement (see jobs::request_cancel): a point requeued meanwhile is not missed.
    sqlx::query(&format!(
        "UPDATE jobs SET {CANCEL_SET}, updated_at = $2, version = version + 1 \
         WHERE {CANCELLABLE} AND {ours}"
    ))
    .param(id)
    .param(now)
    .param(cancelled_while_queued(Some(id)))
    .execute(B::on(&mut *tx))
    .await?;
    tx.commit().await?;
    get(pool, id).await
}

pub(super) async fn delete<B: Backend>(pool: &Pool<B>, id: &str) -> Result<(), StoreError> {
    let mut tx = B::begin_locked(pool).await?;
    let exists = sqlx::query("SELECT id FROM studies WHERE id = $1")
        .param(id)
        .fetch_optional(B::on(&mut *tx))
        .await?;
    if exists.is_none() {
        return Err(StoreError::StudyNotFound(id.to_string()));
    }
    let busy = sqlx::query(
        "SELECT COUNT(*) AS n FROM study_points sp JOIN jobs j ON j.id = sp.job_id \
         WHERE sp.study_id = $1 AND j.state IN ('queued', 'running') \
         AND NOT EXISTS (SELECT 1 FROM study_points o WHERE o.job_id = sp.job_id AND o.study_id <> $1)",
    )
    .param(id)
    .fetch_one(B::on(&mut *tx))
    .await?
    .int("n")?;
    if busy > 0 {
        tx.rollback().await?;
        return Err(StoreError::StudyConflict {
            id: id.to_string(),
            message: format!("{busy} of its points are queued or running; cancel it first"),
        });
    }
    let jobs = sqlx::query("SELECT DISTINCT job_id FROM study_points WHERE study_id = $1")
        .param(id)
        .fetch_all(B::on(&mut *tx))
        .await?;
    sqlx::query("DELETE FROM studies WHERE id = $1")
        .param(id)
        .execute(B::on(&mut *tx))
        .await?;
    // Its jobs go unless another study holds them (one statement each: SQLite has no
    // array parameters).
    for job in jobs {
        sqlx::query(
            "DELETE FROM jobs WHERE id = $1 AND state IN ('succeeded', 'failed', 'cancelled') \
             AND NOT EXISTS (SELECT 1 FROM study_points WHERE job_id = jobs.id)",
        )
        .param(job.text("job_id")?)
        .execute(B::on(&mut *tx))
        .await?;
    }
    tx.commit().await?;
    Ok(())
}
