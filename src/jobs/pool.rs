//! The worker pool: `workers` claim loops plus the lease-recovery task.

use super::env::WorkerEnv;
use super::runner;
use std::time::Duration;
use tokio::sync::watch;
use tokio::task::JoinHandle;

/// Handle on the running workers and the lease-recovery task.
pub struct WorkerPool {
    shutdown: watch::Sender<bool>,
    workers: Vec<JoinHandle<()>>,
    recovery: JoinHandle<()>,
    retention: JoinHandle<()>,
}

impl WorkerPool {
    pub async fn start(env: WorkerEnv) -> WorkerPool {
        let (tx, rx) = watch::channel(false);
        if env.config.worker_count() > 0 {
            // Jobs queued by other processes wake the idle workers at once (PostgreSQL's
            // LISTEN/NOTIFY); without it they are found by the next poll.
            if let Err(e) = env.store.wake_on_new_work(env.wake.clone()).await {
                tracing::warn!(error = %e, "no wake-ups from the database; idle workers poll");
            }
        }
        // One id per process; leases name it so a restarted process never matches a stale lease.
        let process = uuid::Uuid::new_v4().simple().to_string();
        let workers = (0..env.config.worker_count())
            .map(|i| {
                let env = env.clone();
                let rx = rx.clone();
                let owner = format!("{}-{}-w{i}", std::process::id(), &process[..12]);
                tokio::spawn(runner::worker_loop(env, owner, rx))
            })
            .collect();
        let retention = tokio::spawn(super::retention::retention_loop(env.clone(), rx.clone()));
        let recovery = tokio::spawn(recovery_loop(env, rx));
        WorkerPool {
            shutdown: tx,
            workers,
            recovery,
            retention,
        }
    }

    /// Stop claiming; running jobs are cancelled and requeued. Waits up to `grace`.
    pub async fn shutdown(self, grace: Duration) {
        let _ = self.shutdown.send(true);
        let all = futures_join_all(self.workers);
        if tokio::time::timeout(grace, all).await.is_err() {
            tracing::warn!("workers did not stop within {grace:?}; their leases will expire and requeue the jobs");
        }
        self.recovery.abort();
        self.retention.abort();
    }
}

async fn futures_join_all(handles: Vec<JoinHandle<()>>) {
    for h in handles {
        let _ = h.await;
    }
}

/// Requeue jobs whose worker died (lease expired), at start and then periodically.
async fn recovery_loop(env: WorkerEnv, mut shutdown: watch::Receiver<bool>) {
    let period = Duration::from_millis((env.config.lease_ms() / 2).clamp(100, 5000) as u64);
    loop {
        match env.store.recover_expired(env.config.max_attempts).await {
            Ok(0) => {}
            Ok(n) => {
                tracing::info!(jobs = n, "recovered jobs with expired leases");
                env.wake.notify_waiters();
            }
            Err(e) => tracing::warn!(error = %e, "lease recovery failed"),
        }
        tokio::select! {
            _ = tokio::time::sleep(period) => {}
            _ = shutdown.changed() => return,
        }
    }
}
