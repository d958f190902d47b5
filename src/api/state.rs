//! What every handler shares.

use super::database_watch::DatabaseWatch;
use super::large_transfers::{LargePermit, LargeTransfers};
use super::problem::Problem;
use crate::config::{Config, Tokens};
use crate::metrics::Metrics;
use crate::store::Store;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use tokio::sync::{Notify, Semaphore};

#[derive(Clone)]
pub struct AppState {
    pub store: Arc<dyn Store>,
    pub config: Arc<Config>,
    pub metrics: Arc<Metrics>,
    /// API tokens (empty: the service is open).
    pub tokens: Arc<Tokens>,
    /// Wakes idle workers when a job is queued.
    pub wake: Arc<Notify>,
    /// Whether the database answers (requests that need it get 503 while it does not).
    pub database: DatabaseWatch,
    /// False once shutdown began (readiness).
    pub ready: Arc<AtomicBool>,
    /// Bounds large transfers in flight: big request bodies, channel and spectrum answers,
    /// with a share per client.
    pub large: Arc<LargeTransfers>,
    /// Bounds direct (non-queued) computations: quasi-static solves, small analyses.
    pub direct: Arc<Semaphore>,
    /// The OpenAPI document served at `/openapi.yaml` (`api::openapi::yaml()`; handed in so
    /// that the document, which lists that handler, and the handler do not import each other).
    pub openapi_yaml: &'static str,
}

impl AppState {
    /// One of the `--max-large-transfers` slots within `client`'s share, held while a
    /// large body or answer is in memory; waited for within the request timeout.
    pub async fn large_transfer(&self, client: &str) -> Result<LargePermit, Problem> {
        self.large
            .acquire(client, self.config.request_deadline())
            .await
    }
}
