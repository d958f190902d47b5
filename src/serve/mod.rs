//! A running service: the store, the worker pool and the router on one listener, until
//! shutdown (SIGTERM or Ctrl-C for [`run`], any future for [`run_until`]).

mod connections;
mod problem_io;

pub use connections::ConnectionLimits;

use crate::api::{self, AppState};
use crate::config::Config;
use crate::jobs::{WorkerEnv, WorkerPool};
use crate::metrics::Metrics;
use crate::store::sqlite::SqliteStore;
use crate::store::{Store, StoreError};
use std::future::Future;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;
use tokio::net::TcpListener;
use tokio::sync::{Notify, Semaphore};

/// Why the service stopped with an error.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    #[error("database: {0}")]
    Store(#[from] StoreError),
    #[error("server: {0}")]
    Io(#[from] std::io::Error),
    #[error("configuration: {0}")]
    Config(String),
    #[error("server task: {0}")]
    Join(#[from] tokio::task::JoinError),
}

/// Serve on `listener` until SIGTERM or Ctrl-C; running jobs are then stopped and requeued.
pub async fn run(config: Config, listener: TcpListener) -> Result<(), ServeError> {
    run_until(config, listener, shutdown_signal()).await
}

/// Serve on `listener` until `shutdown` completes (tests and embedders choose the signal).
pub async fn run_until(
    config: Config,
    listener: TcpListener,
    shutdown: impl Future<Output = ()> + Send + 'static,
) -> Result<(), ServeError> {
    let config = Arc::new(config);
    let tokens = Arc::new(config.load_tokens().map_err(ServeError::Config)?);
    let addr = listener.local_addr()?;
    if tokens.is_empty() && !addr.ip().is_loopback() {
        let warning = format!(
            "WARNING: serving on {addr}, beyond loopback, WITHOUT API TOKENS: anyone who can reach this address can submit, read, cancel and delete every job. Configure --tokens-file (docs/operations.md)."
        );
        eprintln!("{warning}");
        tracing::warn!("{warning}");
    }
    let store: Arc<dyn Store> = Arc::new(SqliteStore::connect(&config.database_url).await?);
    let metrics = Arc::new(Metrics::default());
    let wake = Arc::new(Notify::new());
    let ready = Arc::new(AtomicBool::new(true));
    let workers = config.worker_count();

    let pool = WorkerPool::start(WorkerEnv {
        store: store.clone(),
        config: config.clone(),
        metrics: metrics.clone(),
        wake: wake.clone(),
    });
    let metrics_for_server = metrics.clone();
    let state = AppState {
        store,
        config: config.clone(),
        metrics,
        wake,
        ready: ready.clone(),
        direct: Arc::new(Semaphore::new(config.direct_count())),
        large: Arc::new(Semaphore::new(config.max_large_transfers.max(1))),
        openapi_yaml: api::openapi::yaml(),
        tokens: tokens.clone(),
    };
    tracing::info!(%addr, workers, tokens = tokens.len(), database = %config.database_url, "serving");

    let (stop_tx, mut stop_rx) = tokio::sync::watch::channel(false);
    tokio::spawn(async move {
        shutdown.await;
        let _ = stop_tx.send(true);
    });
    let mut server_stop = stop_rx.clone();
    let limits = ConnectionLimits {
        max_connections: config.connection_count(),
        header_timeout: Duration::from_secs_f64(config.header_timeout.max(0.1)),
        write_timeout: Duration::from_secs_f64(config.write_timeout.max(0.1)),
        max_header_bytes: config.max_header_bytes.max(1024),
    };
    tracing::info!(
        max_connections = limits.max_connections,
        header_timeout = ?limits.header_timeout,
        "connection limits"
    );
    let server = tokio::spawn(connections::serve(
        listener,
        api::router(state),
        limits,
        metrics_for_server,
        async move {
            let _ = server_stop.wait_for(|s| *s).await;
        },
    ));

    let _ = stop_rx.wait_for(|s| *s).await;
    tracing::info!("shutting down: no new jobs; running jobs are stopped and requeued");
    ready.store(false, Ordering::SeqCst);
    pool.shutdown(Duration::from_secs_f64(config.shutdown_grace.max(0.0)))
        .await;
    match tokio::time::timeout(Duration::from_secs(5), server).await {
        Ok(joined) => joined?,
        Err(_) => tracing::warn!("open connections did not close within 5 s"),
    }
    tracing::info!("stopped");
    Ok(())
}

async fn shutdown_signal() {
    let ctrl_c = async {
        let _ = tokio::signal::ctrl_c().await;
    };
    #[cfg(unix)]
    let term = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let term = std::future::pending::<()>();
    tokio::select! {
        _ = ctrl_c => {}
        _ = term => {}
    }
}
