//! [`Store`] on an embedded SQLite database in WAL mode.
//!
//! Every state change is a single statement (or a transaction that starts with its
//! write), so concurrent writers queue on SQLite's lock with the busy timeout instead of
//! failing on a read-to-write upgrade.

use super::contract::{Store, StoreError};
use super::migrations::additive;
use super::model::*;
use super::rows::*;
use async_trait::async_trait;
use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqlitePoolOptions, SqliteSynchronous};
use sqlx::{Row, SqlitePool};
use std::str::FromStr;
use std::time::Duration;

pub struct SqliteStore {
    pool: SqlitePool,
}

impl SqliteStore {
    /// Open (creating the file and its directory if needed) and migrate.
    pub async fn connect(url: &str) -> Result<SqliteStore, StoreError> {
        let opts = SqliteConnectOptions::from_str(url)?
            .create_if_missing(true)
            .journal_mode(SqliteJournalMode::Wal)
            // WAL + NORMAL survives a process crash (SIGKILL) without losing commits.
            .synchronous(SqliteSynchronous::Normal)
            .busy_timeout(Duration::from_secs(30))
            .foreign_keys(true);
        if let Some(parent) = opts.get_filename().parent() {
            if !parent.as_os_str().is_empty() {
                std::fs::create_dir_all(parent).map_err(|e| StoreError::Db(sqlx::Error::Io(e)))?;
            }
        }
        let pool = SqlitePoolOptions::new()
            .max_connections(8)
            .acquire_timeout(Duration::from_secs(30))
            .connect_with(opts)
            .await?;
        additive(sqlx::migrate!("./migrations/sqlite"))
            .run(&pool)
            .await?;
        Ok(SqliteStore { pool })
    }

    async fn fetch_job(&self, id: &str) -> Result<Option<Job>, StoreError> {
        let row = sqlx::query(&format!("SELECT {JOB_COLUMNS} FROM jobs WHERE id = ?"))
            .bind(id)
            .fetch_optional(&self.pool)
            .await?;
        row.map(|r| job_from_row(&r)).transpose()
    }
}

impl SqliteStore {
    async fn study_points(&self, id: &str) -> Result<Vec<StudyPointRow>, StoreError> {
        let rows = sqlx::query(&format!(
            "SELECT sp.idx AS idx, sp.spec AS spec, \
                 EXISTS (SELECT 1 FROM study_points o WHERE o.job_id = sp.job_id AND o.study_id != sp.study_id) AS others, \
                 {} \
             FROM study_points sp JOIN jobs ON jobs.id = sp.job_id WHERE sp.study_id = ? ORDER BY sp.idx",
            job_columns_of_join()
        ))
        .bind(id)
        .fetch_all(&self.pool)
        .await?;
        rows.iter().map(|r| study_point_from_row(id, r)).collect()
    }
}

#[async_trait]
impl Store for SqliteStore {
    async fn ping(&self) -> Result<(), StoreError> {
        sqlx::query("SELECT 1").execute(&self.pool).await?;
        Ok(())
    }

