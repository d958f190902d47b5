//! [`Store`] on PostgreSQL: one queue and one store shared by several API and worker
//! machines.
//!
//! Claims take the oldest queued row with `FOR UPDATE SKIP LOCKED`, so concurrent
//! workers never wait on each other's row or take the same job. Every worker write is
//! fenced on (id, owner, attempt) as in SQLite. The operations that read a count or a
//! set of rows and then write on it (admission against `--max-queued`, study creation
//! with shared points, cancel and delete of studies, retention) run in a transaction
//! under one advisory lock: PostgreSQL's default isolation would otherwise let two of
//! them act on the same snapshot, where SQLite's single writer serialises them.

use super::contract::{Store, StoreError};
use super::migrations::additive;
use super::model::*;
use super::rows::*;
use async_trait::async_trait;
use sqlx::postgres::{PgListener, PgPool, PgPoolOptions};
use sqlx::{Postgres, Transaction};
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::Notify;

pub struct PostgresStore {
    pool: PgPool,
    /// The LISTEN task of [`Store::wake_on_new_work`], stopped with the store.
    listener: std::sync::Mutex<Option<tokio::task::AbortHandle>>,
}

impl Drop for PostgresStore {
    fn drop(&mut self) {
        if let Some(task) = self.listener.lock().ok().and_then(|mut l| l.take()) {
            task.abort();
        }
    }
}

/// The advisory lock key of the queue's structure (ASCII "bearing").
const QUEUE_LOCK: i64 = 0x62_6561_7269_6e67;

/// The database server's clock, unix ms. Leases are set and judged by one clock: with
/// each machine's own, a node whose clock ran ahead would requeue healthy jobs.
const DB_NOW_MS: &str = "(extract(epoch from clock_timestamp()) * 1000)::bigint";

/// The channel the `jobs` triggers notify when a job becomes claimable
/// (migrations/postgres/0001_schema.sql).
const QUEUE_CHANNEL: &str = "bearing_sim_queue";

/// What a cancel sets on a job: queued ones end cancelled (finished at `$2`, error `$3`),
/// running ones are flagged for their worker's next heartbeat.
const CANCEL_SET: &str = "state = CASE WHEN state = 'queued' THEN 'cancelled' ELSE state END, \
     finished_at = CASE WHEN state = 'queued' THEN $2 ELSE finished_at END, \
     error = CASE WHEN state = 'queued' THEN $3 ELSE error END, \
     cancel_requested = TRUE";

impl PostgresStore {
    /// Connect and migrate. The database must exist; its schema is created on first use
    /// (concurrent starts are safe: sqlx migrates under an advisory lock).
    pub async fn connect(url: &str) -> Result<PostgresStore, StoreError> {
        let pool = PgPoolOptions::new()
            .max_connections(8)
            .acquire_timeout(Duration::from_secs(30))
            .connect(url)
            .await?;
        additive(sqlx::migrate!("./migrations/postgres"))
            .run(&pool)
            .await?;
        Ok(PostgresStore {
            pool,
            listener: Default::default(),
        })
    }

    /// A transaction holding the queue's structure lock until it ends.
    async fn locked(&self) -> Result<Transaction<'static, Postgres>, StoreError> {
        let mut tx = self.pool.begin().await?;
        sqlx::query("SELECT pg_advisory_xact_lock($1)")
            .bind(QUEUE_LOCK)
            .execute(&mut *tx)
            .await?;
        Ok(tx)
    }

    async fn fetch_job(&self, id: &str) -> Result<Option<Job>, StoreError> {
        let row = sqlx::query(&format!("SELECT {JOB_COLUMNS} FROM jobs WHERE id = $1"))
            .bind(id)
            .fetch_optional(&self.pool)
            .await?;
        row.map(|r| job_from_row(&r)).transpose()
    }

    async fn study_points(&self, id: &str) -> Result<Vec<StudyPointRow>, StoreError> {
        let rows = sqlx::query(&format!(
            "SELECT sp.idx AS idx, sp.spec AS spec, \
                 EXISTS (SELECT 1 FROM study_points o WHERE o.job_id = sp.job_id AND o.study_id <> sp.study_id) AS others, \
                 {} \
             FROM study_points sp JOIN jobs ON jobs.id = sp.job_id WHERE sp.study_id = $1 ORDER BY sp.idx",
            job_columns_of_join()
        ))
        .bind(id)
        .fetch_all(&self.pool)
        .await?;
        rows.iter().map(|r| study_point_from_row(id, r)).collect()
    }
}

