//! Jobs as submitters and readers see them: admission, reads and listings, cancel,
//! delete, artifacts, the stored size and the counts, and retention.

use super::backend::Backend;
use super::rows::*;
use super::statement::{BindParam, RowsAffected};
use crate::store::contract::StoreError;
use crate::store::model::*;
use sqlx::Pool;

/// What a cancel sets on a job: queued ones end cancelled (finished at `$2`, error `$3`),
/// running ones are flagged for their worker's next heartbeat.
pub(super) const CANCEL_SET: &str =
    "state = CASE WHEN state = 'queued' THEN 'cancelled' ELSE state END, \
     finished_at = CASE WHEN state = 'queued' THEN $2 ELSE finished_at END, \
     error = CASE WHEN state = 'queued' THEN $3 ELSE error END, \
     cancel_requested = TRUE";

/// Jobs a cancel acts on: queued ones, and running ones not yet asked.
pub(super) const CANCELLABLE: &str =
    "(state = 'queued' OR (state = 'running' AND NOT cancel_requested))";

pub(super) async fn ping<B: Backend>(pool: &Pool<B>) -> Result<(), StoreError> {
    sqlx::query("SELECT 1").execute(B::on_pool(pool)).await?;
    Ok(())
}

pub(super) async fn create<B: Backend>(
    pool: &Pool<B>,
    job: NewJob,
    max_queued: i64,
    tenant_max_queued: i64,
) -> Result<Created, StoreError> {
    let now = now_ms();
    let scoped_key = job
        .idempotency_key
        .as_deref()
        .map(|k| scoped_idempotency_key(&job.tenant, k));
    let mut tx = B::begin_locked(pool).await?;
    // Under the lock the count is exact; a duplicate key inserts nothing.
    let inserted = sqlx::query(
        "INSERT INTO jobs (id, tenant, kind, state, input, input_blob, idempotency_key, request_hash, label, created_at, updated_at, input_format) \
         SELECT $1, $2, $3, 'queued', $4, $5, $6, $7, $8, $9, $9, $11 \
         WHERE (SELECT COUNT(*) FROM jobs WHERE state = 'queued') < $10 \
         AND (SELECT COUNT(*) FROM jobs WHERE state = 'queued' AND tenant = $2) < $12 \
         ON CONFLICT (idempotency_key) DO NOTHING",
    )
    .param(&job.id)
    .param(&job.tenant)
    .param(job.kind.as_str())
    .param(job.input.to_string())
    .param(job.input_blob.as_deref())
    .param(scoped_key.as_deref())
    .param(&job.request_hash)
    .param(&job.label)
    .param(now)
    .param(max_queued)
    .param(job.input_format)
    .param(tenant_max_queued)
    .execute(B::on(&mut *tx))
    .await?
    .rows_affected();
    tx.commit().await?;
    if inserted == 1 {
        let job = fetch(pool, &job.id)
            .await?
            .ok_or_else(|| StoreError::NotFound(job.id.clone()))?;
        return Ok(Created { job, created: true });
    }
    if let Some(key) = &scoped_key {
        let row = sqlx::query("SELECT id, request_hash, kind FROM jobs WHERE idempotency_key = $1")
            .param(key)
            .fetch_optional(B::on_pool(pool))
            .await?;
        if let Some(r) = row {
            let stored = (r.text("id")?, r.opt_text("request_hash")?, r.text("kind")?);
            let id = replay_of(stored, &job)?;
            let existing = fetch(pool, &id).await?.ok_or(StoreError::NotFound(id))?;
            return Ok(Created {
                job: existing,
                created: false,
            });
        }
    }
    let tenant_queued: i64 =
        sqlx::query("SELECT COUNT(*) AS n FROM jobs WHERE state = 'queued' AND tenant = $1")
            .param(&job.tenant)
            .fetch_one(B::on_pool(pool))
            .await?
            .int("n")?;
    if tenant_queued >= tenant_max_queued {
        return Err(StoreError::TenantQueueFull(tenant_queued));
    }
    Err(StoreError::QueueFull(counts(pool).await?.queued))
}

pub(super) async fn fetch<B: Backend>(pool: &Pool<B>, id: &str) -> Result<Option<Job>, StoreError> {
    let row = sqlx::query(&format!("SELECT {JOB_COLUMNS} FROM jobs WHERE id = $1"))
        .param(id)
        .fetch_optional(B::on_pool(pool))
        .await?;
    row.map(|r| job_from_row(&r)).transpose()
}

pub(super) async fn get<B: Backend>(pool: &Pool<B>, id: &str) -> Result<Job, StoreError> {
    fetch(pool, id)
        .await?
        .ok_or_else(|| StoreError::NotFound(id.to_string()))
}

pub(super) async fn list<B: Backend>(pool: &Pool<B>, f: &ListFilter) -> Result<Page, StoreError> {
    let limit = f.limit.clamp(1, 1000);
    // The casts type the NULL tests (PostgreSQL cannot infer a bare `$1 IS NULL`).
    let rows = sqlx::query(&format!(
        "SELECT {JOB_COLUMNS} FROM jobs \
         WHERE (CAST($1 AS TEXT) IS NULL OR kind = $1) AND (CAST($2 AS TEXT) IS NULL OR state = $2) \
           AND (CAST($3 AS BIGINT) IS NULL OR seq < $3) AND (CAST($5 AS TEXT) IS NULL OR tenant = $5) \
         ORDER BY seq DESC LIMIT $4"
    ))
    .param(f.kind.map(|k| k.as_str()))
    .param(f.state.map(|s| s.as_str()))
    .param(f.before)
    .param(limit + 1)
    .param(f.tenant.as_deref())
    .fetch_all(B::on_pool(pool))
    .await?;
    let jobs = rows
        .iter()
        .map(job_from_row)
        .collect::<Result<Vec<_>, _>>()?;
    let (jobs, next) = page_of(jobs, limit, |j| j.seq);
    Ok(Page { jobs, next })
}

