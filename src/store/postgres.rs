//! The PostgreSQL backend: one queue and one store shared by several API and worker
//! machines.
//!
//! Claims take the oldest queued row with `FOR UPDATE SKIP LOCKED`, so concurrent
//! workers never wait on each other's row or take the same job. The operations that read
//! a count or a set of rows and then write on it (admission against `--max-queued`, study
//! creation with shared points, cancel and delete of studies, retention, lease recovery)
//! run in a transaction under one advisory lock: PostgreSQL's default isolation would
//! otherwise let two of them act on the same snapshot, where SQLite's single writer
//! serialises them. Idle workers are woken by LISTEN/NOTIFY.

use super::contract::StoreError;
use super::migrations::additive;
use super::sql::{pool_options, Backend, SqlStore};
use async_trait::async_trait;
use sqlx::postgres::PgListener;
use sqlx::{Pool, Postgres, Transaction};
use std::sync::{Arc, Mutex};
use std::time::Duration;
use tokio::sync::Notify;
use tokio::task::AbortHandle;

/// The [`super::Store`] on a PostgreSQL database.
pub type PostgresStore = SqlStore<Postgres>;

/// The advisory lock key of the queue's structure (ASCII "bearing").
const QUEUE_LOCK: i64 = 0x62_6561_7269_6e67;

/// The channel the `jobs` triggers notify when a job becomes claimable
/// (migrations/postgres/0001_schema.sql).
const QUEUE_CHANNEL: &str = "bearing_sim_queue";

/// The LISTEN task of [`super::Store::wake_on_new_work`], stopped with the store.
#[derive(Default)]
pub struct ListenTask(Mutex<Option<AbortHandle>>);

impl Drop for ListenTask {
    fn drop(&mut self) {
        if let Some(task) = self.0.lock().ok().and_then(|mut t| t.take()) {
            task.abort();
        }
    }
}

#[async_trait]
impl Backend for Postgres {
    const CLAIM_LOCK: &'static str = " FOR UPDATE SKIP LOCKED";
    const SERVER_CLOCK_MS: Option<&'static str> =
        Some("(extract(epoch from clock_timestamp()) * 1000)::bigint");
    const GREATEST: &'static str = "GREATEST";
    /// 1.5 s: with the server down, readiness and submissions answer 503 within 2 s (each
    /// wait for a connection retries the connect until then). A healthy pool hands out a
    /// connection in milliseconds, so only an absent or swamped server reaches it.
    const ACQUIRE_TIMEOUT: Duration = Duration::from_millis(1500);
    type Listener = ListenTask;

    /// Connect and migrate. The database must exist; its schema is created on first use
    /// (concurrent starts are safe: sqlx migrates under an advisory lock).
    async fn open(url: &str) -> Result<Pool<Postgres>, StoreError> {
        let pool = pool_options::<Postgres>().connect(url).await?;
        additive(sqlx::migrate!("./migrations/postgres"))
            .run(&pool)
            .await?;
        Ok(pool)
    }

    async fn begin_locked(
        pool: &Pool<Postgres>,
    ) -> Result<Transaction<'static, Postgres>, StoreError> {
        let mut tx = pool.begin().await?;
        sqlx::query("SELECT pg_advisory_xact_lock($1)")
            .bind(QUEUE_LOCK)
            .execute(&mut *tx)
            .await?;
        Ok(tx)
    }

    async fn wake_on_new_work(
        pool: &Pool<Postgres>,
        listener: &ListenTask,
        wake: Arc<Notify>,
    ) -> Result<(), StoreError> {
        let mut channel = PgListener::connect_with(pool).await?;
        channel.listen(QUEUE_CHANNEL).await?;
        // The listener holds one of the pool's connections for as long as it runs.
        let task = tokio::spawn(async move {
            loop {
                // recv() reconnects by itself after a dropped connection; notifications
                // sent meanwhile are lost, which the workers' polling covers.
                match channel.recv().await {
                    Ok(_) => wake.notify_waiters(),
                    Err(sqlx::Error::PoolClosed) => return,
                    Err(e) => {
                        tracing::warn!(error = %e, "LISTEN connection failed; retrying in 1 s");
                        tokio::time::sleep(Duration::from_secs(1)).await;
                    }
                }
            }
        });
        if let Ok(mut slot) = listener.0.lock() {
            if let Some(previous) = slot.replace(task.abort_handle()) {
                previous.abort();
            }
        }
        Ok(())
    }
}
