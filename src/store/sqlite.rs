//! [`Store`] on an embedded SQLite database in WAL mode.
//!
//! Every state change is a single statement (or a transaction that starts with its
//! write), so concurrent writers queue on SQLite's lock with the busy timeout instead of
//! failing on a read-to-write upgrade.

use super::*;
use async_trait::async_trait;
use sqlx::sqlite::{
    SqliteConnectOptions, SqliteJournalMode, SqlitePoolOptions, SqliteRow, SqliteSynchronous,
};
use sqlx::{Row, SqlitePool};
use std::str::FromStr;
use std::time::Duration;

pub struct SqliteStore {
    pool: SqlitePool,
}

const JOB_COLUMNS: &str =
    "seq, id, tenant, kind, state, label, progress, attempt, cancel_requested, version, \
     created_at, started_at, finished_at, updated_at, error, stats, result";

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
        sqlx::migrate!("./migrations").run(&pool).await?;
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

/// The idempotency key as stored: a tenant's keys live apart from every other tenant's
/// (the unit separator cannot occur in a header value); without tokens it is the key.
fn scoped_idempotency_key(tenant: &str, key: &str) -> String {
    if tenant.is_empty() {
        key.to_string()
    } else {
        format!("{tenant}\u{1f}{key}")
    }
}

fn parse_json(s: Option<String>) -> Option<serde_json::Value> {
    s.and_then(|s| serde_json::from_str(&s).ok())
}

fn job_from_row(r: &SqliteRow) -> Result<Job, StoreError> {
    let kind: String = r.try_get("kind")?;
    let state: String = r.try_get("state")?;
    let decode =
        |what: &str, v: &str| sqlx::Error::Decode(format!("bad {what} '{v}' in jobs row").into());
    Ok(Job {
        seq: r.try_get("seq")?,
        id: r.try_get("id")?,
        tenant: r.try_get("tenant")?,
        kind: JobKind::parse(&kind).ok_or_else(|| decode("kind", &kind))?,
        state: JobState::parse(&state).ok_or_else(|| decode("state", &state))?,
        label: r.try_get("label")?,
        progress: r.try_get("progress")?,
        attempt: r.try_get("attempt")?,
        cancel_requested: r.try_get::<i64, _>("cancel_requested")? != 0,
        version: r.try_get("version")?,
        created_at: r.try_get("created_at")?,
        started_at: r.try_get("started_at")?,
        finished_at: r.try_get("finished_at")?,
        updated_at: r.try_get("updated_at")?,
        error: parse_json(r.try_get("error")?).and_then(|v| serde_json::from_value(v).ok()),
        stats: parse_json(r.try_get("stats")?),
        result: parse_json(r.try_get("result")?),
    })
}

const STUDY_COLUMNS: &str =
    "seq, id, tenant, label, request, design, cancel_requested, version, created_at, updated_at";

fn study_from_row(r: &SqliteRow) -> Result<Study, StoreError> {
    let json = |col: &str| -> Result<serde_json::Value, StoreError> {
        let text: String = r.try_get(col)?;
        serde_json::from_str(&text).map_err(|e| {
            StoreError::Db(sqlx::Error::Decode(
                format!("bad {col} in studies row: {e}").into(),
            ))
        })
    };
    Ok(Study {
        seq: r.try_get("seq")?,
        id: r.try_get("id")?,
        tenant: r.try_get("tenant")?,
        label: r.try_get("label")?,
        request: json("request")?,
        design: json("design")?,
        cancel_requested: r.try_get::<i64, _>("cancel_requested")? != 0,
        version: r.try_get("version")?,
        created_at: r.try_get("created_at")?,
        updated_at: r.try_get("updated_at")?,
        points: vec![],
    })
}

