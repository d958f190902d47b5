//! A running service: the store, the worker pool and the router on one listener, until
//! shutdown (SIGTERM or Ctrl-C for [`run`], any future for [`run_until`]).

mod connections;
mod error;
mod problem_io;
mod signal;
mod worker_node;

pub use connections::ConnectionLimits;
pub use error::ServeError;
use signal::shutdown_signal;
pub use worker_node::{run_worker_node, run_worker_node_until};

use crate::api::{self, AppState, DatabaseWatch, LargeTransfers};
use crate::config::Config;
use crate::jobs::{WorkerEnv, WorkerPool};
use crate::metrics::Metrics;
use crate::store::{self, Store};
use std::future::Future;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;
use tokio::net::TcpListener;
use tokio::sync::{Notify, Semaphore};

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
            "WARNING: serving on {addr}, beyond loopback, WITHOUT API TOKENS: anyone who can reach this address can submit, read, cancel and delete every job. Configure --tokens-file (docs/reference/operations.md)."
        );
        eprintln!("{warning}");
        tracing::warn!("{warning}");
    }
    let store: Arc<dyn Store> = store::connect(&config.worker.database_url).await?;
    let metrics = Arc::new(Metrics::default());
    let wake = Arc::new(Notify::new());
    let ready = Arc::new(AtomicBool::new(true));
    let workers = config.worker.worker_count();

    let mut worker_config = config.worker.clone();
    if !tokens.is_empty() && worker_config.tenant_max_running.is_none() {
        // several tenants: keep a worker for the others
        worker_config.tenant_max_running = Some(workers.saturating_sub(1).max(1));
    }
    let pool = WorkerPool::start(WorkerEnv {
        store: store.clone(),
        config: Arc::new(worker_config),
        metrics: metrics.clone(),
        wake: wake.clone(),
    })
    .await;
    let metrics_for_server = metrics.clone();
    let state = AppState {
        database: DatabaseWatch::start(store.clone()),
        store,
        config: config.clone(),
        metrics,
        wake,
        ready: ready.clone(),
        direct: Arc::new(Semaphore::new(config.direct_count())),
        large: Arc::new(LargeTransfers::new(config.max_large_transfers)),
        openapi_yaml: api::openapi::yaml(),
        tokens: tokens.clone(),
    };
    tracing::info!(%addr, workers, tokens = tokens.len(), database = %store::redact_url(&config.worker.database_url), "serving");

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
    pool.shutdown(Duration::from_secs_f64(
        config.worker.shutdown_grace.max(0.0),
    ))
    .await;
    match tokio::time::timeout(Duration::from_secs(5), server).await {
        Ok(joined) => joined?,
        Err(_) => tracing::warn!("open connections did not close within 5 s"),
    }
    tracing::info!("stopped");
    Ok(())
}
