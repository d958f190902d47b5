//! The SQLite backend: an embedded database in WAL mode, one writer at a time.
//!
//! The operations that read and then write take the write lock at their start
//! (`BEGIN IMMEDIATE`), so concurrent writers queue on SQLite's lock with the busy timeout
//! instead of failing on a read-to-write upgrade; every other write is one statement, or
//! (a job's outcome) a transaction whose first statement writes.

use super::contract::StoreError;
use super::migrations::additive;
use super::sql::{pool_options, Backend, SqlStore};
use async_trait::async_trait;
use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqliteSynchronous};
use sqlx::{Pool, Sqlite, Transaction};
use std::str::FromStr;
use std::time::Duration;

/// The [`super::Store`] on an SQLite file.
pub type SqliteStore = SqlStore<Sqlite>;

#[async_trait]
impl Backend for Sqlite {
    const CLAIM_LOCK: &'static str = "";
    const SERVER_CLOCK_MS: Option<&'static str> = None;
    const GREATEST: &'static str = "MAX";
    /// As long as a request may take: connections of a local file are only ever busy.
    const ACQUIRE_TIMEOUT: Duration = Duration::from_secs(30);
    type Listener = ();

    /// Open (creating the file and its directory if needed) and migrate.
    async fn open(url: &str) -> Result<Pool<Sqlite>, StoreError> {
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
        let pool = pool_options::<Sqlite>().connect_with(opts).await?;
        additive(sqlx::migrate!("./migrations/sqlite"))
            .run(&pool)
            .await?;
        Ok(pool)
    }

    async fn begin_locked(pool: &Pool<Sqlite>) -> Result<Transaction<'static, Sqlite>, StoreError> {
        Ok(pool.begin_with("BEGIN IMMEDIATE").await?)
    }
}
