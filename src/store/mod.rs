//! Durable storage of jobs and their outputs.
//!
//! Handlers and workers only see the [`Store`] trait. [`sqlite::SqliteStore`] is the
//! embedded default; [`postgres::PostgresStore`] lets several API and worker machines
//! share one queue (claims are `SELECT ... FOR UPDATE SKIP LOCKED`). [`connect`] picks
//! the backend from the database URL.

pub mod blob;
mod connect;
mod contract;
mod migrations;
pub mod model;
pub mod postgres;
mod rows;
pub mod sqlite;

pub use connect::{connect, redact_url};
pub use contract::{Store, StoreError};
pub use model::*;
