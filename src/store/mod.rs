//! Durable storage of jobs and their outputs.
//!
//! Handlers and workers only see the [`Store`] trait. Its one implementation,
//! [`sql::SqlStore`], is written once over two backends: [`sqlite`] is the embedded
//! default; [`postgres`] lets several API and worker machines share one queue (claims
//! are `SELECT ... FOR UPDATE SKIP LOCKED`). [`connect`] picks the backend from the
//! database URL.

pub mod blob;
mod connect;
mod contract;
mod migrations;
pub mod model;
pub mod postgres;
mod sql;
pub mod sqlite;

pub use connect::{connect, redact_url};
pub use contract::{Store, StoreError};
pub use model::*;