    async fn create_job(&self, job: NewJob, max_queued: i64) -> Result<Created, StoreError> {
        let now = now_ms();
        let scoped_key = job
            .idempotency_key
            .as_deref()
            .map(|k| scoped_idempotency_key(&job.tenant, k));
        // One statement: admission check and insert are atomic; a duplicate key inserts nothing.
        let inserted = sqlx::query(
            "INSERT INTO jobs (id, tenant, kind, state, input, input_blob, idempotency_key, request_hash, label, created_at, updated_at, input_format) \
             SELECT ?, ?, ?, 'queued', ?, ?, ?, ?, ?, ?, ?, ? \
             WHERE (SELECT COUNT(*) FROM jobs WHERE state = 'queued') < ? \
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
        .bind(now)
        .bind(job.input_format)
        .bind(max_queued)
        .execute(&self.pool)
        .await?
        .rows_affected();
        if inserted == 1 {
            let job = self
                .fetch_job(&job.id)
                .await?
                .ok_or_else(|| StoreError::NotFound(job.id.clone()))?;
            return Ok(Created { job, created: true });
        }
        if let Some(key) = &scoped_key {
            let stored: Option<(String, Option<String>, String)> =
                sqlx::query_as("SELECT id, request_hash, kind FROM jobs WHERE idempotency_key = ?")
                    .bind(key)
                    .fetch_optional(&self.pool)
                    .await?;
            if let Some(stored) = stored {
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
             WHERE (?1 IS NULL OR kind = ?1) AND (?2 IS NULL OR state = ?2) AND (?3 IS NULL OR seq < ?3) \
               AND (?5 IS NULL OR tenant = ?5) \
             ORDER BY seq DESC LIMIT ?4"
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
        // One statement, so a job requeued meanwhile (a lease recovery in another process)
        // is judged as it is now: queued ends cancelled, running gets the flag.
        let state: Option<String> = sqlx::query_scalar(
            "UPDATE jobs SET state = CASE WHEN state = 'queued' THEN 'cancelled' ELSE state END, \
                 finished_at = CASE WHEN state = 'queued' THEN ?2 ELSE finished_at END, \
                 error = CASE WHEN state = 'queued' THEN ?3 ELSE error END, \
                 cancel_requested = 1, updated_at = ?2, version = version + 1 \
             WHERE id = ?1 AND (state = 'queued' OR (state = 'running' AND cancel_requested = 0)) \
             RETURNING state",
        )
        .bind(id)
        .bind(now)
        .bind(cancelled_while_queued(None))
        .fetch_optional(&self.pool)
        .await?;
        let done = state.as_deref() == Some("cancelled");
        cancel_answer(self.get_job(id).await?, done)
    }

    async fn delete_job(&self, id: &str) -> Result<(), StoreError> {
        let n = sqlx::query(
            "DELETE FROM jobs WHERE id = ? AND state IN ('succeeded', 'failed', 'cancelled') \
             AND NOT EXISTS (SELECT 1 FROM study_points WHERE job_id = jobs.id)",
        )
        .bind(id)
        .execute(&self.pool)
        .await?
        .rows_affected();
        if n == 0 {
            let study: Option<String> =
                sqlx::query_scalar("SELECT study_id FROM study_points WHERE job_id = ? LIMIT 1")
                    .bind(id)
                    .fetch_optional(&self.pool)
                    .await?;
            return Err(delete_refusal(self.get_job(id).await?, study));
        }
        Ok(())
    }

    async fn claim_up_to(
        &self,
        owner: &str,
        lease_ms: i64,
        max_input_format: i64,
    ) -> Result<Option<Claimed>, StoreError> {
        let now = now_ms();
        let row = sqlx::query(
            "UPDATE jobs SET state = 'running', owner = ?1, lease_expires_at = ?2, attempt = attempt + 1, \
                 started_at = COALESCE(started_at, ?3), updated_at = ?3, version = version + 1 \
             WHERE seq = (SELECT seq FROM jobs WHERE state = 'queued' AND input_format <= ?4 ORDER BY seq LIMIT 1) \
                 AND state = 'queued' \
             RETURNING id, kind, attempt, input, input_blob, cancel_requested",
        )
        .bind(owner)
        .bind(now + lease_ms)
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
        let row = sqlx::query(
            "UPDATE jobs SET lease_expires_at = ?4, progress = MAX(progress, ?5), updated_at = ?6, \
                 version = version + (CASE WHEN progress < ?5 THEN 1 ELSE 0 END) \
             WHERE id = ?1 AND owner = ?2 AND attempt = ?3 AND state = 'running' \
             RETURNING cancel_requested",
        )
        .bind(&lease.id)
        .bind(&lease.owner)
        .bind(lease.attempt)
        .bind(now + lease_ms)
        .bind(progress)
        .bind(now)
        .fetch_optional(&self.pool)
        .await?;
        match row {
            Some(r) => Ok(Heartbeat {
                cancel_requested: r.try_get::<i64, _>("cancel_requested")? != 0,
            }),
            None => Err(StoreError::LeaseLost),
        }
    }

    async fn finish(&self, lease: &Lease, outcome: Outcome) -> Result<(), StoreError> {
        let now = now_ms();
        let (state, progress, error, stats, result, artifacts) = finished_row(outcome);
        let mut tx = self.pool.begin().await?;
        // The fenced write comes first so the transaction takes the write lock at once.
        let n = sqlx::query(
            "UPDATE jobs SET state = ?4, progress = COALESCE(?5, progress), error = ?6, stats = ?7, result = ?8, \
                 finished_at = ?9, updated_at = ?9, owner = NULL, lease_expires_at = NULL, version = version + 1 \
             WHERE id = ?1 AND owner = ?2 AND attempt = ?3 AND state = 'running'",
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
                "INSERT OR REPLACE INTO artifacts (job_id, name, meta, data) VALUES (?, ?, ?, ?)",
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
                 updated_at = ?4, version = version + 1 \
             WHERE id = ?1 AND owner = ?2 AND attempt = ?3 AND state = 'running'",
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
        // A job asked to cancel is not run again: it ends cancelled.
        let cancelled = sqlx::query(
            "UPDATE jobs SET state = 'cancelled', error = ?2, owner = NULL, lease_expires_at = NULL, \
                 finished_at = ?1, updated_at = ?1, version = version + 1 \
             WHERE state = 'running' AND lease_expires_at < ?1 AND cancel_requested = 1",
        )
        .bind(now)
        .bind(CANCELLED_UNCONFIRMED)
        .execute(&self.pool)
        .await?
        .rows_affected();
        let failed = sqlx::query(
            "UPDATE jobs SET state = 'failed', error = ?3, owner = NULL, lease_expires_at = NULL, \
                 finished_at = ?1, updated_at = ?1, version = version + 1 \
             WHERE state = 'running' AND lease_expires_at < ?1 AND attempt >= ?2",
        )
        .bind(now)
        .bind(max_attempts)
        .bind(lease_expired_error(max_attempts))
        .execute(&self.pool)
        .await?
        .rows_affected();
        let requeued = sqlx::query(
            "UPDATE jobs SET state = 'queued', owner = NULL, lease_expires_at = NULL, updated_at = ?1, \
                 version = version + 1 \
             WHERE state = 'running' AND lease_expires_at < ?1",
        )
        .bind(now)
        .execute(&self.pool)
        .await?
        .rows_affected();
        Ok(failed + cancelled + requeued)
    }

    async fn get_artifact(&self, id: &str, name: &str) -> Result<Option<Artifact>, StoreError> {
        let row =
            sqlx::query("SELECT name, meta, data FROM artifacts WHERE job_id = ? AND name = ?")
                .bind(id)
                .bind(name)
                .fetch_optional(&self.pool)
                .await?;
        row.map(|r| artifact_from_row(id, &r)).transpose()
    }

    async fn stored_bytes(&self) -> Result<i64, StoreError> {
        // length() of a blob reads its size from the record header, not the blob
        let jobs: i64 = sqlx::query_scalar(
            "SELECT COALESCE(SUM(LENGTH(input) + COALESCE(LENGTH(input_blob), 0) \
                 + COALESCE(LENGTH(result), 0) + COALESCE(LENGTH(stats), 0)), 0) FROM jobs",
        )
        .fetch_one(&self.pool)
        .await?;
        let artifacts: i64 = sqlx::query_scalar(
            "SELECT COALESCE(SUM(LENGTH(data) + LENGTH(meta)), 0) FROM artifacts",
        )
        .fetch_one(&self.pool)
        .await?;
        Ok(jobs + artifacts)
    }

    async fn expire(&self, before_ms: i64) -> Result<(u64, u64), StoreError> {
        let mut tx = self.pool.begin().await?;
        // a study goes when every point's job finished before the cutoff (its points go
        // with it: ON DELETE CASCADE)
        let studies = sqlx::query(
            "DELETE FROM studies WHERE updated_at < ?1 AND NOT EXISTS ( \
                 SELECT 1 FROM study_points sp JOIN jobs j ON j.id = sp.job_id \
                 WHERE sp.study_id = studies.id \
                   AND (j.state NOT IN ('succeeded', 'failed', 'cancelled') OR j.finished_at >= ?1))",
        )
        .bind(before_ms)
        .execute(&mut *tx)
        .await?
        .rows_affected();
        // then the finished jobs no study holds any more (artifacts: ON DELETE CASCADE)
        let jobs = sqlx::query(
            "DELETE FROM jobs WHERE state IN ('succeeded', 'failed', 'cancelled') \
                 AND finished_at < ?1 \
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
        let rows = sqlx::query("SELECT state, COUNT(*) AS n FROM jobs GROUP BY state")
            .fetch_all(&self.pool)
            .await?;
        let mut c = StateCounts::default();
        for r in rows {
            let s: String = r.try_get("state")?;
            if let Some(st) = JobState::parse(&s) {
                c.set(st, r.try_get("n")?);
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
        let mut tx = self.pool.begin().await?;
        // The first statement writes, so the transaction holds the write lock throughout.
        sqlx::query(
            "INSERT INTO studies (id, tenant, label, request, design, created_at, updated_at) \
             VALUES (?, ?, ?, ?, ?, ?, ?)",
        )
        .bind(&study.id)
        .bind(&study.tenant)
        .bind(&study.label)
        .bind(study.request.to_string())
        .bind(study.design.to_string())
        .bind(now)
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
                    "SELECT id FROM jobs WHERE scene_key = ? AND tenant = ? AND kind = 'simulation' \
                     AND state IN ('queued', 'running', 'succeeded') AND cancel_requested = 0 \
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
                             VALUES (?, ?, ?, 'queued', ?, ?, ?, ?, ?, ?, ?)",
                        )
                        .bind(&j.id)
                        .bind(&study.tenant)
                        .bind(j.kind.as_str())
                        .bind(j.input.to_string())
                        .bind(&j.request_hash)
                        .bind(&j.label)
                        .bind(&p.scene_key)
                        .bind(now)
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
                "INSERT INTO study_points (study_id, idx, job_id, spec) VALUES (?, ?, ?, ?)",
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
        let row = sqlx::query(&format!("SELECT {STUDY_COLUMNS} FROM studies WHERE id = ?"))
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
            "SELECT {STUDY_COLUMNS} FROM studies WHERE (?1 IS NULL OR seq < ?1) \
             AND (?3 IS NULL OR tenant = ?3) ORDER BY seq DESC LIMIT ?2"
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
        let mut tx = self.pool.begin().await?;
        let n = sqlx::query(
            "UPDATE studies SET cancel_requested = 1, version = version + 1, updated_at = ?2 WHERE id = ?1",
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
             WHERE sp.study_id = ? AND j.state IN ('queued', 'running')",
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
        let ours = "id IN (SELECT job_id FROM study_points WHERE study_id = ?1) \
             AND NOT EXISTS (SELECT 1 FROM study_points o JOIN studies s ON s.id = o.study_id \
                 WHERE o.job_id = jobs.id AND o.study_id != ?1 AND s.cancel_requested = 0)";
        sqlx::query(&format!(
            "UPDATE jobs SET state = 'cancelled', finished_at = ?2, updated_at = ?2, version = version + 1, \
             cancel_requested = 1, error = ?3 WHERE state = 'queued' AND {ours}"
        ))
        .bind(id)
        .bind(now)
        .bind(cancelled_while_queued(Some(id)))
        .execute(&mut *tx)
        .await?;
        sqlx::query(&format!(
            "UPDATE jobs SET cancel_requested = 1, updated_at = ?2, version = version + 1 \
             WHERE state = 'running' AND cancel_requested = 0 AND {ours}"
        ))
        .bind(id)
        .bind(now)
        .execute(&mut *tx)
        .await?;
        tx.commit().await?;
        self.get_study(id).await
    }

    async fn delete_study(&self, id: &str) -> Result<(), StoreError> {
        let mut tx = self.pool.begin().await?;
        // A write first: the transaction holds the lock from here.
        let n = sqlx::query("UPDATE studies SET version = version + 1 WHERE id = ?")
            .bind(id)
            .execute(&mut *tx)
            .await?
            .rows_affected();
        if n == 0 {
            return Err(StoreError::StudyNotFound(id.to_string()));
        }
        let busy: i64 = sqlx::query_scalar(
            "SELECT COUNT(*) FROM study_points sp JOIN jobs j ON j.id = sp.job_id \
             WHERE sp.study_id = ?1 AND j.state IN ('queued', 'running') \
             AND NOT EXISTS (SELECT 1 FROM study_points o WHERE o.job_id = sp.job_id AND o.study_id != ?1)",
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
            sqlx::query_scalar("SELECT DISTINCT job_id FROM study_points WHERE study_id = ?")
                .bind(id)
                .fetch_all(&mut *tx)
                .await?;
        sqlx::query("DELETE FROM studies WHERE id = ?")
            .bind(id)
            .execute(&mut *tx)
            .await?;
        for job in jobs {
            sqlx::query(
                "DELETE FROM jobs WHERE id = ? AND state IN ('succeeded', 'failed', 'cancelled') \
                 AND NOT EXISTS (SELECT 1 FROM study_points WHERE job_id = jobs.id)",
            )
            .bind(job)
            .execute(&mut *tx)
            .await?;
        }
        tx.commit().await?;
        Ok(())
    }
}
