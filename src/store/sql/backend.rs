//! What a SQL backend brings to the shared store: the few fragments of SQL in which the
//! two databases differ (its dialect), and the operations that cannot be shared.

use super::rows::Columns;
use super::statement::{RowsAffected, Statements};
use crate::store::contract::StoreError;
use async_trait::async_trait;
use sqlx::pool::PoolOptions;
use sqlx::{Database, IntoArguments, Pool, Transaction};
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::Notify;

#[async_trait]
pub trait Backend:
    Statements
    + for<'q> Database<
        Row: Columns,
        QueryResult: RowsAffected,
        Arguments<'q>: IntoArguments<'q, Self>,
    >
{
    /// What a claim appends to its choice of the next job, so that concurrent claims pass
    /// each other's row by (PostgreSQL: ` FOR UPDATE SKIP LOCKED`). Empty where one writer
    /// at a time is all the database allows (SQLite).
    const CLAIM_LOCK: &'static str;

    /// The clock leases are set and judged by, as SQL, where it is the database server's
    /// (PostgreSQL: with each machine's own, a node whose clock ran ahead would requeue
    /// healthy jobs). `None`: the process's clock, bound with each statement as `now`
    /// (SQLite: one machine). See [`lease_clock`].
    const SERVER_CLOCK_MS: Option<&'static str>;

    /// The larger of two values: `GREATEST` (PostgreSQL) or the two-argument `MAX` (SQLite).
    const GREATEST: &'static str;

    /// How long a statement waits for a connection of the pool before it fails. Where the
    /// database is a server that can be away (PostgreSQL), short: a request then answers
    /// 503 at once instead of hanging to its timeout. Where it is a local file (SQLite),
    /// a connection is only ever busy, never unreachable, and waiting is right.
    const ACQUIRE_TIMEOUT: Duration;

    /// What the backend keeps beside its pool (PostgreSQL: the LISTEN task).
    type Listener: Default + Send + Sync + 'static;

    /// Open the database the URL names and run its migrations.
    async fn open(url: &str) -> Result<Pool<Self>, StoreError>;

    /// A transaction that holds the queue's structure lock from its start: the operations
    /// that read a count or a set of rows and then write on it run in one, so no two act
    /// on the same view.
    async fn begin_locked(pool: &Pool<Self>) -> Result<Transaction<'static, Self>, StoreError>;

    /// [`crate::store::Store::wake_on_new_work`]; nothing to hear by default.
    async fn wake_on_new_work(
        pool: &Pool<Self>,
        listener: &Self::Listener,
        wake: Arc<Notify>,
    ) -> Result<(), StoreError> {
        let _ = (pool, listener, wake);
        Ok(())
    }
}

/// The lease clock of backend `B` in a statement whose process clock is bound as `now`
/// (a placeholder such as `$3`).
pub fn lease_clock<B: Backend>(now: &'static str) -> &'static str {
    B::SERVER_CLOCK_MS.unwrap_or(now)
}

/// The pool either backend opens: 8 connections a process, waiting for one at most the
/// backend's [`Backend::ACQUIRE_TIMEOUT`].
pub fn pool_options<B: Backend>() -> PoolOptions<B> {
    PoolOptions::new()
        .max_connections(8)
        .acquire_timeout(B::ACQUIRE_TIMEOUT)
}
