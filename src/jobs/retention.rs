//! Retention: finished jobs and studies are deleted `--retention` seconds after they
//! finished, so the database does not grow without end.

use super::env::WorkerEnv;
use std::time::Duration;
use tokio::sync::watch;

/// Expire old results at start and then every quarter of the retention time (between
/// 0.25 s and 10 min), until shutdown. Does nothing when retention is 0.
pub async fn retention_loop(env: WorkerEnv, mut shutdown: watch::Receiver<bool>) {
    let keep = env.config.retention;
    if keep <= 0.0 {
        return;
    }
    let period = Duration::from_secs_f64((keep / 4.0).clamp(0.25, 600.0));
    loop {
        let now_ms = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_millis() as i64)
            .unwrap_or(0);
        match env.store.expire(now_ms - (keep * 1000.0) as i64).await {
            Ok((0, 0)) => {}
            Ok((jobs, studies)) => {
                env.metrics.expired(jobs);
                tracing::info!(
                    jobs,
                    studies,
                    "expired finished work past the retention time"
                );
            }
            Err(e) => tracing::warn!(error = %e, "retention sweep failed"),
        }
        tokio::select! {
            _ = tokio::time::sleep(period) => {}
            _ = shutdown.changed() => return,
        }
    }
}
