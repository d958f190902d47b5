//! A worker node (`bearing-sim worker`): the job workers and the lease-recovery and
//! retention tasks on a shared database, with no HTTP API. API nodes (`serve --workers
//! 0`) queue the jobs; any number of worker nodes run them.

use super::error::ServeError;
use super::signal::shutdown_signal;
use crate::config::WorkerConfig;
use crate::jobs::{WorkerEnv, WorkerPool};
use crate::metrics::Metrics;
use crate::store;
use std::future::Future;
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::Notify;

/// Run workers until SIGTERM or Ctrl-C; running jobs are then stopped and requeued.
pub async fn run_worker_node(config: WorkerConfig) -> Result<(), ServeError> {
    run_worker_node_until(config, shutdown_signal()).await
}

/// Run workers until `shutdown` completes.
pub async fn run_worker_node_until(
    config: WorkerConfig,
    shutdown: impl Future<Output = ()>,
) -> Result<(), ServeError> {
    let workers = config.worker_count();
    if workers == 0 {
        return Err(ServeError::Config(
            "--workers must be at least 1 for a worker process (an API-only node is `serve --workers 0`)".into(),
        ));
    }
    let store = store::connect(&config.database_url).await?;
    let database = store::redact_url(&config.database_url);
    let grace = Duration::from_secs_f64(config.shutdown_grace.max(0.0));
    let pool = WorkerPool::start(WorkerEnv {
        store,
        config: Arc::new(config),
        metrics: Arc::new(Metrics::default()),
        wake: Arc::new(Notify::new()),
    })
    .await;
    // Machine-readable: scripts and tests wait for this line.
    println!("worker ready: {workers} workers on {database}");
    tracing::info!(workers, %database, "worker node running");
    shutdown.await;
    tracing::info!("shutting down: no new jobs; running jobs are stopped and requeued");
    pool.shutdown(grace).await;
    tracing::info!("stopped");
    Ok(())
}
