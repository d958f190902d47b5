//! Whether the database answers, watched in the background, so that requests which need it
//! are answered 503 at once while it is away instead of hanging to their timeout. A
//! stopped server refuses connections quickly, but a frozen or partitioned one accepts and
//! never answers: its pooled connections hang without end (with PostgreSQL down, `/readyz`
//! and a POST used to answer 408 after 30 s).

use super::problem::{Problem, DATABASE_RETRY_AFTER};
use crate::store::Store;
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::watch;

/// How often the database is pinged.
const PROBE_EVERY: Duration = Duration::from_millis(500);

/// A ping slower than this counts as no answer: a healthy database answers in
/// milliseconds. With [`PROBE_EVERY`], an absence is seen within 1.5 s.
const PROBE_TIMEOUT: Duration = Duration::from_secs(1);

/// The latest verdict of the background ping.
#[derive(Clone)]
pub struct DatabaseWatch {
    up: watch::Receiver<bool>,
}

impl DatabaseWatch {
    /// Start pinging `store`; the pinging stops once every clone of the watch is gone.
    pub fn start(store: Arc<dyn Store>) -> DatabaseWatch {
        let (tx, rx) = watch::channel(true);
        tokio::spawn(async move {
            while !tx.is_closed() {
                let up = matches!(
                    tokio::time::timeout(PROBE_TIMEOUT, store.ping()).await,
                    Ok(Ok(()))
                );
                tx.send_if_modified(|was| {
                    if *was != up {
                        if up {
                            tracing::info!("the database answers again");
                        } else {
                            tracing::warn!(
                                "the database does not answer; requests that need it get 503"
                            );
                        }
                    }
                    std::mem::replace(was, up) != up
                });
                tokio::time::sleep(PROBE_EVERY).await;
            }
        });
        DatabaseWatch { up: rx }
    }

    pub fn is_up(&self) -> bool {
        *self.up.borrow()
    }

    /// Resolves once the database is seen to be away (at once if it is).
    pub async fn went_away(&self) {
        let mut up = self.up.clone();
        // an error means the watcher stopped: the service is shutting down
        let _ = up.wait_for(|up| !*up).await;
    }

    /// Does a request for `path` need the database? Liveness, the API document, the web
    /// page, presets and quasi-static solves do not, and keep answering without it.
    pub fn needed_by(path: &str) -> bool {
        !(path == "/healthz"
            || path == "/openapi.yaml"
            || path == "/"
            || path.starts_with("/assets/")
            || path == "/v1/quasi-static"
            || path == "/v1/presets"
            || path.starts_with("/v1/presets/"))
    }

    /// The answer to a request that needs the database while it is away.
    pub fn unavailable() -> Problem {
        let mut p = Problem::unavailable(
            "the database does not answer; retry shortly (the service reconnects by itself)",
        );
        p.retry_after = Some(DATABASE_RETRY_AFTER);
        p
    }
}