#[async_trait]
impl Store for PostgresStore {
    async fn ping(&self) -> Result<(), StoreError> {
        sqlx::query("SELECT 1").execute(&self.pool).await?;
        Ok(())
    }

    async fn wake_on_new_work(&self, wake: Arc<Notify>) -> Result<(), StoreError> {
        let mut listener = PgListener::connect_with(&self.pool).await?;
        listener.listen(QUEUE_CHANNEL).await?;
        // The listener holds one of the pool's connections for as long as it runs.
        let task = tokio::spawn(async move {
            loop {
                // recv() reconnects by itself after a dropped connection; notifications
                // sent meanwhile are lost, which the workers' polling covers.
                match listener.recv().await {
                    Ok(_) => wake.notify_waiters(),
                    Err(sqlx::Error::PoolClosed) => return,
                    Err(e) => {
                        tracing::warn!(error = %e, "LISTEN connection failed; retrying in 1 s");
                        tokio::time::sleep(Duration::from_secs(1)).await;
                    }
                }
            }
        });
        if let Ok(mut slot) = self.listener.lock() {
            if let Some(previous) = slot.replace(task.abort_handle()) {
                previous.abort();
            }
        }
        Ok(())
    }

    async fn create_job(&self, job: NewJob, max_queued: i64) -> Result<Created, StoreError> {
        let now = now_ms();
        let scoped_key = job
            .idempotency_key
            .as_deref()
            .map(|k| scoped_idempotency_key(&job.tenant, k));
        let mut tx = self.locked().await?;
        // Under the lock the count is exact; a duplicate key inserts nothing.
        let inserted = sqlx::query(
            "INSERT INTO jobs (id, tenant, kind, state, input, input_blob, idempotency_key, request_hash, label, created_at, updated_at, input_format) \
             SELECT $1, $2, $3, 'queued', $4, $5, $6, $7, $8, $9, $9, $11 \
             WHERE (SELECT COUNT(*) FROM jobs WHERE state = 'queued') < $10 \
             ON CONFLICT (idempotency_key) DO NOTHING",
        )
        .bind(&job.id)
        .bind(&job.tenant)
        .bind(job.kind.as_str())
        .bind(job.input.to_string())
        .bind(job.input_blob.as_deref())
        .bind(scoped_key.as_deref())
        .bind(&job.request_hash)
        .bind(&job.label)
        .bind(now)
        .bind(max_queued)
        .bind(job.input_format)
        .execute(&mut *tx)
        .await?
        .rows_affected();
        tx.commit().await?;
        if inserted == 1 {
            let job = self
                .fetch_job(&job.id)
                .await?
                .ok_or_else(|| StoreError::NotFound(job.id.clone()))?;
            return Ok(Created { job, created: true });
        }
        if let Some(key) = &scoped_key {
            let row: Option<(String, Option<String>, String)> = sqlx::query_as(
                "SELECT id, request_hash, kind FROM jobs WHERE idempotency_key = $1",
            )
            .bind(key)
            .fetch_optional(&self.pool)
            .await?;
            if let Some(stored) = row {
                let id = replay_of(stored, &job)?;
                let existing = self.fetch_job(&id).await?.ok_or(StoreError::NotFound(id))?;
                return Ok(Created {
                    job: existing,
                    created: false,
                });
            }
        }
        Err(StoreError::QueueFull(self.counts().await?.queued))
    }

    async fn get_job(&self, id: &str) -> Result<Job, StoreError> {
        self.fetch_job(id)
            .await?
            .ok_or_else(|| StoreError::NotFound(id.to_string()))
    }

    async fn list_jobs(&self, f: &ListFilter) -> Result<Page, StoreError> {
        let limit = f.limit.clamp(1, 1000);
        let rows = sqlx::query(&format!(
            "SELECT {JOB_COLUMNS} FROM jobs \
             WHERE ($1::text IS NULL OR kind = $1) AND ($2::text IS NULL OR state = $2) \
               AND ($3::bigint IS NULL OR seq < $3) AND ($5::text IS NULL OR tenant = $5) \
             ORDER BY seq DESC LIMIT $4"
        ))
        .bind(f.kind.map(|k| k.as_str()))
        .bind(f.state.map(|s| s.as_str()))
        .bind(f.before)
        .bind(limit + 1)
        .bind(f.tenant.as_deref())
        .fetch_all(&self.pool)
        .await?;
        let jobs = rows
            .iter()
            .map(job_from_row)
            .collect::<Result<Vec<_>, _>>()?;
        let (jobs, next) = page_of(jobs, limit, |j| j.seq);
        Ok(Page { jobs, next })
    }

