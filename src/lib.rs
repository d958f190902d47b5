//! bearing-sim: the HTTP service and command line around the `bearing_core` engine.
//!
//! Layers, each importing only from those above it in this list:
//! - [`store`]: durable jobs and their outputs behind the [`store::Store`] trait (SQLite).
//! - [`config`], [`metrics`]: service settings and Prometheus counters.
//! - [`plots`]: SVG charts of engine results (plotters' SVG backend).
//! - [`studies`]: what the service adds to the engine's studies (`bearing_core::study`):
//!   the key identical points share a run by, and the study's plots.
//! - [`jobs`]: workers that claim jobs, run the engine, and store typed records.
//! - [`api`]: the axum router, request parsing and problem+json errors.
//! - [`serve`]: a running service (store + workers + router) on a listener.
//! - [`cli`]: the `bearing-sim` subcommands; `main.rs` only dispatches to them.
//!
//! The engine (`bearing_core`) has no async runtime, HTTP or SQL in its dependencies.

pub mod api;
pub mod cli;
pub mod config;
pub mod jobs;
pub mod metrics;
pub mod plots;
pub mod serve;
pub mod store;
pub mod studies;

pub use api::router;
pub use serve::{run, run_until};
