//! The [`Store`], written once for both SQL backends.
//!
//! Every operation is one body here, over a [`Backend`] that supplies only what must
//! differ: how it connects and migrates, the queue's structure lock (PostgreSQL: an
//! advisory lock in the transaction; SQLite: `BEGIN IMMEDIATE`, its one writer), the
//! wake-up of idle workers (PostgreSQL's LISTEN/NOTIFY), and three fragments of SQL: the
//! claim's lock clause (`FOR UPDATE SKIP LOCKED`), the lease clock (the server's or the
//! process's) and the name of the two-value maximum.
//!
//! Why it can be written once:
//! - Placeholders are `$N` in both. sqlx's SQLite driver binds a parameter named `$N` to
//!   the N-th bound value, by its name (sqlx-sqlite `arguments.rs`), so a value used twice
//!   is bound once, as on PostgreSQL; the contract suite (`tests/service/store_contract.rs`) runs
//!   every statement on both.
//! - The rest is SQL both accept: `TRUE` and `NOT flag` (SQLite stores its flags as 0/1
//!   and reads `TRUE` as 1), `CAST(... AS TEXT)` where PostgreSQL must know a parameter's
//!   type, `RETURNING`, `ON CONFLICT ... DO UPDATE`, `length()` (characters of text, bytes
//!   of a blob, in both). Rows are read by column kind ([`rows::Columns`]), so a flag is a
//!   `bool` whichever way the backend stores it.
//! - The claim is one statement for both, with the backend's lock clause: the order in
//!   which jobs are taken is decided in one place (`queue::next_claimable`).
//! - Transactions are the same on both. What reads and then writes runs in
//!   [`Backend::begin_locked`]: under PostgreSQL's advisory lock, or on SQLite with its
//!   write lock taken at `BEGIN IMMEDIATE`, so no statement order has to take it (and no
//!   read-to-write upgrade can fail on a busy database). A worker's outcome is a plain
//!   transaction whose fenced write comes first.
//!
//! Generic functions rather than a macro: sqlx's bounds on what a driver can bind and
//! run are stated once ([`statement::Statements`]); the shared code only names
//! `B: Backend`, and reads as plain sqlx.

mod backend;
mod jobs;
mod queue;
pub(super) mod rows;
mod statement;
mod studies;

pub use backend::{pool_options, Backend};

use super::contract::{Store, StoreError};
use super::model::*;
use async_trait::async_trait;
use sqlx::Pool;
use std::sync::Arc;
use tokio::sync::Notify;

/// A [`Store`] on the database of backend `B`.
pub struct SqlStore<B: Backend> {
    pool: Pool<B>,
    listener: B::Listener,
}

impl<B: Backend> SqlStore<B> {
    /// Open (creating the schema as needed) the database the URL names.
    pub async fn connect(url: &str) -> Result<SqlStore<B>, StoreError> {
        Ok(SqlStore {
            pool: B::open(url).await?,
            listener: Default::default(),
        })
    }
}

#[async_trait]
impl<B: Backend> Store for SqlStore<B> {
    async fn ping(&self) -> Result<(), StoreError> {
        jobs::ping(&self.pool).await
    }

    async fn wake_on_new_work(&self, wake: Arc<Notify>) -> Result<(), StoreError> {
        B::wake_on_new_work(&self.pool, &self.listener, wake).await
    }

    async fn create_job_within(
        &self,
        job: NewJob,
        max_queued: i64,
        tenant_max_queued: i64,
    ) -> Result<Created, StoreError> {
        jobs::create(&self.pool, job, max_queued, tenant_max_queued).await
    }

    async fn get_job(&self, id: &str) -> Result<Job, StoreError> {
        jobs::get(&self.pool, id).await
    }

    async fn list_jobs(&self, filter: &ListFilter) -> Result<Page, StoreError> {
        jobs::list(&self.pool, filter).await
    }

    async fn request_cancel(&self, id: &str) -> Result<Job, StoreError> {
        jobs::request_cancel(&self.pool, id).await
    }

    async fn delete_job(&self, id: &str) -> Result<(), StoreError> {
        jobs::delete(&self.pool, id).await
    }

    async fn claim_shared(
        &self,
        owner: &str,
        lease_ms: i64,
        max_input_format: i64,
        tenant_share: i64,
    ) -> Result<Option<Claimed>, StoreError> {
        queue::claim(&self.pool, owner, lease_ms, max_input_format, tenant_share).await
    }

    async fn heartbeat(
        &self,
        lease: &Lease,
        progress: f64,
        lease_ms: i64,
    ) -> Result<Heartbeat, StoreError> {
        queue::heartbeat(&self.pool, lease, progress, lease_ms).await
    }

    async fn finish(&self, lease: &Lease, outcome: Outcome) -> Result<(), StoreError> {
        queue::finish(&self.pool, lease, outcome).await
    }

    async fn release(&self, lease: &Lease) -> Result<(), StoreError> {
        queue::release(&self.pool, lease).await
    }

    async fn recover_expired(&self, max_attempts: i64) -> Result<u64, StoreError> {
        queue::recover_expired(&self.pool, max_attempts).await
    }

    async fn get_artifact(&self, id: &str, name: &str) -> Result<Option<Artifact>, StoreError> {
        jobs::artifact(&self.pool, id, name).await
    }

    async fn stored_bytes(&self) -> Result<i64, StoreError> {
        jobs::stored_bytes(&self.pool).await
    }

    async fn expire(&self, before_ms: i64) -> Result<(u64, u64), StoreError> {
        jobs::expire(&self.pool, before_ms).await
    }

    async fn counts(&self) -> Result<StateCounts, StoreError> {
        jobs::counts(&self.pool).await
    }

    async fn create_study(
        &self,
        study: NewStudy,
        max_queued: i64,
    ) -> Result<StudyCreated, StoreError> {
        studies::create(&self.pool, study, max_queued).await
    }

    async fn get_study(&self, id: &str) -> Result<Study, StoreError> {
        studies::get(&self.pool, id).await
    }

    async fn list_studies(
        &self,
        tenant: Option<&str>,
        before: Option<i64>,
        limit: i64,
    ) -> Result<StudyPage, StoreError> {
        studies::list(&self.pool, tenant, before, limit).await
    }

    async fn cancel_study(&self, id: &str) -> Result<Study, StoreError> {
        studies::cancel(&self.pool, id).await
    }

    async fn delete_study(&self, id: &str) -> Result<(), StoreError> {
        studies::delete(&self.pool, id).await
    }
}
