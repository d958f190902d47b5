//! The queue as workers see it: claims, heartbeats, outcomes, release and the recovery of
//! lost leases. Every write after a claim is fenced on (id, owner, attempt): a worker
//! that lost its lease can never overwrite the job.

use super::backend::{lease_clock, Backend};
use super::rows::*;
use super::statement::{BindParam, RowsAffected, Statement};
use crate::store::contract::StoreError;
use crate::store::model::*;
use sqlx::Pool;

/// The row a lease still holds: the job it claimed, at the attempt it claimed, still
/// running. `$1..$3` are bound by [`fenced`].
const HELD: &str = "id = $1 AND owner = $2 AND attempt = $3 AND state = 'running'";

/// A worker's write (`sql` with [`HELD`] in its `WHERE`), bound to its lease.
fn fenced<'q, B: Backend>(sql: &'q str, lease: &'q Lease) -> Statement<'q, B> {
    sqlx::query(sql)
        .param(&lease.id)
        .param(&lease.owner)
        .param(lease.attempt)
}

/// The job the next claim takes (its `seq`), locked as the backend needs
/// ([`Backend::CLAIM_LOCK`]): a queued one whose input format is at most `$4`, of a
/// tenant running fewer than `$5` jobs; of those tenants the one running fewest first
/// (round robin: one tenant's backlog never starves another's job), then the oldest.
/// The one place that decides the order jobs are run in. Two claims at once (PostgreSQL)
/// may both count a tenant below its share and let it run one more.
fn next_claimable<B: Backend>() -> String {
    let running = "(SELECT COUNT(*) FROM jobs r WHERE r.state = 'running' AND r.tenant = q.tenant)";
    format!(
        "SELECT q.seq FROM jobs q WHERE q.state = 'queued' AND q.input_format <= $4 \
         AND {running} < $5 ORDER BY {running}, q.seq LIMIT 1{}",
        B::CLAIM_LOCK
    )
}

pub(super) async fn claim<B: Backend>(
    pool: &Pool<B>,
    owner: &str,
    lease_ms: i64,
    max_input_format: i64,
    tenant_share: i64,
) -> Result<Option<Claimed>, StoreError> {
    let now = now_ms();
    let row = sqlx::query(&format!(
        "UPDATE jobs SET state = 'running', owner = $1, lease_expires_at = {clock} + $2, attempt = attempt + 1, \
             attempt_progress = 0, claim_progress = progress, \
             started_at = COALESCE(started_at, $3), updated_at = $3, version = version + 1 \
         WHERE seq = ({next}) AND state = 'queued' \
         RETURNING id, kind, attempt, input, input_blob, cancel_requested",
        clock = lease_clock::<B>("$3"),
        next = next_claimable::<B>(),
    ))
    .param(owner)
    .param(lease_ms)
    .param(now)
    .param(max_input_format)
    .param(tenant_share.max(1))
    .fetch_optional(B::on_pool(pool))
    .await?;
    row.map(|r| claimed_from_row(owner, &r)).transpose()
}