impl SqliteStore {
    async fn study_points(&self, id: &str) -> Result<Vec<StudyPointRow>, StoreError> {
        let rows = sqlx::query(&format!(
            "SELECT sp.idx AS idx, sp.spec AS spec, \
                 EXISTS (SELECT 1 FROM study_points o WHERE o.job_id = sp.job_id AND o.study_id != sp.study_id) AS others, \
                 {} \
             FROM study_points sp JOIN jobs ON jobs.id = sp.job_id WHERE sp.study_id = ? ORDER BY sp.idx",
            JOB_COLUMNS
                .split(", ")
                .map(|c| format!("jobs.{} AS {}", c.trim(), c.trim()))
                .collect::<Vec<_>>()
                .join(", ")
        ))
        .bind(id)
        .fetch_all(&self.pool)
        .await?;
        rows.iter()
            .map(|r| {
                let spec: String = r.try_get("spec")?;
                Ok(StudyPointRow {
                    index: r.try_get::<i64, _>("idx")? as usize,
                    spec: serde_json::from_str(&spec).map_err(|e| {
                        StoreError::Db(sqlx::Error::Decode(
                            format!("bad spec of a point of study {id}: {e}").into(),
                        ))
                    })?,
                    job: job_from_row(r)?,
                    shared_with_other_studies: r.try_get::<i64, _>("others")? != 0,
                })
            })
            .collect()
    }
}