    async fn request_cancel(&self, id: &str) -> Result<Job, StoreError> {
        let now = now_ms();
        // One statement, so a job requeued meanwhile (a lease recovery elsewhere) is
        // judged as it is now: queued ends cancelled, running gets the flag.
        let state: Option<String> = sqlx::query_scalar(&format!(
            "UPDATE jobs SET {CANCEL_SET}, updated_at = $2, version = version + 1 \
             WHERE id = $1 AND (state = 'queued' OR (state = 'running' AND NOT cancel_requested)) \
             RETURNING state"
        ))
        .bind(id)
        .bind(now)
        .bind(cancelled_while_queued(None))
        .fetch_optional(&self.pool)
        .await?;
        let done = state.as_deref() == Some("cancelled");
        cancel_answer(self.get_job(id).await?, done)
    }

    async fn delete_job(&self, id: &str) -> Result<(), StoreError> {
        // Under the lock: a study being created cannot take this job as a shared point
        // between the check and the delete.
        let mut tx = self.locked().await?;
        let n = sqlx::query(
            "DELETE FROM jobs WHERE id = $1 AND state IN ('succeeded', 'failed', 'cancelled') \
             AND NOT EXISTS (SELECT 1 FROM study_points WHERE job_id = jobs.id)",
        )
        .bind(id)
        .execute(&mut *tx)
        .await?
        .rows_affected();
        if n == 1 {
            tx.commit().await?;
            return Ok(());
        }
        let study: Option<String> =
            sqlx::query_scalar("SELECT study_id FROM study_points WHERE job_id = $1 LIMIT 1")
                .bind(id)
                .fetch_optional(&mut *tx)
                .await?;
        tx.rollback().await?;
        Err(delete_refusal(self.get_job(id).await?, study))
    }

    async fn claim_up_to(
        &self,
        owner: &str,
        lease_ms: i64,
        max_input_format: i64,
    ) -> Result<Option<Claimed>, StoreError> {
        let now = now_ms();
        let row = sqlx::query(&format!(
            "UPDATE jobs SET state = 'running', owner = $1, lease_expires_at = {DB_NOW_MS} + $2, attempt = attempt + 1, \
                 started_at = COALESCE(started_at, $3), updated_at = $3, version = version + 1 \
             WHERE seq = (SELECT seq FROM jobs WHERE state = 'queued' AND input_format <= $4 \
                          ORDER BY seq LIMIT 1 FOR UPDATE SKIP LOCKED) AND state = 'queued' \
             RETURNING id, kind, attempt, input, input_blob, cancel_requested"
        ))
        .bind(owner)
        .bind(lease_ms)
        .bind(now)
        .bind(max_input_format)
        .fetch_optional(&self.pool)
        .await?;
        row.map(|r| claimed_from_row(owner, &r)).transpose()
    }

    async fn heartbeat(
        &self,
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
        let cancel: Option<bool> = sqlx::query_scalar(&format!(
            "UPDATE jobs SET lease_expires_at = {DB_NOW_MS} + $4, progress = GREATEST(progress, $5), updated_at = $6, \
                 version = version + (CASE WHEN progress < $5 THEN 1 ELSE 0 END) \
             WHERE id = $1 AND owner = $2 AND attempt = $3 AND state = 'running' \
             RETURNING cancel_requested"
        ))
        .bind(&lease.id)
        .bind(&lease.owner)
        .bind(lease.attempt)
        .bind(lease_ms)
        .bind(progress)
        .bind(now)
        .fetch_optional(&self.pool)
        .await?;
        match cancel {
            Some(cancel_requested) => Ok(Heartbeat { cancel_requested }),
            None => Err(StoreError::LeaseLost),
        }
    }

