//! Why a service or worker node stopped with an error.

use crate::store::StoreError;

/// Why the service stopped with an error.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    #[error("database: {0}")]
    Store(#[from] StoreError),
    #[error("server: {0}")]
    Io(#[from] std::io::Error),
    #[error("configuration: {0}")]
    Config(String),
    #[error("server task: {0}")]
    Join(#[from] tokio::task::JoinError),
}
