//! Job execution: a fixed pool of workers claims jobs from the [`Store`] under leases,
//! runs each on a blocking thread, heartbeats progress and cancel requests, and records
//! the outcome fenced by its lease.
//!
//! Concurrency is bounded by construction: `workers` async loops, each awaiting at most
//! one blocking task, so at most `workers` engine runs exist per process.

pub mod analysis_job;
pub mod artifacts;
pub mod control;
mod env;
pub mod outcome;
mod pool;
pub mod record;
mod retention;
mod runner;
pub mod simulation_job;

pub use analysis_job::{run_analysis, AnalysisInput};
pub use env::WorkerEnv;
pub use pool::WorkerPool;
