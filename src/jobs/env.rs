//! What every worker shares.

use crate::config::WorkerConfig;
use crate::metrics::Metrics;
use crate::store::Store;
use std::sync::Arc;
use tokio::sync::Notify;

/// What every worker shares.
#[derive(Clone)]
pub struct WorkerEnv {
    pub store: Arc<dyn Store>,
    pub config: Arc<WorkerConfig>,
    pub metrics: Arc<Metrics>,
    /// Poked by submissions so an idle worker claims at once instead of at its next poll.
    pub wake: Arc<Notify>,
}
