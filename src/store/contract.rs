//! What every backend does: the [`Store`] trait and its error.

use super::model::*;
use async_trait::async_trait;
use std::sync::Arc;
use tokio::sync::Notify;

/// Why a store operation did not happen.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    #[error("no job with id {0}")]
    NotFound(String),
    /// The job is in a state that does not allow the operation.
    #[error("job {id} is {state}: {message}")]
    Conflict {
        id: String,
        state: JobState,
        message: String,
    },
    #[error("no study with id {0}")]
    StudyNotFound(String),
    /// The study is in a state that does not allow the operation.
    #[error("study {id}: {message}")]
    StudyConflict { id: String, message: String },
    #[error("the queue is full ({0} jobs waiting)")]
    QueueFull(i64),
    /// The tenant holds its share of the queue.
    #[error("the tenant has {0} jobs queued, its share of the queue")]
    TenantQueueFull(i64),
    /// Same Idempotency-Key, different request.
    #[error("Idempotency-Key was already used for a different request (job {0})")]
    IdempotencyMismatch(String),
    /// The caller no longer holds the job's lease (it expired and the job moved on).
    #[error("lease lost")]
    LeaseLost,
    #[error("database error: {0}")]
    Db(#[from] sqlx::Error),
    #[error("migration error: {0}")]
    Migrate(#[from] sqlx::migrate::MigrateError),
    #[error("{0}")]
    Url(String),
}

impl StoreError {
    /// The database could not be reached (down, restarting, or no connection free within
    /// the pool's wait), as opposed to refusing a statement: worth retrying later.
    pub fn is_unreachable(&self) -> bool {
        match self {
            StoreError::Db(e) => match e {
                sqlx::Error::PoolTimedOut
                | sqlx::Error::PoolClosed
                | sqlx::Error::Io(_)
                | sqlx::Error::Tls(_)
                | sqlx::Error::WorkerCrashed => true,
                // PostgreSQL shutting down, starting up, or out of connection slots
                sqlx::Error::Database(d) => d
                    .code()
                    .is_some_and(|c| c.starts_with("57P") || c == "53300"),
                _ => false,
            },
            _ => false,
        }
    }
}

#[async_trait]
pub trait Store: Send + Sync + 'static {
    /// Check the database answers (readiness).
    async fn ping(&self) -> Result<(), StoreError>;

    /// Poke `wake` whenever another process makes a job claimable, until the store is
    /// dropped. Workers poll as well; this only makes them start sooner. The default does
    /// nothing (an embedded database has no other process to hear from).
    async fn wake_on_new_work(&self, wake: Arc<Notify>) -> Result<(), StoreError> {
        let _ = wake;
        Ok(())
    }

    /// Queue a job unless the queue holds `max_queued` jobs already. With an idempotency
    /// key already seen from the same tenant, returns the existing job (`created = false`) when the request hash
    /// matches and `IdempotencyMismatch` otherwise.
    async fn create_job(&self, job: NewJob, max_queued: i64) -> Result<Created, StoreError> {
        self.create_job_within(job, max_queued, i64::MAX).await
    }

    /// [`Store::create_job`], and unless the job's tenant has `tenant_max_queued` jobs
    /// queued already (`TenantQueueFull`).
    async fn create_job_within(
        &self,
        job: NewJob,
        max_queued: i64,
        tenant_max_queued: i64,
    ) -> Result<Created, StoreError>;

    async fn get_job(&self, id: &str) -> Result<Job, StoreError>;

    /// Newest first; `before` is the cursor returned by the previous page.
    async fn list_jobs(&self, filter: &ListFilter) -> Result<Page, StoreError>;

    /// Queued: cancelled at once. Running: flagged for the worker's next heartbeat.
    /// Finished: `Conflict`.
    async fn request_cancel(&self, id: &str) -> Result<Job, StoreError>;

    /// Delete a finished job and its outputs; `Conflict` while queued or running, or while
    /// a study holds it as a point.
    async fn delete_job(&self, id: &str) -> Result<(), StoreError>;

    /// Atomically take a queued job whose input format is at most `max_input_format`
    /// under a lease held by `owner`: of the tenants running fewer than `tenant_share`
    /// jobs, the one running fewest (round robin across tenants), its oldest job. Newer
    /// formats are skipped, not blocked on.
    async fn claim_shared(
        &self,
        owner: &str,
        lease_ms: i64,
        max_input_format: i64,
        tenant_share: i64,
    ) -> Result<Option<Claimed>, StoreError>;

    /// [`Store::claim_shared`] with no bound on a tenant's running jobs.
    async fn claim_up_to(
        &self,
        owner: &str,
        lease_ms: i64,
        max_input_format: i64,
    ) -> Result<Option<Claimed>, StoreError> {
        self.claim_shared(owner, lease_ms, max_input_format, i64::MAX)
            .await
    }

    /// [`Store::claim_up_to`] the formats this binary runs ([`INPUT_FORMAT`]).
    async fn claim(&self, owner: &str, lease_ms: i64) -> Result<Option<Claimed>, StoreError> {
        self.claim_up_to(owner, lease_ms, INPUT_FORMAT).await
    }

    /// Renew the lease and record progress; tells whether cancel was requested.
    async fn heartbeat(
        &self,
        lease: &Lease,
        progress: f64,
        lease_ms: i64,
    ) -> Result<Heartbeat, StoreError>;

    /// Record the final state of a claimed job. Fenced: `LeaseLost` if `lease` is stale.
    async fn finish(&self, lease: &Lease, outcome: Outcome) -> Result<(), StoreError>;

    /// Give a claimed job back to the queue without counting the attempt (shutdown).
    async fn release(&self, lease: &Lease) -> Result<(), StoreError>;

    /// Requeue running jobs whose lease expired: their worker died, which is not their
    /// fault. A job whose worker died `max_attempts` times in a row without the job getting
    /// further than before is failed instead (it appears to kill its worker).
    async fn recover_expired(&self, max_attempts: i64) -> Result<u64, StoreError>;

    async fn get_artifact(&self, id: &str, name: &str) -> Result<Option<Artifact>, StoreError>;

    /// Bytes held by jobs (inputs, input blobs, results) and their artifacts: what the
    /// storage bound (`--max-store-bytes`) and the metrics count.
    async fn stored_bytes(&self) -> Result<i64, StoreError>;

    /// Delete what finished before `before_ms` (unix ms): studies all of whose points
    /// finished before it, then finished jobs no study holds, with their artifacts.
    /// Returns (jobs, studies) deleted.
    async fn expire(&self, before_ms: i64) -> Result<(u64, u64), StoreError>;

    /// Number of jobs per state, for metrics and admission.
    async fn counts(&self) -> Result<StateCounts, StoreError>;

    /// Store a study and queue its points, all or nothing. A point whose scene key matches
    /// a queued, running or succeeded simulation of the same tenant (not being cancelled)
    /// shares that job;
    /// identical points within the study share one. `QueueFull` if the new jobs do not fit.
    async fn create_study(
        &self,
        study: NewStudy,
        max_queued: i64,
    ) -> Result<StudyCreated, StoreError>;

    /// The study with its points and their jobs.
    async fn get_study(&self, id: &str) -> Result<Study, StoreError>;

    /// Newest first; `before` is the cursor returned by the previous page.
    /// Only `tenant`'s studies when given.
    async fn list_studies(
        &self,
        tenant: Option<&str>,
        before: Option<i64>,
        limit: i64,
    ) -> Result<StudyPage, StoreError>;

    /// Mark the study cancelled and cancel its unfinished points that no other study still
    /// wants. `StudyConflict` if every point has finished.
    async fn cancel_study(&self, id: &str) -> Result<Study, StoreError>;

    /// Delete the study and the finished jobs of its points that no other study shares.
    /// `StudyConflict` while a point only it holds is queued or running.
    async fn delete_study(&self, id: &str) -> Result<(), StoreError>;
}
