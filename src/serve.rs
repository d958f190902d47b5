//! A running service: the store, the worker pool and the router on one listener, until
//! shutdown (SIGTERM or Ctrl-C for [`run`], any future for [`run_until`]).

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
    let state = AppState {
        store,
        config: config.clone(),
        metrics,
        wake,
        ready: ready.clone(),
        direct: Arc::new(Semaphore::new(config.direct_count())),
        openapi_yaml: api::openapi::yaml(),
    };
    let addr = listener.local_addr()?;
    tracing::info!(%addr, workers, database = %config.database_url, "serving");

    let (stop_tx, mut stop_rx) = tokio::sync::watch::channel(false);
    tokio::spawn(async move {
        shutdown.await;
        let _ = stop_tx.send(true);
    });
    let mut server_stop = stop_rx.clone();
    let server = axum::serve(listener, api::router(state)).with_graceful_shutdown(async move {
        let _ = server_stop.wait_for(|s| *s).await;
    });
    let server = tokio::spawn(async move { server.await });

    let _ = stop_rx.wait_for(|s| *s).await;
    tracing::info!("shutting down: no new jobs; running jobs are stopped and requeued");
    ready.store(false, Ordering::SeqCst);
    pool.shutdown(Duration::from_secs_f64(config.shutdown_grace.max(0.0)))
        .await;
    match tokio::time::timeout(Duration::from_secs(5), server).await {
        Ok(joined) => joined??,
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
