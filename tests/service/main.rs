//! The service's integration tests, one test binary (so axum, sqlx and the service link
//! once): one module per concern, around one in-process test app (`common/app.rs`). Tests
//! of process signals, descriptor limits and several processes on one database start the
//! real `bearing-sim` binary as a child (`common/server.rs`), so nothing here changes
//! process-wide state and the modules can share the process.

mod common;

mod abuse;
mod api;
mod bench_cli;
mod concurrency;
mod hardening;
mod recordings;
mod recovery;
mod scale_out;
mod signal_cli;
mod simulation;
mod store_contract;
mod studies;
