//! HTTP API: router, shared state and the middleware every route gets.

// `Problem` is the error of every handler and is turned into a response at once; boxing it
// would only add noise.
#![allow(clippy::result_large_err)]

mod analyses;
mod analysis_sense;
mod budget;
mod caller;
mod database_watch;
mod direct;
mod extract;
mod input_bounds;
mod job_resource;
mod large_transfers;
mod middleware;
pub mod openapi;
mod ops;
mod presets;
pub mod problem;
mod quasi_static;
mod recording_upload;
mod recordings;
pub mod results;
mod router;
pub mod routes;
mod scene_input;
mod simulation_plots;
mod simulation_recording;
mod simulations;
mod state;
mod strict_json;
mod studies;
mod study_views;
mod submission;
mod views;
mod web;

pub use caller::ClientAddr;
pub use database_watch::DatabaseWatch;
pub use large_transfers::LargeTransfers;
pub use router::router;
pub use state::AppState;