    async fn finish(&self, lease: &Lease, outcome: Outcome) -> Result<(), StoreError> {
        let now = now_ms();
        let (state, progress, error, stats, result, artifacts) = finished_row(outcome);
        let mut tx = self.pool.begin().await?;
        // The fenced write first: it locks the row until commit.
        let n = sqlx::query(
            "UPDATE jobs SET state = $4, progress = COALESCE($5, progress), error = $6, stats = $7, result = $8, \
                 finished_at = $9, updated_at = $9, owner = NULL, lease_expires_at = NULL, version = version + 1 \
             WHERE id = $1 AND owner = $2 AND attempt = $3 AND state = 'running'",
        )
        .bind(&lease.id)
        .bind(&lease.owner)
        .bind(lease.attempt)
        .bind(state)
        .bind(progress)
        .bind(error)
        .bind(stats)
        .bind(result)
        .bind(now)
        .execute(&mut *tx)
        .await?
        .rows_affected();
        if n == 0 {
            tx.rollback().await?;
            return Err(StoreError::LeaseLost);
        }
        for a in artifacts {
            sqlx::query(
                "INSERT INTO artifacts (job_id, name, meta, data) VALUES ($1, $2, $3, $4) \
                 ON CONFLICT (job_id, name) DO UPDATE SET meta = EXCLUDED.meta, data = EXCLUDED.data",
            )
            .bind(&lease.id)
            .bind(&a.name)
            .bind(serde_json::to_string(&a.meta).unwrap_or_default())
            .bind(a.data)
            .execute(&mut *tx)
            .await?;
        }
        tx.commit().await?;
        Ok(())
    }

    async fn release(&self, lease: &Lease) -> Result<(), StoreError> {
        let n = sqlx::query(
            "UPDATE jobs SET state = 'queued', owner = NULL, lease_expires_at = NULL, attempt = attempt - 1, \
                 updated_at = $4, version = version + 1 \
             WHERE id = $1 AND owner = $2 AND attempt = $3 AND state = 'running'",
        )
        .bind(&lease.id)
        .bind(&lease.owner)
        .bind(lease.attempt)
        .bind(now_ms())
        .execute(&self.pool)
        .await?
        .rows_affected();
        if n == 0 {
            return Err(StoreError::LeaseLost);
        }
        Ok(())
    }

    async fn recover_expired(&self, max_attempts: i64) -> Result<u64, StoreError> {
        let now = now_ms();
        // Every process runs this. Under the lock its three statements act on one view of
        // the expired leases, and it cannot deadlock with a study's cancel, which updates
        // many of the same rows.
        let mut tx = self.locked().await?;
        let expired = format!("state = 'running' AND lease_expires_at < {DB_NOW_MS}");
        // A job asked to cancel is not run again: it ends cancelled.
        let cancelled = sqlx::query(&format!(
            "UPDATE jobs SET state = 'cancelled', error = $2, owner = NULL, lease_expires_at = NULL, \
                 finished_at = $1, updated_at = $1, version = version + 1 \
             WHERE {expired} AND cancel_requested"
        ))
        .bind(now)
        .bind(CANCELLED_UNCONFIRMED)
        .execute(&mut *tx)
        .await?
        .rows_affected();
        let failed = sqlx::query(&format!(
            "UPDATE jobs SET state = 'failed', error = $3, owner = NULL, lease_expires_at = NULL, \
                 finished_at = $1, updated_at = $1, version = version + 1 \
             WHERE {expired} AND attempt >= $2"
        ))
        .bind(now)
        .bind(max_attempts)
        .bind(lease_expired_error(max_attempts))
        .execute(&mut *tx)
        .await?
        .rows_affected();
        let requeued = sqlx::query(&format!(
            "UPDATE jobs SET state = 'queued', owner = NULL, lease_expires_at = NULL, updated_at = $1, \
                 version = version + 1 \
             WHERE {expired}"
        ))
        .bind(now)
        .execute(&mut *tx)
        .await?
        .rows_affected();
        tx.commit().await?;
        Ok(failed + cancelled + requeued)
    }

    async fn get_artifact(&self, id: &str, name: &str) -> Result<Option<Artifact>, StoreError> {
        let row =
            sqlx::query("SELECT name, meta, data FROM artifacts WHERE job_id = $1 AND name = $2")
                .bind(id)
                .bind(name)
                .fetch_optional(&self.pool)
                .await?;
        row.map(|r| artifact_from_row(id, &r)).transpose()
    }

    async fn stored_bytes(&self) -> Result<i64, StoreError> {
        // As SQLite's LENGTH(): characters of text (JSON, nearly all ASCII), bytes of
        // bytea; both read a large value's size from its header.
        let jobs: i64 = sqlx::query_scalar(
            "SELECT COALESCE(SUM(length(input) + COALESCE(octet_length(input_blob), 0) \
                 + COALESCE(length(result), 0) + COALESCE(length(stats), 0)), 0)::BIGINT FROM jobs",
        )
        .fetch_one(&self.pool)
        .await?;
        let artifacts: i64 = sqlx::query_scalar(
            "SELECT COALESCE(SUM(octet_length(data) + length(meta)), 0)::BIGINT FROM artifacts",
        )
        .fetch_one(&self.pool)
        .await?;
        Ok(jobs + artifacts)
    }