fn opt_json(v: &Option<serde_json::Value>) -> Option<String> {
    v.as_ref().map(|v| v.to_string())
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
            "INSERT INTO jobs (id, tenant, kind, state, input, input_blob, idempotency_key, request_hash, label, created_at, updated_at) \
             SELECT ?, ?, ?, 'queued', ?, ?, ?, ?, ?, ?, ? \
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
            let row =
                sqlx::query("SELECT id, request_hash, kind FROM jobs WHERE idempotency_key = ?")
                    .bind(key)
                    .fetch_optional(&self.pool)
                    .await?;
            if let Some(row) = row {
                let id: String = row.try_get("id")?;
                let hash: Option<String> = row.try_get("request_hash")?;
                let kind: String = row.try_get("kind")?;
                if hash.as_deref() != Some(job.request_hash.as_str()) || kind != job.kind.as_str() {
                    return Err(StoreError::IdempotencyMismatch(id));
                }
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
        let mut jobs = rows
            .iter()
            .map(job_from_row)
            .collect::<Result<Vec<_>, _>>()?;
        let next = if jobs.len() as i64 > limit {
            jobs.truncate(limit as usize);
            jobs.last().map(|j| j.seq)
        } else {
            None
        };
        Ok(Page { jobs, next })
    }

    async fn request_cancel(&self, id: &str) -> Result<Job, StoreError> {
        let now = now_ms();
        let err = JobError {
            kind: FailureKind::Cancelled,
            message: "cancelled while queued".into(),
        };
        let done = sqlx::query(
            "UPDATE jobs SET state = 'cancelled', finished_at = ?2, updated_at = ?2, version = version + 1, \
             cancel_requested = 1, error = ?3 WHERE id = ?1 AND state = 'queued'",
        )
        .bind(id)
        .bind(now)
        .bind(serde_json::to_string(&err).unwrap_or_default())
        .execute(&self.pool)
        .await?
        .rows_affected();
        if done == 0 {
            sqlx::query(
                "UPDATE jobs SET cancel_requested = 1, updated_at = ?2, version = version + 1 \
                 WHERE id = ?1 AND state = 'running' AND cancel_requested = 0",
            )
            .bind(id)
            .bind(now)
            .execute(&self.pool)
            .await?;
        }
        let job = self.get_job(id).await?;
        if job.state.is_finished() && !(job.state == JobState::Cancelled && done == 1) {
            return Err(StoreError::Conflict {
                id: job.id,
                state: job.state,
                message: "only queued or running jobs can be cancelled".into(),
            });
        }
        Ok(job)
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
            let job = self.get_job(id).await?;
            if job.state.is_finished() {
                let study: Option<String> = sqlx::query_scalar(
                    "SELECT study_id FROM study_points WHERE job_id = ? LIMIT 1",
                )
                .bind(id)
                .fetch_optional(&self.pool)
                .await?;
                return Err(StoreError::Conflict {
                    id: job.id,
                    state: job.state,
                    message: format!(
                        "it is a point of study {}; delete the study instead",
                        study.unwrap_or_default()
                    ),
                });
            }
            return Err(StoreError::Conflict {
                id: job.id,
                state: job.state,
                message: "only finished jobs can be deleted; cancel it first".into(),
            });
        }
        Ok(())
    }

    async fn claim(&self, owner: &str, lease_ms: i64) -> Result<Option<Claimed>, StoreError> {
        let now = now_ms();
        let row = sqlx::query(
            "UPDATE jobs SET state = 'running', owner = ?1, lease_expires_at = ?2, attempt = attempt + 1, \
                 started_at = COALESCE(started_at, ?3), updated_at = ?3, version = version + 1 \
             WHERE seq = (SELECT seq FROM jobs WHERE state = 'queued' ORDER BY seq LIMIT 1) AND state = 'queued' \
             RETURNING id, kind, attempt, input, input_blob, cancel_requested",
        )
        .bind(owner)
        .bind(now + lease_ms)
        .bind(now)
        .fetch_optional(&self.pool)
        .await?;
        let Some(r) = row else { return Ok(None) };
        let kind: String = r.try_get("kind")?;
        let input: String = r.try_get("input")?;
        Ok(Some(Claimed {
            lease: Lease {
                id: r.try_get("id")?,
                owner: owner.to_string(),
                attempt: r.try_get("attempt")?,
            },
            kind: JobKind::parse(&kind).unwrap_or(JobKind::Simulation),
            input: serde_json::from_str(&input).unwrap_or(serde_json::Value::Null),
            input_blob: r.try_get("input_blob")?,
            cancel_requested: r.try_get::<i64, _>("cancel_requested")? != 0,
        }))
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
        let (state, progress, error, stats, result, artifacts) = match outcome {
            Outcome::Succeeded {
                result,
                stats,
                artifacts,
            } => ("succeeded", Some(1.0), None, stats, Some(result), artifacts),
            Outcome::Failed { error, stats } => ("failed", None, Some(error), stats, None, vec![]),
            Outcome::Cancelled { error } => ("cancelled", None, Some(error), None, None, vec![]),
        };
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
        .bind(error.map(|e| serde_json::to_string(&e).unwrap_or_default()))
        .bind(opt_json(&stats))
        .bind(opt_json(&result))
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
        let err = JobError {
            kind: FailureKind::LeaseExpired,
            message: format!(
                "the worker running this job stopped responding {max_attempts} times; giving up"
            ),
        };
        // A job asked to cancel is not run again: it ends cancelled.
        let cancelled = sqlx::query(
            "UPDATE jobs SET state = 'cancelled', error = ?2, owner = NULL, lease_expires_at = NULL, \
                 finished_at = ?1, updated_at = ?1, version = version + 1 \
             WHERE state = 'running' AND lease_expires_at < ?1 AND cancel_requested = 1",
        )
        .bind(now)
        .bind(r#"{"kind":"cancelled","message":"cancelled (its worker stopped before confirming)"}"#)
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
        .bind(serde_json::to_string(&err).unwrap_or_default())
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
        Ok(match row {
            Some(r) => {
                let name: String = r.try_get("name")?;
                let meta: String = r.try_get("meta")?;
                let meta = serde_json::from_str(&meta).map_err(|e| {
                    sqlx::Error::Decode(
                        format!("bad metadata of artifact {name} of job {id}: {e}").into(),
                    )
                })?;
                Some(Artifact {
                    name,
                    meta,
                    data: r.try_get("data")?,
                })
            }
            None => None,
        })
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
                            "INSERT INTO jobs (id, tenant, kind, state, input, request_hash, label, scene_key, created_at, updated_at) \
                             VALUES (?, ?, ?, 'queued', ?, ?, ?, ?, ?, ?)",
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
        let err = JobError {
            kind: FailureKind::Cancelled,
            message: format!("cancelled while queued, with study {id}"),
        };
        sqlx::query(&format!(
            "UPDATE jobs SET state = 'cancelled', finished_at = ?2, updated_at = ?2, version = version + 1, \
             cancel_requested = 1, error = ?3 WHERE state = 'queued' AND {ours}"
        ))
        .bind(id)
        .bind(now)
        .bind(serde_json::to_string(&err).unwrap_or_default())
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

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    async fn store() -> (tempfile::TempDir, SqliteStore) {
        let dir = tempfile::tempdir().unwrap();
        let url = format!("sqlite://{}", dir.path().join("t.db").display());
        let s = SqliteStore::connect(&url).await.unwrap();
        (dir, s)
    }

    fn new_job(key: Option<&str>, hash: &str) -> NewJob {
        NewJob {
            id: uuid::Uuid::now_v7().to_string(),
            tenant: String::new(),
            kind: JobKind::Simulation,
            label: "t".into(),
            input: json!({}),
            input_blob: None,
            idempotency_key: key.map(String::from),
            request_hash: hash.into(),
        }
    }

    #[tokio::test]
    async fn a_stale_lease_can_never_write() {
        let (_d, s) = store().await;
        let id = s.create_job(new_job(None, "h"), 10).await.unwrap().job.id;
        // Worker A claims with a lease that is already over (as if it hung).
        let a = s.claim("A", -1).await.unwrap().unwrap().lease;
        assert_eq!((a.id.as_str(), a.attempt), (id.as_str(), 1));
        assert_eq!(s.recover_expired(3).await.unwrap(), 1);
        let b = s.claim("B", 60_000).await.unwrap().unwrap().lease;
        assert_eq!(b.attempt, 2);
        // A wakes up: every write of its lease is refused.
        assert!(matches!(
            s.heartbeat(&a, 0.5, 1000).await,
            Err(StoreError::LeaseLost)
        ));
        let late = Outcome::Failed {
            error: JobError {
                kind: FailureKind::Numerical,
                message: "stale".into(),
            },
            stats: None,
        };
        assert!(matches!(
            s.finish(&a, late).await,
            Err(StoreError::LeaseLost)
        ));
        assert!(matches!(s.release(&a).await, Err(StoreError::LeaseLost)));
        // B's outcome stands.
        s.heartbeat(&b, 0.5, 60_000).await.unwrap();
        s.finish(
            &b,
            Outcome::Succeeded {
                result: json!({"ok": true}),
                stats: None,
                artifacts: vec![],
            },
        )
        .await
        .unwrap();
        let job = s.get_job(&id).await.unwrap();
        assert_eq!(job.state, JobState::Succeeded);
        assert_eq!(job.result, Some(json!({"ok": true})));
        assert!(s.claim("C", 1000).await.unwrap().is_none());
    }

    #[tokio::test]
    async fn lost_leases_give_up_after_max_attempts_and_release_does_not_count() {
        let (_d, s) = store().await;
        let id = s.create_job(new_job(None, "h"), 10).await.unwrap().job.id;
        let l = s.claim("A", 60_000).await.unwrap().unwrap().lease;
        s.release(&l).await.unwrap();
        assert_eq!(s.get_job(&id).await.unwrap().attempt, 0);
        for _ in 0..2 {
            s.claim("A", -1).await.unwrap().unwrap();
            s.recover_expired(2).await.unwrap();
        }
        let job = s.get_job(&id).await.unwrap();
        assert_eq!(job.state, JobState::Failed);
        assert_eq!(job.error.unwrap().kind, FailureKind::LeaseExpired);
    }

    #[tokio::test]
    async fn admission_idempotency_and_cancel() {
        let (_d, s) = store().await;
        let first = s.create_job(new_job(Some("k"), "h1"), 2).await.unwrap();
        assert!(first.created);
        let replay = s.create_job(new_job(Some("k"), "h1"), 2).await.unwrap();
        assert!(!replay.created);
        assert_eq!(replay.job.id, first.job.id);
        assert!(matches!(
            s.create_job(new_job(Some("k"), "h2"), 2).await,
            Err(StoreError::IdempotencyMismatch(_))
        ));
        s.create_job(new_job(None, "h"), 2).await.unwrap();
        assert!(matches!(
            s.create_job(new_job(None, "h"), 2).await,
            Err(StoreError::QueueFull(2))
        ));

        // queued -> cancelled at once; running -> flagged, seen by the heartbeat
        let c = s.request_cancel(&first.job.id).await.unwrap();
        assert_eq!(c.state, JobState::Cancelled);
        assert!(matches!(
            s.request_cancel(&first.job.id).await,
            Err(StoreError::Conflict { .. })
        ));
        let l = s.claim("A", 60_000).await.unwrap().unwrap().lease;
        assert!(!s.heartbeat(&l, 0.1, 60_000).await.unwrap().cancel_requested);
        assert_eq!(
            s.request_cancel(&l.id).await.unwrap().state,
            JobState::Running
        );
        assert!(s.heartbeat(&l, 0.2, 60_000).await.unwrap().cancel_requested);
        assert!(matches!(
            s.delete_job(&l.id).await,
            Err(StoreError::Conflict { .. })
        ));
        assert!(matches!(
            s.get_job("nope").await,
            Err(StoreError::NotFound(_))
        ));
    }
}
