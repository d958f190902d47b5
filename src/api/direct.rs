//! Direct (non-queued) computations: run on a blocking thread under a permit of their own
//! bounded pool (`--direct-concurrency`, separate from the job workers), cancelled when
//! the request goes away, with a panic answered as a problem instead of taking the
//! process down.

use super::problem::Problem;
use super::state::AppState;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Sets the flag when dropped: the handler's future is dropped when the client resets
/// the connection or the request times out, and the computation then stops at its next
/// check instead of burning a core for nobody.
struct CancelOnDrop(Arc<AtomicBool>);

impl Drop for CancelOnDrop {
    fn drop(&mut self) {
        self.0.store(true, Ordering::SeqCst);
    }
}

/// Run `f` on a blocking thread under one `direct` permit. `f` gets a cancel flag it
/// should check between stages; the permit is held until `f` returns, so computations
/// whose client has gone still count against the bound until they stop. `what` names the
/// computation in error messages ("the quasi-static solver", "the analysis").
pub async fn run_direct<T, F>(state: &AppState, what: &'static str, f: F) -> Result<T, Problem>
where
    T: Send + 'static,
    F: FnOnce(&AtomicBool) -> T + Send + 'static,
{
    let permit = state
        .direct
        .clone()
        .acquire_owned()
        .await
        .map_err(|_| Problem::unavailable("shutting down"))?;
    let cancel = Arc::new(AtomicBool::new(false));
    let _cancel_on_drop = CancelOnDrop(cancel.clone());
    let metrics = state.metrics.clone();
    tokio::task::spawn_blocking(move || {
        let _permit = permit;
        let _running = metrics.direct_started();
        let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(&cancel)));
        if cancel.load(Ordering::SeqCst) {
            metrics.direct_cancelled();
        }
        out
    })
    .await
    .map_err(|e| Problem::internal(format!("{what} task failed: {e}")))?
    .map_err(|_| Problem::internal(format!("{what} panicked")))
}