    async fn expire(&self, before_ms: i64) -> Result<(u64, u64), StoreError> {
        let mut tx = self.locked().await?;
        // a study goes when every point's job finished before the cutoff (its points go
        // with it: ON DELETE CASCADE)
        let studies = sqlx::query(
            "DELETE FROM studies WHERE updated_at < $1 AND NOT EXISTS ( \
                 SELECT 1 FROM study_points sp JOIN jobs j ON j.id = sp.job_id \
                 WHERE sp.study_id = studies.id \
                   AND (j.state NOT IN ('succeeded', 'failed', 'cancelled') OR j.finished_at >= $1))",
        )
        .bind(before_ms)
        .execute(&mut *tx)
        .await?
        .rows_affected();
        // then the finished jobs no study holds any more (artifacts: ON DELETE CASCADE)
        let jobs = sqlx::query(
            "DELETE FROM jobs WHERE state IN ('succeeded', 'failed', 'cancelled') \
                 AND finished_at < $1 \
                 AND NOT EXISTS (SELECT 1 FROM study_points sp WHERE sp.job_id = jobs.id)",
        )
        .bind(before_ms)
        .execute(&mut *tx)
        .await?
        .rows_affected();
        tx.commit().await?;
        Ok((jobs, studies))
    }

    async fn counts(&self) -> Result<StateCounts, StoreError> {
        let rows: Vec<(String, i64)> =
            sqlx::query_as("SELECT state, COUNT(*) FROM jobs GROUP BY state")
                .fetch_all(&self.pool)
                .await?;
        let mut c = StateCounts::default();
        for (s, n) in rows {
            if let Some(st) = JobState::parse(&s) {
                c.set(st, n);
            }
        }
        Ok(c)
    }