pub(super) async fn heartbeat<B: Backend>(
    pool: &Pool<B>,
    lease: &Lease,
    progress: f64,
    lease_ms: i64,
) -> Result<Heartbeat, StoreError> {
    let now = now_ms();
    let progress = if progress.is_finite() {
        progress.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let sql = format!(
        "UPDATE jobs SET lease_expires_at = {clock} + $4, progress = {greatest}(progress, $5), \
             attempt_progress = $5, updated_at = $6, \
             version = version + (CASE WHEN progress < $5 THEN 1 ELSE 0 END) \
         WHERE {HELD} RETURNING cancel_requested",
        clock = lease_clock::<B>("$6"),
        greatest = B::GREATEST,
    );
    let row = fenced::<B>(&sql, lease)
        .param(lease_ms)
        .param(progress)
        .param(now)
        .fetch_optional(B::on_pool(pool))
        .await?;
    match row {
        Some(r) => Ok(Heartbeat {
            cancel_requested: r.flag("cancel_requested")?,
        }),
        None => Err(StoreError::LeaseLost),
    }
}

pub(super) async fn finish<B: Backend>(
    pool: &Pool<B>,
    lease: &Lease,
    outcome: Outcome,
) -> Result<(), StoreError> {
    let now = now_ms();
    let (state, progress, error, stats, result, artifacts, key) = finished_row(outcome);
    let mut tx = pool.begin().await?;
    // The fenced write first: it locks the row (PostgreSQL) or takes the write lock
    // (SQLite) until commit. A study point's key becomes the finishing worker's
    // (`Outcome::Succeeded`); a job without one (a simulation submitted on its own) keeps
    // none, so no study takes it over.
    let sql = format!(
        "UPDATE jobs SET state = $4, progress = COALESCE($5, progress), error = $6, stats = $7, result = $8, \
             finished_at = $9, updated_at = $9, owner = NULL, lease_expires_at = NULL, version = version + 1, \
             scene_key = CASE WHEN scene_key IS NULL THEN NULL ELSE COALESCE($10, scene_key) END \
         WHERE {HELD}"
    );
    let n = fenced::<B>(&sql, lease)
        .param(state)
        .param(progress)
        .param(error)
        .param(stats)
        .param(result)
        .param(now)
        .param(key)
        .execute(B::on(&mut *tx))
        .await?
        .rows_affected();
    if n == 0 {
        tx.rollback().await?;
        return Err(StoreError::LeaseLost);
    }
    for a in &artifacts {
        sqlx::query(
            "INSERT INTO artifacts (job_id, name, meta, data) VALUES ($1, $2, $3, $4) \
             ON CONFLICT (job_id, name) DO UPDATE SET meta = excluded.meta, data = excluded.data",
        )
        .param(&lease.id)
        .param(&a.name)
        .param(serde_json::to_string(&a.meta).unwrap_or_default())
        .param(a.data.as_slice())
        .execute(B::on(&mut *tx))
        .await?;
    }
    tx.commit().await?;
    Ok(())
}

pub(super) async fn release<B: Backend>(pool: &Pool<B>, lease: &Lease) -> Result<(), StoreError> {
    let sql = format!(
        "UPDATE jobs SET state = 'queued', owner = NULL, lease_expires_at = NULL, attempt = attempt - 1, \
             updated_at = $4, version = version + 1 \
         WHERE {HELD}"
    );
    let n = fenced::<B>(&sql, lease)
        .param(now_ms())
        .execute(B::on_pool(pool))
        .await?
        .rows_affected();
    if n == 0 {
        return Err(StoreError::LeaseLost);
    }
    Ok(())
}

/// How much further (a fraction of the job) an attempt must get than every earlier one for
/// its worker's death to count as headway: more than the progress between two heartbeats
/// of all but the shortest jobs, so that a job dying at one point does not seem to
/// advance because its last heartbeat fell a little later.
const HEADWAY: &str = "0.01";

pub(super) async fn recover_expired<B: Backend>(
    pool: &Pool<B>,
    max_attempts: i64,
) -> Result<u64, StoreError> {
    let now = now_ms();
    // Every process runs this. Under the lock its three statements act on one view of
    // the expired leases, and it cannot deadlock with a study's cancel, which updates
    // many of the same rows.
    let mut tx = B::begin_locked(pool).await?;
    let expired = format!(
        "state = 'running' AND lease_expires_at < {}",
        lease_clock::<B>("$1")
    );
    // A job asked to cancel is not run again: it ends cancelled.
    let cancelled = sqlx::query(&format!(
        "UPDATE jobs SET state = 'cancelled', error = $2, owner = NULL, lease_expires_at = NULL, \
             finished_at = $1, updated_at = $1, version = version + 1 \
         WHERE {expired} AND cancel_requested"
    ))
    .param(now)
    .param(CANCELLED_UNCONFIRMED)
    .execute(B::on(&mut *tx))
    .await?
    .rows_affected();
    // A worker that died is not the job's fault: the job is requeued, however often that
    // happens, as long as it gets further than before. Only deaths in a row without
    // headway (a job that kills its worker at the same point each time) stop it.
    let no_headway = format!("attempt_progress < claim_progress + {HEADWAY}");
    let failed = sqlx::query(&format!(
        "UPDATE jobs SET state = 'failed', error = $3, owner = NULL, lease_expires_at = NULL, \
             worker_deaths = worker_deaths + 1, finished_at = $1, updated_at = $1, version = version + 1 \
         WHERE {expired} AND {no_headway} AND worker_deaths + 1 >= $2"
    ))
    .param(now)
    .param(max_attempts)
    .param(poison_error(max_attempts))
    .execute(B::on(&mut *tx))
    .await?
    .rows_affected();
    let requeued = sqlx::query(&format!(
        "UPDATE jobs SET state = 'queued', owner = NULL, lease_expires_at = NULL, updated_at = $1, \
             worker_deaths = CASE WHEN {no_headway} THEN worker_deaths + 1 ELSE 0 END, \
             version = version + 1 \
         WHERE {expired}"
    ))
    .param(now)
    .execute(B::on(&mut *tx))
    .await?
    .rows_affected();
    tx.commit().await?;
    Ok(failed + cancelled + requeued)
}
