//! Direct (non-queued) computations: run on a blocking thread, bounded by the `direct`
//! semaphore, with a panic answered as a problem instead of taking the process down.

use super::problem::Problem;
use super::state::AppState;

/// Run `f` on a blocking thread under one `direct` permit. `what` names the computation
/// in error messages ("the quasi-static solver", "the analysis").
pub async fn run_direct<T, F>(state: &AppState, what: &'static str, f: F) -> Result<T, Problem>
where
    T: Send + 'static,
    F: FnOnce() -> T + Send + 'static,
{
    let _permit = state
        .direct
        .clone()
        .acquire_owned()
        .await
        .map_err(|_| Problem::unavailable("shutting down"))?;
    tokio::task::spawn_blocking(move || std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)))
        .await
        .map_err(|e| Problem::internal(format!("{what} task failed: {e}")))?
        .map_err(|_| Problem::internal(format!("{what} panicked")))
}