    async fn create_study(
        &self,
        study: NewStudy,
        max_queued: i64,
    ) -> Result<StudyCreated, StoreError> {
        let now = now_ms();
        let mut tx = self.locked().await?;
        sqlx::query(
            "INSERT INTO studies (id, tenant, label, request, design, created_at, updated_at) \
             VALUES ($1, $2, $3, $4, $5, $6, $6)",
        )
        .bind(&study.id)
        .bind(&study.tenant)
        .bind(&study.label)
        .bind(study.request.to_string())
        .bind(study.design.to_string())
        .bind(now)
        .execute(&mut *tx)
        .await?;
        let waiting: i64 = sqlx::query_scalar("SELECT COUNT(*) FROM jobs WHERE state = 'queued'")
            .fetch_one(&mut *tx)
            .await?;
        let mut by_key: std::collections::HashMap<String, String> = Default::default();
        let (mut queued, mut shared) = (0usize, 0usize);
        for (idx, p) in study.points.iter().enumerate() {
            let job_id = if let Some(id) = by_key.get(&p.scene_key) {
                shared += 1;
                id.clone()
            } else {
                let existing: Option<String> = sqlx::query_scalar(
                    "SELECT id FROM jobs WHERE scene_key = $1 AND tenant = $2 AND kind = 'simulation' \
                     AND state IN ('queued', 'running', 'succeeded') AND NOT cancel_requested \
                     ORDER BY seq DESC LIMIT 1",
                )
                .bind(&p.scene_key)
                .bind(&study.tenant)
                .fetch_optional(&mut *tx)
                .await?;
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
                        .bind(&j.id)
                        .bind(&study.tenant)
                        .bind(j.kind.as_str())
                        .bind(j.input.to_string())
                        .bind(&j.request_hash)
                        .bind(&j.label)
                        .bind(&p.scene_key)
                        .bind(now)
                        .bind(j.input_format)
                        .execute(&mut *tx)
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
            .bind(&study.id)
            .bind(idx as i64)
            .bind(&job_id)
            .bind(p.spec.to_string())
            .execute(&mut *tx)
            .await?;
        }
        if queued > 0 && waiting + queued as i64 > max_queued {
            tx.rollback().await?;
            return Err(StoreError::QueueFull(waiting));
        }
        tx.commit().await?;
        Ok(StudyCreated {
            study: self.get_study(&study.id).await?,
            queued,
            shared,
        })
    }

    async fn get_study(&self, id: &str) -> Result<Study, StoreError> {
        let row = sqlx::query(&format!(
            "SELECT {STUDY_COLUMNS} FROM studies WHERE id = $1"
        ))
        .bind(id)
        .fetch_optional(&self.pool)
        .await?
        .ok_or_else(|| StoreError::StudyNotFound(id.to_string()))?;
        let mut study = study_from_row(&row)?;
        study.points = self.study_points(id).await?;
        Ok(study)
    }

    async fn list_studies(
        &self,
        tenant: Option<&str>,
        before: Option<i64>,
        limit: i64,
    ) -> Result<StudyPage, StoreError> {
        let limit = limit.clamp(1, 500);
        let rows = sqlx::query(&format!(
            "SELECT {STUDY_COLUMNS} FROM studies WHERE ($1::bigint IS NULL OR seq < $1) \
             AND ($3::text IS NULL OR tenant = $3) ORDER BY seq DESC LIMIT $2"
        ))
        .bind(before)
        .bind(limit + 1)
        .bind(tenant)
        .fetch_all(&self.pool)
        .await?;
        let mut studies = Vec::with_capacity(rows.len());
        for r in rows.iter().take(limit as usize) {
            let mut st = study_from_row(r)?;
            st.points = self.study_points(&st.id).await?;
            studies.push(st);
        }
        let next = if rows.len() as i64 > limit {
            studies.last().map(|s| s.seq)
        } else {
            None
        };
        Ok(StudyPage { studies, next })
    }

    async fn cancel_study(&self, id: &str) -> Result<Study, StoreError> {
        let now = now_ms();
        let mut tx = self.locked().await?;
        let n = sqlx::query(
            "UPDATE studies SET cancel_requested = TRUE, version = version + 1, updated_at = $2 WHERE id = $1",
        )
        .bind(id)
        .bind(now)
        .execute(&mut *tx)
        .await?
        .rows_affected();
        if n == 0 {
            return Err(StoreError::StudyNotFound(id.to_string()));
        }
        let unfinished: i64 = sqlx::query_scalar(
            "SELECT COUNT(*) FROM study_points sp JOIN jobs j ON j.id = sp.job_id \
             WHERE sp.study_id = $1 AND j.state IN ('queued', 'running')",
        )
        .bind(id)
        .fetch_one(&mut *tx)
        .await?;
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
        // One statement (see request_cancel): a point requeued meanwhile is not missed.
        sqlx::query(&format!(
            "UPDATE jobs SET {CANCEL_SET}, updated_at = $2, version = version + 1 \
             WHERE (state = 'queued' OR (state = 'running' AND NOT cancel_requested)) AND {ours}"
        ))
        .bind(id)
        .bind(now)
        .bind(cancelled_while_queued(Some(id)))
        .execute(&mut *tx)
        .await?;
        tx.commit().await?;
        self.get_study(id).await
    }

    async fn delete_study(&self, id: &str) -> Result<(), StoreError> {
        let mut tx = self.locked().await?;
        let exists: Option<String> = sqlx::query_scalar("SELECT id FROM studies WHERE id = $1")
            .bind(id)
            .fetch_optional(&mut *tx)
            .await?;
        if exists.is_none() {
            return Err(StoreError::StudyNotFound(id.to_string()));
        }
        let busy: i64 = sqlx::query_scalar(
            "SELECT COUNT(*) FROM study_points sp JOIN jobs j ON j.id = sp.job_id \
             WHERE sp.study_id = $1 AND j.state IN ('queued', 'running') \
             AND NOT EXISTS (SELECT 1 FROM study_points o WHERE o.job_id = sp.job_id AND o.study_id <> $1)",
        )
        .bind(id)
        .fetch_one(&mut *tx)
        .await?;
        if busy > 0 {
            tx.rollback().await?;
            return Err(StoreError::StudyConflict {
                id: id.to_string(),
                message: format!("{busy} of its points are queued or running; cancel it first"),
            });
        }
        let jobs: Vec<String> =
            sqlx::query_scalar("SELECT DISTINCT job_id FROM study_points WHERE study_id = $1")
                .bind(id)
                .fetch_all(&mut *tx)
                .await?;
        sqlx::query("DELETE FROM studies WHERE id = $1")
            .bind(id)
            .execute(&mut *tx)
            .await?;
        sqlx::query(
            "DELETE FROM jobs WHERE id = ANY($1) AND state IN ('succeeded', 'failed', 'cancelled') \
             AND NOT EXISTS (SELECT 1 FROM study_points WHERE job_id = jobs.id)",
        )
        .bind(&jobs)
        .execute(&mut *tx)
        .await?;
        tx.commit().await?;
        Ok(())
    }
}