pub(super) async fn request_cancel<B: Backend>(
    pool: &Pool<B>,
    id: &str,
) -> Result<Job, StoreError> {
    let now = now_ms();
    // One statement, so a job requeued meanwhile (a lease recovery elsewhere) is judged
    // as it is now: queued ends cancelled, running gets the flag.
    let row = sqlx::query(&format!(
        "UPDATE jobs SET {CANCEL_SET}, updated_at = $2, version = version + 1 \
         WHERE id = $1 AND {CANCELLABLE} RETURNING state"
    ))
    .param(id)
    .param(now)
    .param(cancelled_while_queued(None))
    .fetch_optional(B::on_pool(pool))
    .await?;
    let done = match row {
        Some(r) => r.text("state")? == "cancelled",
        None => false,
    };
    cancel_answer(get(pool, id).await?, done)
}

pub(super) async fn delete<B: Backend>(pool: &Pool<B>, id: &str) -> Result<(), StoreError> {
    // Under the lock: a study being created cannot take this job as a shared point
    // between the check and the delete.
    let mut tx = B::begin_locked(pool).await?;
    let n = sqlx::query(
        "DELETE FROM jobs WHERE id = $1 AND state IN ('succeeded', 'failed', 'cancelled') \
         AND NOT EXISTS (SELECT 1 FROM study_points WHERE job_id = jobs.id)",
    )
    .param(id)
    .execute(B::on(&mut *tx))
    .await?
    .rows_affected();
    if n == 1 {
        tx.commit().await?;
        return Ok(());
    }
    let study = sqlx::query("SELECT study_id FROM study_points WHERE job_id = $1 LIMIT 1")
        .param(id)
        .fetch_optional(B::on(&mut *tx))
        .await?
        .map(|r| r.text("study_id"))
        .transpose()?;
    tx.rollback().await?;
    Err(delete_refusal(get(pool, id).await?, study))
}

pub(super) async fn artifact<B: Backend>(
    pool: &Pool<B>,
    id: &str,
    name: &str,
) -> Result<Option<Artifact>, StoreError> {
    let row = sqlx::query("SELECT name, meta, data FROM artifacts WHERE job_id = $1 AND name = $2")
        .param(id)
        .param(name)
        .fetch_optional(B::on_pool(pool))
        .await?;
    row.map(|r| artifact_from_row(id, &r)).transpose()
}

pub(super) async fn stored_bytes<B: Backend>(pool: &Pool<B>) -> Result<i64, StoreError> {
    // length() counts characters of text (JSON, nearly all ASCII) and bytes of a blob
    // (bytea), in both databases; both read a large value's size from its header.
    let jobs = sqlx::query(
        "SELECT CAST(COALESCE(SUM(length(input) + COALESCE(length(input_blob), 0) \
             + COALESCE(length(result), 0) + COALESCE(length(stats), 0)), 0) AS BIGINT) AS n FROM jobs",
    )
    .fetch_one(B::on_pool(pool))
    .await?
    .int("n")?;
    let artifacts = sqlx::query(
        "SELECT CAST(COALESCE(SUM(length(data) + length(meta)), 0) AS BIGINT) AS n FROM artifacts",
    )
    .fetch_one(B::on_pool(pool))
    .await?
    .int("n")?;
    Ok(jobs + artifacts)
}

pub(super) async fn counts<B: Backend>(pool: &Pool<B>) -> Result<StateCounts, StoreError> {
    let rows = sqlx::query("SELECT state, COUNT(*) AS n FROM jobs GROUP BY state")
        .fetch_all(B::on_pool(pool))
        .await?;
    let mut c = StateCounts::default();
    for r in rows {
        if let Some(st) = JobState::parse(&r.text("state")?) {
            c.set(st, r.int("n")?);
        }
    }
    Ok(c)
}

pub(super) async fn expire<B: Backend>(
    pool: &Pool<B>,
    before_ms: i64,
) -> Result<(u64, u64), StoreError> {
    let mut tx = B::begin_locked(pool).await?;
    // a study goes when every point's job finished before the cutoff (its points go
    // with it: ON DELETE CASCADE)
    let studies = sqlx::query(
        "DELETE FROM studies WHERE updated_at < $1 AND NOT EXISTS ( \
             SELECT 1 FROM study_points sp JOIN jobs j ON j.id = sp.job_id \
             WHERE sp.study_id = studies.id \
               AND (j.state NOT IN ('succeeded', 'failed', 'cancelled') OR j.finished_at >= $1))",
    )
    .param(before_ms)
    .execute(B::on(&mut *tx))
    .await?
    .rows_affected();
    // then the finished jobs no study holds any more (artifacts: ON DELETE CASCADE)
    let jobs = sqlx::query(
        "DELETE FROM jobs WHERE state IN ('succeeded', 'failed', 'cancelled') \
             AND finished_at < $1 \
             AND NOT EXISTS (SELECT 1 FROM study_points sp WHERE sp.job_id = jobs.id)",
    )
    .param(before_ms)
    .execute(B::on(&mut *tx))
    .await?
    .rows_affected();
    tx.commit().await?;
    Ok((jobs, studies))
}
